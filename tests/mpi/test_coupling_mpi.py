"""Two-way coupling on 1 and 2 MPI ranks (FE distributed, DEM on rank 0).

Runs tests/mpi/coupling_bed_case.py and coupling_demo_case.py under ``mpirun -n 1`` and
``mpirun -n 2``:

* the bed-on-membrane case (docs/design.md, "Validation cases", case 8): every coupling record (loads, wall force,
  deflection, work) and the support reactions agree to 1e-9 relative (measured 4e-12:
  the direct solver's round-off differs with the partition, nothing else does);
* the quick hopper_membrane demo: the coupling records agree to 1e-9 of their range from
  the start (discharge, fall) through the first coupling step with impacts, whose loads
  the 2-rank FE receives and answers like the 1-rank FE (measured 7e-13). After that the
  granular stream on the membrane is chaotic: the 1e-11 round-off of the partitioned
  direct solve moves the wall by ~1e-14 m, and a discrete contact event (a contact on a
  triangle face instead of its edge, a contact that starts a step earlier) soon differs:
  measured from the 2nd to the 9th impact step depending on the realisation, then growing
  to a few percent within 0.1 s. So from there on what the stream delivers is compared:
  the discharged mass at every step to 2 % of the charge (measured 0.75 %) and the impulse
  delivered to the membrane over the run to 2 % (measured 0.25 %). The bed case above is
  the tight whole-run comparison.
"""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("gsi_tests_mpirun", HERE / "mpirun.py")
mpirun = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mpirun)

pytestmark = pytest.mark.mpi


def _run(n, name, tmp_path):
    return mpirun.run_json(HERE / f"coupling_{name}_case.py", n, tmp_path / f"{name}{n}.json",
                           timeout=600)


def test_bed_on_membrane_same_on_1_and_2_ranks(tmp_path):
    a = _run(1, "bed", tmp_path)
    b = _run(2, "bed", tmp_path)
    force = np.abs(a["records"]["load_z"]).max()     # lateral loads are noise: same scale
    for key, scale in (("load_x", force), ("load_y", force), ("load_z", force),
                       ("wall_force_z", force), ("max_deflection", None), ("min_uz", None),
                       ("work", None)):
        x, y = np.asarray(a["records"][key]), np.asarray(b["records"][key])
        assert np.abs(x - y).max() <= 1e-9 * (scale or np.abs(x).max()), key
    assert np.asarray(b["reaction"]) == pytest.approx(a["reaction"], rel=1e-9, abs=1e-9 * a["weight"])
    assert b["u_max"] == pytest.approx(a["u_max"], rel=1e-9)
    assert max(a["records"]["balance_rel"] + b["records"]["balance_rel"]) < 1e-12


def test_quick_demo_same_on_1_and_2_ranks(tmp_path):
    r1, r2 = _run(1, "demo", tmp_path), _run(2, "demo", tmp_path)
    a = {k: np.asarray(v) for k, v in r1["coupling"].items()}
    b = {k: np.asarray(v) for k, v in r2["coupling"].items()}
    assert len(a["t"]) == len(b["t"]) and np.array_equal(a["t"], b["t"])
    first = np.flatnonzero(a["load_z"] != 0.0)[0]
    assert a["t"][first] > 0.5                      # the stream reaches the membrane
    upto = np.arange(len(a["t"])) <= first      # discharge, fall, the first impact step
    for key in ("load_x", "load_y", "load_z", "wall_force_z", "max_deflection", "min_uz",
                "work"):
        scale = np.abs(a[key]).max()
        assert np.abs(a[key][upto] - b[key][upto]).max() <= 1e-9 * scale, key
    assert a["max_deflection"][first] > 0
    assert max(a["balance_rel"].max(), b["balance_rel"].max()) < 1e-12
    # after that, the stream on the membrane is chaotic: compare what it delivers
    h1 = {k: np.asarray(v) for k, v in r1["history"].items()}
    h2 = {k: np.asarray(v) for k, v in r2["history"].items()}
    total = h1["mass_kg"].max()
    assert np.abs(h1["mass_kg"] - h2["mass_kg"]).max() < 0.02 * total
    dt = a["t"][0]
    assert b["load_z"].sum() * dt == pytest.approx(a["load_z"].sum() * dt, rel=0.02)
