"""The output files of a coupled structure: its fields (:class:`gsi.fem.output.FemOutput`:
``<name>.xdmf`` + ``.h5`` and ``<name>.csv``) and its couplings' records
(``<name>_coupling.csv``, ``<name>_energy.csv``)."""
from __future__ import annotations

import pathlib

from gsi.checkpoint import truncate_csv


class StructureOutput:
    """The files of structure ``name`` under ``out_dir`` (collective). ``resume=n``
    continues the files of an earlier run: the first n field writes and as many coupling
    rows as the couplings hold records are kept, later ones dropped."""

    def __init__(self, name: str, out_dir, *, elasticity, heat, xdmf: bool = True,
                 resume: int | None = None):
        from gsi.fem.output import FemOutput
        self.name = name
        self.dir = pathlib.Path(out_dir)
        self.resume = resume is not None
        self.fem = FemOutput(self.dir, elasticity=elasticity, heat=heat, prefix=name,
                             xdmf=xdmf, resume=resume)

    def open_csvs(self, mechanics, thermal) -> None:
        """Point the couplings' records at their CSVs (cut back to their records when
        resuming)."""
        for c, suffix in ((mechanics, "coupling"), (thermal, "energy")):
            if c is None:
                continue
            path = self.dir / f"{self.name}_{suffix}.csv"
            if self.resume:
                c.csv_path = path
                if c.is_root:
                    truncate_csv(path, len(c.records))
            else:
                c.open_csv(path)

    @property
    def n_writes(self) -> int:
        """Field writes so far."""
        return 0 if self.fem is None else self.fem.n_writes

    def write(self, t: float) -> dict:
        """Append the fields at time ``t`` (s) and a row of ``<name>.csv``; returns it."""
        return self.fem.write(t)

    def files(self, mechanics, thermal) -> list:
        """Paths written so far."""
        names = [f"{self.name}.xdmf", f"{self.name}.csv"]
        if mechanics is not None:
            names.append(f"{self.name}_coupling.csv")
        if thermal is not None:
            names.append(f"{self.name}_energy.csv")
        return [self.dir / n for n in names]

    def close(self) -> None:
        """Close the field files."""
        if self.fem is not None:
            self.fem.close()
            self.fem = None
