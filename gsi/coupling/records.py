"""The per-interval records of a coupling: kept in memory, appended to a CSV as they come.

:class:`RecordLog` is the part :class:`gsi.coupling.staggered.StaggeredCoupling` and
:class:`gsi.coupling.thermal.ThermalCoupling` share: a record is a dataclass row
(``RECORD``), its fields are the CSV columns, each row is appended (and closed) when it is
made, so a killed run leaves a complete CSV, and the rows round-trip through plain arrays
for checkpoints.
"""
from __future__ import annotations

import csv
import dataclasses
import pathlib

import numpy as np

__all__ = ["RecordLog"]


def _fmt(v) -> str:
    return f"{v:.12g}" if isinstance(v, float) else str(v)


class RecordLog:
    """Records of one coupling (subclasses set ``RECORD``, a dataclass, and ``is_root``)."""

    RECORD: type = None

    @classmethod
    def columns(cls) -> list[str]:
        return [f.name for f in dataclasses.fields(cls.RECORD)]

    def _init_log(self, csv_path) -> None:
        self.records = []
        self.csv_path = None
        if csv_path is not None:
            self.open_csv(csv_path)

    def open_csv(self, path) -> None:
        """Write the records from now on to the CSV file ``path`` (header now; rank root)."""
        self.csv_path = pathlib.Path(path)
        if self.is_root:
            self.csv_path.parent.mkdir(parents=True, exist_ok=True)
            with self.csv_path.open("w", newline="") as fh:
                csv.writer(fh).writerow(self.columns())

    def _log(self, rec):
        """Keep ``rec`` and append it to the CSV (rank root); returns it."""
        self.records.append(rec)
        if self.csv_path is not None and self.is_root:
            with self.csv_path.open("a", newline="") as fh:
                csv.writer(fh).writerow([_fmt(getattr(rec, c)) for c in self.columns()])
        return rec

    def history(self) -> dict:
        """The records as arrays: {column: ndarray}."""
        return {c: np.array([getattr(r, c) for r in self.records]) for c in self.columns()}

    def _records_state(self) -> dict:
        """The records as plain arrays ``rec.<column>`` (int columns stay int)."""
        types = {f.name: f.type for f in dataclasses.fields(self.RECORD)}
        return {f"rec.{c}": np.array([getattr(r, c) for r in self.records],
                                     np.int64 if types[c] in (int, "int") else np.float64)
                for c in self.columns()}

    def _set_records_state(self, d: dict) -> None:
        cols = {c: d[f"rec.{c}"].tolist() for c in self.columns()}
        n = len(cols[self.columns()[0]])
        self.records = [self.RECORD(**{c: cols[c][i] for c in cols}) for i in range(n)]
