"""The cases with walls that respond (demos/servo_lid.toml, free_piston.toml,
vibrated_plate.toml, vibrated_bed.toml, grate.toml) run in their quick form, each checked
against statics, the lift-off time or the prescribed motion."""
import dataclasses
import math
import pathlib
import types

import numpy as np
import pytest

from gsi.case import load_case
from gsi.run import run_case
from gsi.studies.ensemble import run_ensemble

DEMOS = pathlib.Path(__file__).resolve().parents[2] / "demos"


def _run(name, tmp_path):
    return run_case(load_case(DEMOS / f"{name}.toml"), out=tmp_path, quick=True,
                    pictures=False, verbose=False)


def _last_third(mon, duration):
    return mon["time_s"] >= 2.0 * duration / 3.0


def test_servo_lid_quick(tmp_path, record_validation):
    """The lid holds 600 Pa over the box section; the floor carries the lid force plus
    the bed's weight (frictionless sides carry no vertical load)."""
    case = load_case(DEMOS / "servo_lid.toml")
    res = _run("servo_lid", tmp_path)
    lid, box = res.monitors["lid"], res.monitors["box"]
    late = _last_third(lid, case.quick_variant().run.duration)
    W = np.linalg.norm(res.weight)
    target = 600.0 * 9.0e-4
    lid_force = -lid["load"][late].mean()
    floor = -box["Fz_N"][late].mean()
    assert lid["target_N"][late] == pytest.approx(target)
    record_validation("servo lid demo (150 beads): mean lid stress over the last third = "
                      "target", reference=600.0, measured=lid_force / 9.0e-4, tolerance=1e-2,
                      unit="Pa", source="the controller's set point")
    record_validation("servo lid demo: floor force = lid force + bed weight",
                      reference=lid_force + W, measured=floor, tolerance=1e-2, unit="N",
                      source="statics of the bed, frictionless side walls")
    assert lid_force == pytest.approx(target, rel=1e-2)
    assert floor == pytest.approx(lid_force + W, rel=1e-2)


def test_free_piston_quick(tmp_path, record_validation):
    """A 20 g piston comes to rest on the bed: the floor carries (M + m_bed) g."""
    case = load_case(DEMOS / "free_piston.toml")
    res = _run("free_piston", tmp_path)
    lid, box = res.monitors["lid"], res.monitors["box"]
    late = _last_third(lid, case.quick_variant().run.duration)
    W = np.linalg.norm(res.weight)
    Mg = 0.02 * 9.81
    floor = -box["Fz_N"][late].mean()
    record_validation("free piston demo: floor force = (M + m_bed) g", reference=Mg + W,
                      measured=floor, tolerance=5e-3, unit="N", source="statics")
    assert floor == pytest.approx(Mg + W, rel=5e-3)
    assert -lid["load"][late].mean() == pytest.approx(Mg, rel=5e-3)   # the bed holds it up


def test_vibrated_bed_quick(tmp_path):
    """The box moves exactly as prescribed; at Gamma = 2.5 the bed flies each cycle (the
    floor carries nothing for a while) and lands hard (several weights)."""
    res = _run("vibrated_bed", tmp_path)
    sh = res.monitors["shaker"]
    A, f = 0.000994, 25.0
    np.testing.assert_allclose(sh["position"], A * np.sin(2 * math.pi * f * sh["time_s"]),
                               rtol=0, atol=1e-9)
    W = np.linalg.norm(res.weight)
    late = sh["time_s"] >= 0.1
    assert sh["load"][late].max() > -0.05 * W      # in flight: the floor carries < 5 %
    assert sh["load"][late].min() < -3.0 * W       # landing
    assert res.n_lost == 0


GRATE_SEEDS = (11, 12, 13)          # the demo's seed and two more: an ensemble of fills


def _grate_member(seed, case, out):
    """The grate with fill ``seed``, quick: its result (counts and monitors: picklable)."""
    member = dataclasses.replace(case, run=dataclasses.replace(case.run, seed=seed))
    res = run_case(member, out=out / f"seed{seed}", quick=True, pictures=False,
                   verbose=False)
    return types.SimpleNamespace(n_lost=res.n_lost, monitors=res.monitors)


def test_grate_quick(tmp_path, record_validation):
    """Seed 000's forward-acting grate (demos/grate.toml): the moving bars follow their
    stroke (on the chord between updates every 20 steps, within A (w k dt)^2/8); the bed
    ratchets forward: sampled once per stroke with the bars home, the particles past the
    front of bar0 grow from t = 0.4 s (filled, the roof down) to 1 s by more than 5 of 150
    in the ensemble mean less 3 standard errors (the bed is chaotic: one fill is one
    realisation; measured on seeds 11-15: gains 12, 18, 15, 18, 14, a systematic push of
    ~1.5 mm per stroke); in every member the hot roof heats the top of the bed while its
    bottom stays cold (the fills run two at a time)."""
    case = load_case(DEMOS / "grate.toml")
    A, w, k = 0.006, 2 * math.pi * 5.0, 20
    dt = case.time_step()
    gains = []
    # the fills run two at a time (gsi.studies.ensemble: one worker process per core)
    for res in run_ensemble(_grate_member, GRATE_SEEDS, args=(case, tmp_path)):
        st = res.monitors["stroke"]
        s = A * (1 - np.cos(w * st["time_s"]))
        np.testing.assert_allclose(st["position"], s, rtol=0,
                                   atol=A * (w * k * dt) ** 2 / 8 + 1e-12)
        fw = res.monitors["forward"]
        at = lambda t: fw["count"][np.argmin(np.abs(fw["time_s"] - t))]     # noqa: E731
        gains.append(at(1.0) - at(0.4))
        assert res.n_lost == 0
        T = res.monitors["fuel_T"]
        assert T["T_max_K"][-1] > 320.0 and T["T_min_K"][-1] < 301.0
    mean = float(np.mean(gains))
    se = float(np.std(gains, ddof=1) / math.sqrt(len(gains)))
    record_validation(f"grate demo (seed 000, 150 particles, M = {len(gains)}): particles "
                      "carried past bar0 from 0.4 to 1 s, ensemble mean - 3 SE",
                      reference=5, measured=mean - 3 * se, tolerance=0, kind="bound",
                      source="seed 000's forward-acting grate (Figs. 10-13): the bed moves on",
                      note=f"mean {mean:.1f} +- {se:.1f} (SE) > 5: a systematic push")
    assert mean - 3 * se > 5, gains


def test_vibrated_plate_quick(tmp_path, record_validation):
    """The sphere stays on the plate until the plate's acceleration first falls below -g,
    at w t1 = pi - arccos(1/Gamma), and then leaves it (quick: 30 ms, past t1 = 19.5 ms)."""
    res = _run("vibrated_plate", tmp_path)
    ball = res.monitors["ball"]
    gamma, w = 1.3, 2 * math.pi * 20.0
    t1 = (math.pi - math.acos(1 / gamma)) / w
    settled = ball["time_s"] > 0.003               # the start has rung out
    off = ball["time_s"][settled & (ball["contacts"] == 0)]
    assert len(off) > 0
    record_validation("vibrated plate demo (Gamma = 1.3): lift-off time t1 = (pi - "
                      "arccos(1/Gamma))/w", reference=t1, measured=off[0], tolerance=1e-3,
                      kind="abs", unit="s", source="the plate's acceleration reaches -g",
                      note="monitor samples every 0.2 ms")
    assert off[0] == pytest.approx(t1, abs=1e-3)
