"""Walls: shapes (closed, inward normals), motions (rpm, rotation velocities, schedules
taking effect at their event times), a drum dragging a particle, the hopper's slide gate
as a plate with a schedule, mesh files, and the checks (each names its key)."""
import math

import meshio
import numpy as np
import pytest

from gsi.case.walls import Motion, MotionEvent, Wall, next_event
from gsi.config.schema import load
from gsi.dem import Material, Simulation, shapes
from gsi.errors import GsiInputError

MAT = {"m": Material(E=5e6, nu=0.3, rho=2500, mu=0.5, e=0.5)}
DOM = ((-0.1, -0.1, 0.0), (0.1, 0.1, 0.15))


def _sim(dt=5e-5):
    return Simulation(MAT, dt=dt, skin=1e-3, domain=DOM)


def _step_to(sim, t, walls):
    """Advance to time t, stopping at every schedule event to apply the motions (what a
    runner does)."""
    while sim.time < t - 1e-12:
        t_next = min(t, next_event([w for w, _ in walls], sim.time))
        sim.step(max(1, math.ceil((t_next - sim.time) / sim.dt - 1e-9)))
        for w, handles in walls:
            w.apply_motion(handles, sim.time)


@pytest.mark.parametrize("axis", [(0, 0, 1), (0, 1, 0), (1, -1, 0.5)])
def test_drum_closed_consistent_inward(axis):
    V, T = shapes.drum(centre=(0.1, 0.2, 0.3), axis=axis, radius=0.05, length=0.04, facets=32)
    assert shapes.closed_and_consistent(T) == (True, True)
    # inward normals: negative enclosed volume equal to the inscribed 32-gon prism
    prism = 0.5 * 32 * 0.05 ** 2 * math.sin(2 * math.pi / 32) * 0.04
    assert shapes.enclosed_volume(V, T) == pytest.approx(-prism, rel=1e-12)
    # every end-cap vertex lies in its end plane, every mantle vertex at the radius
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    s = (V - (0.1, 0.2, 0.3)) @ a
    rho = np.linalg.norm(V - (0.1, 0.2, 0.3) - s[:, None] * a, axis=1)
    assert ((np.abs(s) < 1e-12) | (np.abs(s - 0.04) < 1e-12) | (np.abs(rho - 0.05) < 1e-12)).all()


@pytest.mark.parametrize("make", [
    lambda: shapes.cone(outlet_radius=0.02, top_radius=0.1, length=0.1, facets=24),
    lambda: shapes.funnel(outlet_radius=0.02, top_radius=0.1, length=0.1, spout_length=0.05),
    lambda: shapes.cylinder(radius=0.05, length=0.1, facets=16)])
def test_open_shapes_face_the_axis(make):
    V, T = make()
    n = shapes.triangle_normals(V, T)
    c = V[T].mean(axis=1)
    assert (np.einsum("ij,ij->i", n[:, :2], c[:, :2]) < 0).all()
    closed, consistent = shapes.closed_and_consistent(T)
    assert consistent and not closed


def test_box_and_plate_shapes():
    V, T = shapes.box(lo=(0, 0, 0), hi=(1, 2, 3))
    assert shapes.closed_and_consistent(T) == (True, True)
    assert shapes.enclosed_volume(V, T) == pytest.approx(-6.0)
    u, v = shapes.plate_edges(normal=(0, 0, 2), size=(0.3, 0.2))
    V, T = shapes.plate(centre=(1, 1, 1), edge_u=u, edge_v=v)
    assert np.allclose(shapes.triangle_normals(V, T), (0, 0, 1))
    assert np.ptp(V, axis=0) == pytest.approx([0.3, 0.2, 0.0])


@pytest.mark.parametrize("spec, omega", [(dict(rpm=10.0), 2 * math.pi / 6),
                                         (dict(omega=1.5), 1.5), (dict(rpm=-30.0), -math.pi)])
