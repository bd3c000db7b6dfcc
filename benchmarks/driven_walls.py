"""The cost of walls that respond (gsi.dem.wall_drivers): a driven wall makes the step
loop run one-step chunks, each a call into the compiled engine (its arguments are
typed and unboxed per call) plus the driver's few Python lines.

A settled bed of ``--n`` beads in a box is stepped ``--steps`` steps without a driver
and again with a servo lid (its target reached first); the difference per step is the
overhead that ``gsi check``'s estimate adds per DEM step of a case with a driven wall
(:data:`gsi.case.sizes.DRIVEN_STEP_S`).

Run: python benchmarks/driven_walls.py [--n 500] [--steps 2000]
Last line: key=value pairs.
"""
import argparse
import sys
import time

import numpy as np

from gsi.dem import Box, Material, Simulation, lattice_fill
from gsi.dem.wall_drivers import Servo


def bed(n, seed=0):
    mats = {"glass": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5)}
    r = 2e-3
    side = 2.2 * r * int(np.ceil(np.sqrt(n / 4)))
    sim = Simulation(mats, gravity=(0, 0, -9.81), dt=4e-5, skin=5e-4,
                     domain=((0, 0, -0.01), (side, side, 0.2)))
    sim.add_plane((0, 0, 0), (0, 0, 1), material="glass")
    for p, q in (((0, 0, 0), (1, 0, 0)), ((side, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)),
                 ((0, side, 0), (0, -1, 0))):
        sim.add_plane(p, q, material="glass")
    x = lattice_fill(Box((0, 0, 0), (side, side, 0.2)), r, spacing=2.2 * r)[:n]
    rng = np.random.default_rng(seed)
    sim.add_particles(x + rng.uniform(-1e-4, 1e-4, x.shape), r, material="glass")
    sim.step(int(0.3 / sim.dt))
    return sim, side


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=500)
    ap.add_argument("--steps", type=int, default=2000)
    args = ap.parse_args(argv)
    sim, side = bed(args.n)
    t = time.perf_counter()
    sim.step(args.steps)
    free = (time.perf_counter() - t) / args.steps
    top = (sim.x[:, 2] + sim.radius).max()
    lid = sim.add_plane((0, 0, top), (0, 0, -1), material="glass")
    sim.drivers.add(Servo(lid, target=200.0, area=side * side, max_speed=0.05))
    sim.step(args.steps)
    t = time.perf_counter()
    sim.step(args.steps)
    driven = (time.perf_counter() - t) / args.steps
    print(f"particles={sim.n} step_s={free:.4g} driven_step_s={driven:.4g} "
          f"overhead_s={driven - free:.4g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
