"""The benchmarks' own plumbing, at a toy size (their figures are measured by hand, not here).

benchmarks/drum_extrapolation.py once lost an 80,000-particle run (48 min of DEM) at its
last step: ``--out`` named a directory that did not exist, and it was first written after
the DEM.  It now makes ``--out`` at start; this runs the whole benchmark on 200 particles
into a nested directory that does not exist yet and checks what it writes there.
"""
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "benchmarks"))

import drum_extrapolation  # noqa: E402


def test_drum_benchmark_makes_its_out_directory(tmp_path, capsys):
    out = tmp_path / "not" / "yet" / "there"
    res = drum_extrapolation.main(["--particles", "200", "--periods", "1", "--every", "10",
                                   "--spin-up", "0.05", "--period-turns", "0.05",
                                   "--halves-at-t0", "--twin", "0", "--out", str(out)])
    files = sorted(os.listdir(out))
    assert files == ["contact_log_every10.npz", "reference.npz"], files
    with np.load(out / "reference.npz") as ref:
        assert ref["dem_T"].shape[0] == 2          # t1 and t2 of the full DEM
        assert ref["extra10_T"].shape == ref["dem_T"].shape
        hot = ref["hot"]
    assert 0 < hot.sum() < hot.size
    with np.load(out / "contact_log_every10.npz") as log:
        assert np.array_equal(log["T0"], np.where(hot, 30.0, 10.0))
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith("particles=200 ") and "speedup_per_period=" in last
    # one cell of 200 particles has a sampling level; 200 cells of one particle have none
    assert np.isfinite(res["eps_over_level_400_max"]) and "eps_over_level_max=nan" in last
    assert res["particles"] == 200 and res["energy_drift_max"] < 1e-12
    # the twin DEM restarted at t1 without a move is the reference itself, bit for bit
    assert res["twin_eps_abs_max"] == 0.0