def test_rotation_sets_vertex_velocities(spec, omega):
    sim = _sim()
    centre = np.array([0.0, -0.02, 0.06])
    wall = load(Wall, dict(kind="drum", material="m", centre=list(centre), axis=[0, 2, 0],
                           radius=0.05, length=0.04, motion=dict(kind="rotation", **spec)), "walls[0]")
    (h,) = wall.add_to(sim)
    x = h.vertices
    expect = np.cross([0.0, omega, 0.0], x - centre)
    np.testing.assert_allclose(h.vertex_velocity, expect, rtol=0, atol=1e-14)
    assert np.abs(expect).max() > 0.04                  # the rim moves at omega R
    np.testing.assert_array_equal(h.centre, centre)


@pytest.mark.parametrize("rpm", [10.0, -10.0])
def test_particle_in_rotating_drum_stays_inside_and_is_dragged(rpm):
    sim = _sim()
    drum = Wall(kind="drum", material="m", centre=(0, -0.02, 0.06), axis=(0, 1, 0), radius=0.05,
                length=0.04, motion=Motion.rotation(rpm=rpm))
    h = drum.add_to(sim)
    r = 4e-3
    sim.add_particles([[0.0, 0.0, 0.06 - 0.05 + r + 1e-3]], r, material="m")   # 1 mm gap
    for _ in range(20):
        sim.step(100)
        x = sim.x[0]
        assert math.hypot(x[0], x[2] - 0.06) + r < 0.05 + 5e-4        # overlap < 0.5 mm
        assert abs(x[1]) + r < 0.02 + 5e-4
    w = rpm * 2 * math.pi / 60
    wall_speed = -w * 0.05                 # omega y x (0, 0, -R): the bottom moves along -x w
    assert sim.time == pytest.approx(0.1)
    assert np.sign(sim.x[0, 0]) == np.sign(wall_speed) and abs(sim.x[0, 0]) > 1.5e-3
    # it rolls on the wall without slipping: the contact point moves with the wall
    n = np.array([sim.x[0, 0], 0.0, sim.x[0, 2] - 0.06])
    n /= np.linalg.norm(n)
    v_contact = sim.v[0] + np.cross(sim.omega[0], r * n)
    v_wall = np.cross([0.0, w, 0.0], (0.05 - 1e-4) * n)
    assert np.linalg.norm(v_contact - v_wall) < 0.1 * abs(wall_speed)
    assert len(h) == 1


def test_schedule_state_and_event_times():
    m = load(Motion, dict(kind="schedule", axis=[0, 0, 1], centre=[1, 0, 0], events=[
        dict(t=0.1, velocity=[1, 0, 0]), dict(t=0.2, rpm=60.0), dict(t=0.3)]), "walls[0].motion")
    assert m.event_times() == [0.1, 0.2, 0.3]
    assert m.next_event(0.0) == 0.1 and m.next_event(0.1) == 0.2 and m.next_event(0.3) == math.inf
    v, om, c = m.state_at(0.0999)
    assert not v.any() and not om.any() and c is None
    v, om, c = m.state_at(0.1)
    assert v.tolist() == [1, 0, 0] and not om.any()
    v, om, c = m.state_at(0.25)
    assert not v.any() and om == pytest.approx([0, 0, 2 * math.pi]) and c.tolist() == [1, 0, 0]
    assert not np.any(m.state_at(0.3)[1])


def test_slide_gate_is_a_plate_with_a_schedule():
    """The hopper's gate: fixed until open_time, then +x at gate_speed until it cleared the
    outlet (travel 2 half + 2 r_max), then fixed; a particle resting on it falls through."""
    half, r, speed, t_open = 0.02, 4e-3, 2.0, 0.02
    travel = 2 * half + 2 * r
    gate = Wall.slide_gate(material="m", centre=(0.0, 0.0, 0.05), half=half, open_time=t_open,
                           speed=speed, travel=travel)
    assert gate.kind == "plate" and gate.motion.event_times() == [t_open, t_open + travel / speed]
    sim = _sim()
    handles = gate.add_to(sim)
    (h,) = handles
    x0 = h.vertices.copy()
    sim.add_particles([[0.0, 0.0, 0.05 + r + 2e-4]], r, material="m")
    walls = [(gate, handles)]
    _step_to(sim, t_open, walls)
    np.testing.assert_array_equal(h.vertices, x0)                  # closed until open_time
    z_rest = sim.x[0, 2]
    assert 0.05 + r - 2e-4 < z_rest < 0.05 + r                       # resting on the gate
    assert h.vertex_velocity[:, 0] == pytest.approx(speed)          # velocity switched at t_open
    sim.step(1)
    assert h.vertices[:, 0] - x0[:, 0] == pytest.approx(speed * sim.dt, rel=1e-9)
    _step_to(sim, t_open + travel / speed, walls)
    assert h.vertices[:, 0] - x0[:, 0] == pytest.approx(travel, rel=1e-9)
    assert not h.vertex_velocity.any()                               # stopped at the event
    _step_to(sim, 0.08, walls)
    assert h.vertices[:, 0] - x0[:, 0] == pytest.approx(travel, rel=1e-9)
    assert sim.x[0, 2] < 0.05 - r                                    # fell through the opening


