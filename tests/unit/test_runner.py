"""The one runner: events at exact steps, monitors, files that stay readable, errors."""
import csv
import math
import pathlib


import pytest

from gsi.case import (Case, CaseInfo, Dem, Material, Monitor, Motion, Output, ParticleSource,
                      Region, Run, Size, Wall)
from gsi.case.walls import MotionEvent
from gsi.errors import GsiRunError
from gsi.run import Runner

GLASS = Material(E=5.0e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5, k=1.0, cp=840.0)


def _case(**kw):
    base = dict(
        case=CaseInfo(name="tiny"), run=Run(duration=0.05, dt=1.0e-4, seed=1, progress=False),
        dem=Dem(heat="radius", domain_lo=(-0.1, -0.1, -0.1), domain_hi=(0.1, 0.1, 0.1)),
        materials={"glass": GLASS},
        particles=[ParticleSource(name="pile", material="glass", fill="lattice", count=8,
                                  temperature=350.0, size=Size(radius=0.004),
                                  region=Region(kind="box", lo=(-0.02, -0.02, -0.09),
                                                hi=(0.0, 0.0, -0.07)))],
        walls=[Wall(name="floor", kind="plane", material="glass", point=(0.0, 0.0, -0.09),
                    normal=(0.0, 0.0, 1.0), temperature=300.0),
               Wall(name="gate", kind="plate", material="glass", centre=(0.05, 0.05, 0.05),
                    edge_u=(0.02, 0.0, 0.0), edge_v=(0.0, 0.02, 0.0),
                    motion=Motion(kind="schedule", events=[
                        MotionEvent(t=0.01225, velocity=(1.0, 0.0, 0.0)),
                        MotionEvent(t=0.03105)]))],
        monitors=[Monitor(name="hot", kind="temperature", group="pile"),
                  Monitor(name="low", kind="temperature",
                          region=Region(kind="box", lo=(-0.1, -0.1, -0.1), hi=(0.1, 0.1, 0.0))),
                  Monitor(name="floor", kind="wall", target="floor", interval=0.005),
                  Monitor(name="state", kind="particles")],
        output=Output(interval=0.01, pictures=False))
    base.update(kw)
    return Case(**base)


def test_schedule_events_take_effect_at_their_step(tmp_path):
    runner = Runner(_case(), out=tmp_path, verbose=False)
    res = runner.run()
    gate = runner.wall_handles("gate")[0]
    # events between steps take effect at the next step boundary: the gate moves at 1 m/s
    # from step 123 to step 311, exactly 0.0188 m, and then stops
    shift = gate.vertices[:, 0].mean() - 0.05
    assert shift == pytest.approx((311 - 123) * 1.0e-4, abs=1e-12)
    assert res.steps == 500 and res.time == pytest.approx(0.05, abs=1e-15)


def test_monitors_sample_their_interval_and_agree(tmp_path):
    res = Runner(_case(), out=tmp_path, verbose=False).run()
    m = res.monitors
    assert len(m["floor"]["time_s"]) == 11 and len(m["hot"]["time_s"]) == 6
    # the group and the region (everything below z = 0) hold the same 8 particles
    assert (m["hot"]["count"] == 8).all() and (m["low"]["count"] == 8).all()
    assert m["hot"]["T_mean_K"] == pytest.approx(m["low"]["T_mean_K"], rel=1e-15)
    # a 300 K floor cools the 350 K particles; the mean never leaves [300, 350]
    assert m["hot"]["T_mean_K"][-1] < 350.0 and (m["hot"]["T_min_K"] >= 300.0).all()
    with open(tmp_path / "monitors" / "floor.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["time_s", "Fx_N", "Fy_N", "Fz_N", "Tx_Nm", "Ty_Nm", "Tz_Nm"]
    assert len(rows) == 12
    assert float(rows[-1][3]) == pytest.approx(m["floor"]["Fz_N"][-1], rel=1e-9)


def test_a_blow_up_stops_with_a_diagnosis_and_keeps_the_files(tmp_path):
    """Stiff overlapping particles with a step far above their Rayleigh time (forced) fly
    apart faster than v_max: the run stops with a message naming the likely causes, and what
    was written stays readable."""
    case = _case()
    case.materials = {"glass": Material(E=5.0e11, nu=0.3, rho=2500.0)}
    case.particles = [ParticleSource(name="pile", material="glass", fill="file",
                                     file=str(tmp_path / "overlap.csv"))]
    (tmp_path / "overlap.csv").write_text("x,y,z,radius\n0,0,0,0.004\n0.0001,0,0,0.004\n")
    case.monitors = [Monitor(name="state", kind="particles")]
    case.dem.force_dt = True
    with pytest.raises(GsiRunError, match=r"blow-up at step \d+.*dt = 0.0001 s too large"):
        Runner(case, out=tmp_path / "out", verbose=False).run()
    rows = (tmp_path / "out" / "monitors" / "state.csv").read_text().splitlines()
    assert rows[0].startswith("time_s,count") and len(rows) >= 2
    pvd = (tmp_path / "out" / "particles" / "particles.pvd").read_text()
    assert pvd.rstrip().endswith("</VTKFile>")
    assert math.isfinite(float(rows[1].split(",")[1]))
    assert not list(pathlib.Path(tmp_path / "out").rglob("*.tmp*"))

