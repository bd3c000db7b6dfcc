"""Seed 001 (thesis), chapter III, cases 6 and 7: a smooth rotating cavity and the same
cavity with L-shaped flights; the thesis finds "little influence of the cavity rotation"
in the smooth one and a "huge impact" of the flights.

The cases are ``demos/graded/case6_drum_smooth.toml`` and ``case7_drum_flights.toml``
(D = 0.1524 m; 336 copper spheres, r = 2 mm, in a quasi-2D slab; linear law K = 6000 N/m,
e_pp = 0.8, e_pw = 0.5; left half hot, right half cold, conduction between particles
only). Both are run here for one turn at 30 rpm (the thesis's fastest speed, Fr = 0.077).

Mixing is Lacey's index of the two halves on 10 x 10 cells (``kind = "mixing"``
monitor). Measured (one turn, 30 rpm): smooth cavity 0.46 at the end of the turn and
0.43 on average over its second half; with flights 0.68 and 0.55. The test asks that
both beds start segregated, that the flights mix more over the second half of the turn
(by at least 0.05) and at its end, and that the cavity being adiabatic, the mean
temperature of the bed is conserved.
"""
import dataclasses
import pathlib

import numpy as np
import pytest

from gsi.case import load_case
from gsi.runner import Runner

GRADED = pathlib.Path(__file__).resolve().parents[2] / "demos" / "graded"


def one_turn(tmp_path, name):
    case = load_case(GRADED / name)
    case.walls = [dataclasses.replace(w, motion=dataclasses.replace(w.motion, rpm=30.0))
                  if w.motion.kind == "rotation" else w for w in case.walls]
    case.run = dataclasses.replace(case.run, duration=2.0)
    case.output = dataclasses.replace(case.output, interval=1.0)
    res = Runner(case, out=tmp_path / name, pictures=False, verbose=False).run()
    assert res.n_particles == 336 and res.n_lost == 0
    return res.monitors


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    base = tmp_path_factory.mktemp("drums")
    return {k: one_turn(base, f) for k, f in (("smooth", "case6_drum_smooth.toml"),
                                               ("flights", "case7_drum_flights.toml"))}


def test_flights_mix_faster_than_the_smooth_cavity(runs):
    lacey = {k: np.asarray(m["mixing"]["lacey"]) for k, m in runs.items()}
    t = np.asarray(runs["smooth"]["mixing"]["time_s"])
    second_half = t > 1.0
    mean = {k: float(v[second_half].mean()) for k, v in lacey.items()}
    print(f"Lacey index, one turn at 30 rpm: smooth {lacey['smooth'][-1]:.3f} (second-half "
          f"mean {mean['smooth']:.3f}), flights {lacey['flights'][-1]:.3f} "
          f"({mean['flights']:.3f})")
    for v in lacey.values():
        assert v[0] < 0.15                    # the two halves start segregated
    assert mean["flights"] > mean["smooth"] + 0.05
    assert lacey["flights"][-1] > lacey["smooth"][-1]


def test_the_adiabatic_cavity_conserves_the_bed_temperature(runs):
    for m in runs.values():
        # equal halves of identical particles: the bed's mean is the mean of the halves'
        T = 0.5 * (np.asarray(m["left_T"]["T_mean_K"]) + np.asarray(m["right_T"]["T_mean_K"]))
        assert np.abs(T - 323.15).max() < 1e-9 * 323.15
        assert m["left_T"]["T_mean_K"][-1] < 373.15 and m["right_T"]["T_mean_K"][-1] > 273.15