def test_mesh_wall_from_a_file_in_mm(tmp_path):
    V, T = shapes.drum(centre=(0, 0, 0), axis=(1, 0, 0), radius=50.0, length=40.0, facets=16)
    meshio.write(tmp_path / "drum.stl", meshio.Mesh(V, [("triangle", T)]))
    table = dict(kind="mesh", material="m", file="drum.stl", translate=[-0.02, 0.0, 0.06])
    with pytest.raises(GsiInputError, match=r"^walls\[1\]\.scale: .*did you give mm\? set scale = 0\.001"):
        load(Wall, table, "walls[1]").check("walls[1]", domain_lo=DOM[0], domain_hi=DOM[1],
                                            base_dir=tmp_path)
    wall = load(Wall, dict(table, scale=1e-3), "walls[1]")
    wall.check("walls[1]", domain_lo=DOM[0], domain_hi=DOM[1], base_dir=tmp_path)
    sim = _sim()
    (h,) = wall.add_to(sim, base_dir=tmp_path)
    assert h.vertices.min(0) == pytest.approx([-0.02, -0.05, 0.01], abs=1e-6)
    assert h.vertices.max(0) == pytest.approx([0.02, 0.05, 0.11], abs=1e-6)
    assert shapes.closed_and_consistent(h.triangles) == (True, True)


def test_box_of_planes_and_triangulated_box():
    sim = _sim()
    planes = Wall(kind="box", material="m", lo=(-0.05, -0.05, 0.0), hi=(0.05, 0.05, 0.1),
                  motion=Motion.translation((0.0, 0.0, 0.1))).add_to(sim)
    assert len(planes) == 5 and all(p.velocity.tolist() == [0, 0, 0.1] for p in planes)
    mesh = Wall(kind="box", material="m", lo=(-0.05, -0.05, 0.0), hi=(0.05, 0.05, 0.1), lid=True,
                as_planes=False, motion=Motion.rotation(axis=(0, 0, 1), centre=(0, 0, 0), omega=2.0))
    (h,) = mesh.add_to(sim)
    assert len(h.triangles) == 12
    np.testing.assert_allclose(h.vertex_velocity, np.cross([0, 0, 2.0], h.vertices), atol=1e-15)


@pytest.mark.parametrize("table, match", [
    (dict(kind="plane", point=[0, 0, 0], normal=[0, 0, 1],
          motion=dict(kind="rotation", rpm=5.0, axis=[0, 0, 1], centre=[0, 0, 0])),
     r"^walls\[2\]\.motion\.kind = 'rotation': a plane cannot rotate"),
    (dict(kind="box", lo=[0, 0, 0], hi=[1, 1, 1], motion=dict(kind="schedule", events=[
        dict(t=0.1, omega=1.0, axis=[0, 0, 1], centre=[0, 0, 0])])),
     r"^walls\[2\]\.motion\.kind = 'schedule': a box of planes cannot rotate; set as_planes = false"),
    (dict(kind="plate", centre=[0, 0, 0], edge_u=[1, 0, 0], edge_v=[0, 1, 0],
          motion=dict(kind="translation", rpm=3.0)),
     r"^walls\[2\]\.motion\.rpm: not a key of a 'translation' motion; set walls\[2\]\.motion\.kind = 'rotation'"),
    (dict(kind="plate", centre=[0, 0, 0], edge_u=[1, 0, 0], edge_v=[0, 1, 0],
          motion=dict(kind="rotation", rpm=3.0)), r"^walls\[2\]\.motion\.axis: missing"),
    (dict(kind="drum", centre=[0, 0, 0], radius=0.1, length=0.1, motion=dict(kind="rotation")),
     r"^walls\[2\]\.motion\.rpm: give exactly one of rpm"),
    (dict(kind="drum", centre=[0, 0, 0], radius=0.1, length=0.1,
          motion=dict(kind="schedule", events=[dict(t=0.2), dict(t=0.1)])),
     r"^walls\[2\]\.motion\.events\[1\]\.t = 0\.1: event times must increase"),
    (dict(kind="cone", centre=[0, 0, 0], outlet_radius=0.1, top_radius=0.05, length=0.1),
     r"^walls\[2\]\.outlet_radius = 0\.1: must be < top_radius"),
    (dict(kind="plate", centre=[0, 0, 0], normal=[0, 0, 1]), r"^walls\[2\]\.size: missing"),
    (dict(kind="mesh", file="a.stl", radius=0.1), r"^walls\[2\]\.radius: not a key of a mesh wall"),
])
def test_wall_keys_name_the_key(table, match):
    with pytest.raises(GsiInputError, match=match):
        load(Wall, dict(table, material="m"), "walls[2]")


