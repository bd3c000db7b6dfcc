"""The drive torque of a turning drum against the moment balance about its axis (exact).

The bed's torque on the drum about the axis y is M g x_com - dL/dt: gravity's moment
about the axis (the weight M g acting at the centre of mass, x_com from the axis) less the
rate of change of the bed's angular momentum.  Once the bed cascades steadily, dL/dt
averages out over a window, so the wall's reported torque (``wall.torque``, the moment of
each contact force at its contact point, as LIGGGHTS' ``mesh/surface/stress`` computes
it) must equal M g times the window's mean x_com.

The case is the seed-003 drum of benchmarks/drum_vs_liggghts.py at 300 spheres (R =
46.6 mm, one turn per 1.97 s, Fr 0.048), turned 2 s from rest; the window is its second
second, after the first avalanche (measured: the 0.5 s windows from 0.75 s on balance to
0.02-1.8 %).  The bound, 3 %: |dL/dt| over the window is the change of L = I omega between
its ends over 1 s, with I omega of this bed about 7e-4 N m s and its fluctuation a fraction
of that against a torque of 0.047 N m; a contact force's moment taken at the sphere's
centre instead of the contact point would change the torque of the friction on the
cylinder by r/R = 11 %.
"""
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "benchmarks"))


def test_drum_torque_is_the_moment_of_the_weight(tmp_path, record_validation):
    import drum_vs_liggghts as bench
    from gsi.studies import drum
    geometry = drum.drum_geometry(300)
    x, r = bench.settled_bed(geometry, 0.5, str(tmp_path / "bed.npz"))
    hot = x[:, 0] < 0.0
    bench.write_particles(tmp_path / "p.csv", x, r, np.where(hot, drum.T_HOT, drum.T_COLD))
    steps = 20000                                   # 2 s at dt = 1e-4 s
    case = bench.gsi_case(geometry, tmp_path / "p.csv", steps * drum.DT)
    rows, _, n = bench.run_gsi(case, 1, steps, hot)
    assert n == 300
    window = rows[len(rows) // 2:]                  # 1-2 s
    torque = np.mean([s["torque_y"] for s in window])
    weight = float(np.sum(bench.RHO * 4.0 / 3.0 * np.pi * r ** 3)) * 9.81
    moment = weight * np.mean([s["com_x"] for s in window])
    assert abs(moment) > 0.02 * weight * geometry.radius   # the bed is tilted
    record_validation("turning drum (seed 003, 300 spheres, 1-2 s): mean drive torque "
                      "against M g x_com", reference=moment, measured=torque, tolerance=0.03,
                      source="moment balance about the axis (dL/dt averages out)", unit="N m")
    assert abs(torque - moment) <= 0.03 * abs(moment), (torque, moment)
