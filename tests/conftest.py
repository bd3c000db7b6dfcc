"""Test-session set-up: load VTK (pyvista) before dolfinx; record validation results.

Test modules import dolfinx at collection; VTK's scalar bars abort a process in which
dolfinx was loaded first (see gsi.viz._preload_vtk). Importing gsi.viz here, before any
test module, lets the demo tests render their pictures in-process.

``record_validation`` (a fixture) is how a validation test states what it checks:
``record_validation(name, reference=..., measured=..., tolerance=..., source=...)``, called
with the very numbers its assert compares. At the end of the session the records go to
``tests/validation/results.json`` (``$GSI_VALIDATION_RESULTS`` overrides the path), merged
by name with the records of earlier sessions, each with the test's outcome, the date, the
host's CPU and the git commit. The documentation's Validation page is rendered from that
file (docs/_ext/gsi_docs.py), so the page shows what the tests asserted, as they ran.
The file is not committed (.gitignore): it is the output of a test run on some machine,
and a committed copy would go stale with the first change to the code it describes.
"""
import datetime
import json
import math
import os
import pathlib
import platform
import subprocess

import pytest

import gsi.viz  # noqa: F401

_ROOT = pathlib.Path(__file__).resolve().parents[1]
_RECORDS: list[dict] = []


def _results_path() -> pathlib.Path:
    return pathlib.Path(os.environ.get("GSI_VALIDATION_RESULTS",
                                       _ROOT / "tests" / "validation" / "results.json"))


def _number(x):
    """JSON-safe numbers (numpy scalars, tuples, nan, inf)."""
    if isinstance(x, (list, tuple)):
        return [_number(v) for v in x]
    if isinstance(x, (str, bool)) or x is None:
        return x
    if isinstance(x, int):
        return x
    try:
        f = float(x)
    except (TypeError, ValueError):
        return str(x)
    return f if math.isfinite(f) else str(f)


@pytest.fixture
def record_validation(request):
    """Record one checked quantity of a validation test (call before its assert).

    Parameters
    ----------
    name : str
        What is checked, e.g. "Hertz impact on a wall: restitution (e = 0.5)".
    reference, measured : float (or a short list)
        The reference value (analytic, exact, a paper's) and what the test computed.
    tolerance : float or str
        The bound the assert holds, e.g. ``1e-2``.
    kind : "rel", "abs" or "bound"
        ``rel``: |measured - reference| <= tolerance |reference|; ``abs``:
        |measured - reference| <= tolerance; ``bound``: the assert is an inequality that
        ``note`` states (``reference`` is then the bound).
    source : str
        Where the reference comes from (docs/design.md section, a paper, a formula).
    goal : str
        A paper's own target where the test cannot assert it at its size (e.g. seed 003's
        Table 5 at 80,000 particles): shown beside the bound as a goal, not asserted.
    """
    def record(name, *, reference, measured, tolerance, kind="rel", source="", unit="",
               note="", goal=""):
        _RECORDS.append({
            "name": name, "test": request.node.nodeid, "reference": _number(reference),
            "measured": _number(measured), "tolerance": _number(tolerance), "kind": kind,
            "unit": unit, "source": source, "note": note, "goal": goal})
    return record


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    rep = outcome.get_result()
    if rep.when == "call" or (rep.when == "setup" and rep.outcome != "passed"):
        for r in _RECORDS:
            if r["test"] == item.nodeid and "outcome" not in r:
                r["outcome"] = rep.outcome


def _host() -> str:
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return f"{line.split(':', 1)[1].strip()} ({os.cpu_count()} cores)"
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=_ROOT,
                              capture_output=True, text=True, timeout=10).stdout.strip()
    except Exception:
        return ""


def pytest_sessionfinish(session, exitstatus):
    if not _RECORDS:
        return
    path = _results_path()
    try:
        old = json.loads(path.read_text()).get("records", []) if path.exists() else []
    except (OSError, ValueError):
        old = []
    stamp = {"date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
             "host": _host(), "commit": _commit()}
    new = {(r["test"], r["name"]): {**r, **stamp} for r in _RECORDS}
    # keep earlier sessions' records (a partial run updates its own) unless their test
    # file is gone
    kept = [r for r in old if (r.get("test"), r.get("name")) not in new
            and (_ROOT / r.get("test", "").split("::")[0]).exists()]
    merged = kept + list(new.values())
    merged.sort(key=lambda r: (r["test"], r["name"]))
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps({"records": merged}, indent=1) + "\n")
    os.replace(tmp, path)
