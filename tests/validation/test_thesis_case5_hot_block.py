"""Seed 001 (thesis), chapter III, case 5: a packed hot block falls on a cold bed while
heat diffuses through the particle contacts.

The case is ``demos/graded/case5_hot_block.toml``, run by the runner as a user would
(``gsi.run.Runner``; monitors as arrays). 25 copper particles at 373.15 K fall 7 mm
onto 24 at 273.15 K resting on the floor; ``radius`` model; adiabatic walls (the thesis:
heat only between particles).

References:

* heat is conserved: the heat-capacity weighted mean stays (24 x 273.15 + 25 x
  373.15)/49 = 324.1704 K (to round-off);
* the spread max T - min T never grows: the explicit update T_i += dt sum_j H_ij (T_j -
  T_i)/C_i makes each new temperature a convex combination of old ones while dt sum_j
  H_ij/C_i <= 1 (the DEM checks it), so max T cannot rise nor min T fall;
* heat does diffuse: the block's mean falls and the bed's rises, monotonically.
"""
import pathlib

import numpy as np
import pytest

from gsi.case import load_case
from gsi.case.biot_check import check_biot
from gsi.run import Runner

CASE = pathlib.Path(__file__).resolve().parents[2] / "demos" / "graded" / "case5_hot_block.toml"


def test_hot_block_on_cold_bed(tmp_path):
    case = load_case(CASE)
    runner = Runner(case, out=tmp_path, pictures=False, verbose=False)
    res = runner.run()
    assert res.n_particles == 49 and res.n_lost == 0
    mon = res.monitors
    T_all, block, bed = mon["all_T"], mon["block_T"], mon["bed_T"]
    assert np.all(T_all["count"] == 49)
    mean0 = (24 * 273.15 + 25 * 373.15) / 49
    # heat conserved (adiabatic walls): round-off only (measured 1.8e-12 K)
    assert np.abs(T_all["T_mean_K"] - mean0).max() < 1e-9
    # the spread never grows (max principle of the explicit contact conduction)
    spread = T_all["T_max_K"] - T_all["T_min_K"]
    assert spread[0] == pytest.approx(100.0, abs=1e-9)
    assert np.diff(T_all["T_max_K"]).max() <= 1e-12
    assert np.diff(T_all["T_min_K"]).min() >= -1e-12
    assert np.diff(spread).max() <= 1e-12
    assert spread[-1] < spread[0] - 0.3                 # measured 99.52 K at 0.4 s
    # heat flows from the block to the bed: the gap of the group means closes monotonically
    gap = block["T_mean_K"] - bed["T_mean_K"]
    assert np.diff(gap).max() <= 1e-12
    assert gap[-1] < 90.0                               # measured 86.2 K at 0.4 s
    # the block landed and the bed came to rest
    assert mon["particles"]["kinetic_energy_J"][-1] < 1e-8
    # the Biot number of the resting contacts (thesis eq. II.4): small here
    rep = check_biot(runner.case, runner.sim, warn=False)
    assert rep.n_contacts > 40
    assert rep.max < 0.1
