"""Input checks, time-step checks, lost particles and blow-up diagnosis."""
import warnings

import numpy as np
import pytest

from gsi.dem import Material, MeshWall, Simulation
from gsi.errors import GsiInputError, GsiRunError

MAT = {"m": Material(E=5e6, nu=0.3, rho=2500)}
DOM = ((0, 0, 0), (0.01, 0.01, 0.01))


def test_dt_above_rayleigh_refused_unless_forced():
    """gsi's one rule (gsi.dem.materials.DT_*): refused above 0.5 t_R unless forced."""
    sim = Simulation(MAT, dt=1e-3, skin=2e-4, domain=DOM)
    sim.add_particles([[0.005] * 3], 1e-3, material="m")
    with pytest.raises(GsiInputError, match=r"dt = 0.001: above 0.5 x the Rayleigh time t_R"):
        sim.step(1)
    sim = Simulation(MAT, dt=8e-5, skin=2e-4, domain=DOM)
    sim.add_particles([[0.005] * 3], 1e-3, material="m")
    assert 0.5 * sim.rayleigh_time() < 8e-5 < sim.rayleigh_time()
    with pytest.raises(GsiInputError, match=r"use dt <= 2.4\de-05 s or pass force_dt=True"):
        sim.step(1)
    sim = Simulation(MAT, dt=1e-3, skin=2e-4, domain=DOM, force_dt=True, gravity=(0, 0, 0))
    sim.add_particles([[0.005] * 3], 1e-3, material="m")
    with pytest.warns(UserWarning, match="Rayleigh"):
        sim.step(1)


def test_dt_warns_above_03_rayleigh():
    sim = Simulation(MAT, dt=4e-5, skin=2e-4, domain=DOM)
    sim.add_particles([[0.005] * 3], 1e-3, material="m")
    assert 0.3 * sim.rayleigh_time() < 4e-5 < sim.rayleigh_time()
    assert 4e-5 < 0.5 * sim.rayleigh_time()
    with pytest.warns(UserWarning, match="above 0.3 x the Rayleigh time"):
        sim.step(1)


def test_linear_dt_rule():
    sim = Simulation(MAT, contact="linear", k_n=1e3, dt=1e-3, skin=2e-4, domain=DOM)
    sim.add_particles([[0.005] * 3], 1e-3, material="m")
    with pytest.raises(GsiInputError, match=r"above 0.1 x t_c = pi sqrt\(m\*/k_n\)"):
        sim.step(1)


@pytest.mark.parametrize("kw,match", [
    (dict(dt=-1.0), "dt = -1.0"), (dict(skin=0.0), "skin = 0.0"),
    (dict(contact="bogus"), "contact = 'bogus'"), (dict(heat="x"), "heat = 'x'"),
    (dict(contact="linear"), "k_n = None"),
    (dict(domain=((0, 0, 0), (1, 1, -1))), "domain = "),
])
def test_constructor_errors_name_the_key(kw, match):
    args = dict(dt=1e-6, skin=2e-4, domain=DOM)
    args.update(kw)
    with pytest.raises(GsiInputError, match=match):
        Simulation(MAT, **args)


def test_bad_particles_and_walls():
    sim = Simulation(MAT, dt=1e-6, skin=2e-4, domain=DOM)
    with pytest.raises(GsiInputError, match="particles.radius"):
        sim.add_particles([[0.005] * 3], -1.0, material="m")
    with pytest.raises(GsiInputError, match="outside the domain"):
        sim.add_particles([[0.05] * 3], 1e-3, material="m")
    with pytest.raises(GsiInputError, match="unknown material"):
        sim.add_particles([[0.005] * 3], 1e-3, material="steel")
    with pytest.raises(GsiInputError, match="plane.normal"):
        sim.add_plane((0, 0, 0), (0, 0, 0), material="m")
    with pytest.raises(GsiInputError, match="mesh_wall.triangles"):
        MeshWall([[0, 0, 0]], [[0, 1, 2]], material="m")
    with pytest.raises(GsiInputError, match="mesh_wall.file"):
        MeshWall.from_file("/nonexistent.stl", material="m")


def test_lost_particles_deleted_or_error():
    sim = Simulation(MAT, dt=1e-6, skin=2e-4, domain=DOM, gravity=(0, 0, 0))
    ids = sim.add_particles([[0.005, 0.005, 0.0095], [0.005, 0.005, 0.005]], 1e-4,
                            material="m", v=[[0, 0, 1.0], [0, 0, 0]])
    sim.step(1000)
    assert sim.n_lost == 1 and sim.n == 1 and sim.ids[0] == ids[1]
    sim = Simulation(MAT, dt=1e-6, skin=2e-4, domain=DOM, gravity=(0, 0, 0), lost="error")
    sim.add_particles([[0.005, 0.005, 0.0095]], 1e-4, material="m", v=[[0, 0, 1.0]])
    with pytest.raises(GsiRunError, match="left the domain"):
        sim.step(1000)


def test_blow_up_names_step_particle_and_cause():
    sim = Simulation(MAT, dt=5e-5, skin=2e-4, domain=DOM, gravity=(0, 0, 0), force_dt=True,
                     v_max=1.0)
    sim.add_particles([[0.005, 0.005, 0.005], [0.0055, 0.005, 0.005]], 1e-3, material="m")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(GsiRunError, match=r"blow-up at step \d+: particle id \d.*dt"):
            sim.step(100)


def test_mesh_wall_from_stl(tmp_path):
    import meshio
    pts = np.array([[0, 0, 0], [0.01, 0, 0], [0, 0.01, 0]], float)
    meshio.write(tmp_path / "t.stl", meshio.Mesh(pts, [("triangle", np.array([[0, 1, 2]]))]))
    sim = Simulation(MAT, dt=1e-6, skin=2e-4, domain=DOM)
    w = sim.add_mesh_wall_file(tmp_path / "t.stl", material="m")
    np.testing.assert_allclose(w.vertices, pts, atol=1e-7)


def test_runaway_loss_stops_the_run_with_a_diagnosis():
    """Most particles leaving the domain in one step is a blow-up, not an outflow."""
    sim = Simulation(MAT, dt=2e-6, skin=2e-4, domain=DOM, gravity=(0, 0, 0))
    x = np.column_stack([np.full(12, 0.00995), np.linspace(0.001, 0.009, 12),
                         np.full(12, 0.005)])
    sim.add_particles(x, 1e-4, material="m", v=(50.0, 0.0, 0.0))
    with pytest.raises(GsiRunError, match=r"runaway loss at step \d+: 12 of 12 particles left "
                                          r"the domain in one step \(fastest 50 m/s\)"):
        sim.step(5)
    # a few particles leaving is an outflow: counted, the run goes on
    sim = Simulation(MAT, dt=2e-6, skin=2e-4, domain=DOM, gravity=(0, 0, 0))
    sim.add_particles(x[:3], 1e-4, material="m", v=(50.0, 0.0, 0.0))
    sim.add_particles(x[3:] - [0.005, 0, 0], 1e-4, material="m")
    sim.step(5)
    assert sim.n_lost == 3 and sim.n == 9
