"""VTU/PVD output is readable (meshio parses the binary XML) and the series is valid."""
import xml.etree.ElementTree as ET

import meshio
import numpy as np

from gsi.dem import Material, ParticleWriter, Simulation, write_wall_vtu


def test_particle_series_and_wall(tmp_path):
    sim = Simulation({"m": Material(E=5e6, nu=0.3, rho=2500)}, gravity=(0, 0, -9.81),
                     dt=2e-6, skin=2e-4, domain=((-0.01,) * 3, (0.01,) * 3))
    wall = sim.add_mesh_wall([[-0.01, -0.01, 0], [0.01, -0.01, 0], [0, 0.01, 0]], [[0, 1, 2]],
                             material="m", vertex_temperature=[1.0, 2.0, 3.0])
    sim.add_particles([[0, 0, 1.0e-3], [0.003, 0, 2e-3]], [1e-3, 0.8e-3], material="m",
                      T=[5.0, 6.0])
    w = ParticleWriter(tmp_path / "out", "p")
    for _ in range(3):
        sim.step(100)
        w.write(sim)
        root = ET.parse(tmp_path / "out" / "p.pvd").getroot()   # valid after every write
    w.close()
    files = [d.get("file") for d in root.iter("DataSet")]
    assert len(files) == 3
    m = meshio.read(tmp_path / "out" / files[-1])
    np.testing.assert_allclose(m.points, sim.x)
    np.testing.assert_allclose(m.point_data["velocity"], sim.v)
    np.testing.assert_allclose(m.point_data["temperature"], sim.T)
    np.testing.assert_array_equal(m.point_data["id"], sim.ids)
    assert set(m.point_data) >= {"radius", "speed", "omega", "type", "contact_count"}
    write_wall_vtu(tmp_path / "wall.vtu", wall)
    mw = meshio.read(tmp_path / "wall.vtu")
    np.testing.assert_allclose(mw.points, wall.vertices)
    np.testing.assert_allclose(mw.point_data["vertex_temperature"], [1, 2, 3])
    np.testing.assert_allclose(mw.cell_data["triangle_force"][0], wall.triangle_force)
