"""The pour demo in its quick form: the settled bed's weight is carried by the walls."""
import pathlib

import numpy as np

from gsi.config.case import load_case
from gsi.drivers import run_case

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_pour_quick(tmp_path):
    case = load_case(ROOT / "demos" / "pour.toml")
    res = run_case(case, out=tmp_path, quick=True)
    assert res.n_particles == 2000 and res.n_lost == 0
    # at rest the walls carry the weight: 1 % is the residual motion of the bed at t = 0.25 s
    assert abs(res.wall_load / res.weight - 1.0) < 0.02
    # kinetic energy is small compared with the potential energy of the fall (m g * 5 cm)
    assert res.kinetic_energy < 1e-3 * res.weight * 0.05
    # a bed of 2000 beads of r ~ 2 mm (67 cm^3 of glass) in a 6 x 6 cm box at a packing
    # fraction of ~0.6 is 3.1 cm deep; its top lies within a bead diameter or so above that
    solid = 2000 * 4 / 3 * np.pi * 0.002 ** 3
    h_bed = solid / (0.6 * 0.06 * 0.06)
    assert 0.8 * h_bed < res.bed_height < 1.3 * h_bed + 0.004
    for name in ("particles.pvd", "history.csv", "history.png", "pour.png"):
        assert (tmp_path / name).stat().st_size > 0
    pvd = (tmp_path / "particles.pvd").read_text()
    assert pvd.count("<DataSet") == len(list(tmp_path.glob("particles_*.vtu")))