@pytest.mark.parametrize("table, match", [
    (dict(kind="plate", centre=[0, 0, 0.05], edge_u=[0.04, 0, 0], edge_v=[0, 0.04, 0],
          motion=dict(kind="schedule", events=[dict(t=0.5, velocity=[1, 0, 0]), dict(t=2.0)])),
     r"^walls\[0\]\.motion\.events\[1\]\.t = 2\.0: at or after the end of the run \(run\.duration = 1\.0 s\)"),
    (dict(kind="mesh", file="missing.stl"), r"^walls\[0\]\.file = 'missing\.stl': no such file"),
    (dict(kind="drum", centre=[0, 0, 0.05], radius=50.0, length=40.0),
     r"^walls\[0\]\.radius: .*did you give mm\? lengths are in m"),
    (dict(kind="cylinder", centre=[0.5, 0, 0.05], radius=0.05, length=0.04),
     r"^walls\[0\]\.centre: the cylinder wall .* lies wholly outside dem\.domain"),
    (dict(kind="plane", point=[0, 0, 0.2], normal=[0, 0, 1]),
     r"^walls\[0\]\.point = \[0\.0, 0\.0, 0\.2\]: the plane leaves the whole domain on its back side"),
])
def test_wall_checks_name_the_key(tmp_path, table, match):
    wall = load(Wall, dict(table, material="m"), "walls[0]")
    with pytest.raises(GsiInputError, match=match):
        wall.check("walls[0]", domain_lo=DOM[0], domain_hi=DOM[1], duration=1.0, base_dir=tmp_path)


def test_motion_python_api_matches_toml():
    a = Motion.schedule([dict(t=0.1, velocity=(1.0, 0.0, 0.0)), MotionEvent(t=0.2)])
    b = load(Motion, dict(kind="schedule", events=[dict(t=0.1, velocity=[1, 0, 0]), dict(t=0.2)]))
    assert a == b


def test_wall_surfaces_write_and_read_back(tmp_path):
    from gsi.dem.output import write_surface_vtu
    funnel = Wall(kind="funnel", material="m", centre=(0, 0, 0.06), outlet_radius=0.01,
                  top_radius=0.05, length=0.05, spout_length=0.02, facets=16)
    plane = Wall(kind="plane", material="m", point=(0, 0, 0.01), normal=(0, 0, 1))
    for i, w in enumerate((funnel, plane)):
        V, T = w.surface(domain=DOM)
        write_surface_vtu(tmp_path / f"w{i}.vtu", V, T, point_data={"z": V[:, 2]})
        m = meshio.read(tmp_path / f"w{i}.vtu")
        np.testing.assert_array_equal(m.points, V)
        np.testing.assert_array_equal(m.cells_dict["triangle"], T)
    V, _ = plane.surface(domain=DOM)
    assert np.allclose(V[:, 2], 0.01) and np.ptp(V[:, 0]) > 0.2     # a patch across the domain
    assert funnel.vertices()[:, 2].min() == pytest.approx(0.04)     # spout 2 cm below the outlet
