"""Drivers: one per case kind (``[case] kind``), each a module with ``check(case)`` and
``run(case, *, out, quick)``. Imported lazily so ``gsi check`` stays fast."""
from __future__ import annotations

import importlib
import pathlib

DRIVERS = {
    "pour": "gsi.drivers.pour",
    "thermal_silo": "gsi.drivers.thermal_silo",
    "hopper_membrane": "gsi.drivers.hopper_membrane",
}


def _driver(kind: str):
    return importlib.import_module(DRIVERS[kind])


def check_case(case) -> None:
    """Checks that need more than the schema (time step against the Rayleigh time, ...)."""
    _driver(case.case.kind).check(case)


def run_case(case, *, out: pathlib.Path, quick: bool = False):
    """Run a validated case, writing its files under ``out``; returns the driver's result."""
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    return _driver(case.case.kind).run(case, out=out, quick=quick)
