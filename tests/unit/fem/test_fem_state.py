"""Checkpoint state: a run restarted from state() continues bit-identically."""
import numpy as np

from gsi import meshes
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat


def _problems(sm):
    p = Elasticity(sm, "aluminium", scheme="generalized_alpha", dt=1e-4, rho_inf=0.7,
                   rayleigh=(2.0, 1e-6), gravity=(0.0, 0.0, -9.81))
    p.clamp("x0")
    p.set_traction("x1", [0.0, 1e4, -2e4])
    h = Heat(sm, "aluminium", dt=0.1, theta=0.5, T_initial=20.0)
    h.set_convection("x1", 50.0, 100.0)
    return p, h


def test_restart_is_bit_identical():
    sm = meshes.build("box", length_x=0.5, length_y=0.05, length_z=0.05, n=(10, 1, 1))
    p, h = _problems(sm)
    for _ in range(4):
        p.step()
        h.step()
    sp, sh = p.state(), h.state()
    for _ in range(3):
        p.step()
        h.step()
    q, g = _problems(sm)
    q.set_state(sp)
    g.set_state(sh)
    for _ in range(3):
        q.step()
        g.step()
    assert np.array_equal(q.u.x.array, p.u.x.array)
    assert np.array_equal(q.v.x.array, p.v.x.array)
    assert np.array_equal(g.T.x.array, h.T.x.array)
    assert q.t == p.t and q.n_steps == p.n_steps == 7
