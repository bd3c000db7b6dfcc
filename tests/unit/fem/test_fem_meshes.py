"""gmsh builders: tags present, tagged areas and volumes equal the geometry's, bad input."""
import math

import numpy as np
import pytest

from gsi import meshes
from gsi.errors import GsiInputError
from gsi.fem import compat
from gsi.fem.elasticity import Elasticity
from gsi.meshes import shell


def _area(sm, name):
    ds = compat.measure("ds", sm.mesh, sm.facet_tags)
    one = compat.constant(sm.mesh, 1.0)
    return compat.assemble_scalar(compat.form(one * ds(sm.tags[name])), sm.mesh.comm)


def _volume(sm):
    one = compat.constant(sm.mesh, 1.0)
    return compat.assemble_scalar(compat.form(one * compat.measure("dx", sm.mesh)), sm.mesh.comm)


def test_membrane_rectangle_tags_and_exact_areas():
    sm = meshes.build("membrane", length_x=0.8, length_y=0.5, thickness=0.01, h=0.1)
    assert set(sm.tags) == {"contact", "support", "outer", "volume"}
    # planar faces are meshed exactly
    assert _area(sm, "contact") == pytest.approx(0.4, rel=1e-12)
    assert _area(sm, "outer") == pytest.approx(0.4, rel=1e-12)
    assert _area(sm, "support") == pytest.approx(2 * (0.8 + 0.5) * 0.01, rel=1e-12)
    assert _volume(sm) == pytest.approx(0.004, rel=1e-12)
    # two element layers through the thickness: vertices on z = 0, t/2, t only
    z = np.unique(np.round(compat.geometry_x(sm.mesh)[:, 2], 12))
    assert z.size == 3


def test_membrane_circle_area_within_faceting_error():
    R, h = 0.5, 0.05
    sm = meshes.build("membrane", shape="circle", radius=R, thickness=0.01, h=h)
    # inscribed polygon with edges ~h: relative area deficit ~ (h/R)^2 / 6 ~ 2e-3
    assert _area(sm, "contact") == pytest.approx(math.pi * R**2, rel=5e-3)
    assert _area(sm, "contact") < math.pi * R**2


def test_silo_flat_areas():
    R, H, t = 0.5, 1.0, 0.01
    sm = meshes.build("silo", radius=R, height=H, thickness=t, h=0.08)
    assert set(sm.tags) == {"contact", "support", "outer", "top", "volume"}
    assert _area(sm, "contact") == pytest.approx(2 * math.pi * R * H + math.pi * R**2, rel=1e-2)
    assert _area(sm, "outer") == pytest.approx(2 * math.pi * (R + t) * (H + t), rel=1e-2)
    assert _area(sm, "support") == pytest.approx(math.pi * (R + t) ** 2, rel=1e-2)
    vol = math.pi * ((R + t) ** 2 - R**2) * H + math.pi * (R + t) ** 2 * t
    assert _volume(sm) == pytest.approx(vol, rel=2e-2)


def test_silo_conical_contact_area():
    R, H, t, hc, r0 = 0.5, 1.0, 0.01, 0.4, 0.1
    sm = meshes.build("silo", radius=R, height=H, thickness=t, bottom="conical",
                      hopper_height=hc, outlet_radius=r0, h=0.08)
    cone = math.pi * (R + r0) * math.hypot(R - r0, hc)
    assert _area(sm, "contact") == pytest.approx(2 * math.pi * R * H + cone, rel=1e-2)
    assert _area(sm, "support") == pytest.approx(
        math.pi * ((r0 + t * math.hypot(1, (R - r0) / hc)) ** 2 - r0**2), rel=5e-2)


def test_hopper_areas():
    r1, r0, H, t = 0.5, 0.1, 0.6, 0.005
    sm = meshes.build("hopper", top_radius=r1, outlet_radius=r0, height=H, thickness=t, h=0.05)
    assert set(sm.tags) == {"contact", "support", "outer", "outlet", "volume"}
    s = math.hypot(r1 - r0, H)
    assert _area(sm, "contact") == pytest.approx(math.pi * (r1 + r0) * s, rel=1e-2)
    # wall volume = lateral area x normal thickness (to first order in t)
    assert _volume(sm) == pytest.approx(math.pi * (r1 + r0) * s * t, rel=3e-2)


def test_drum_areas():
    R, L, t = 0.25, 0.3, 0.005
    sm = meshes.build("drum", radius=R, length=L, thickness=t, h=0.03)
    assert _area(sm, "contact") == pytest.approx(2 * math.pi * R * L, rel=1e-2)
    assert _area(sm, "support") == pytest.approx(2 * math.pi * ((R + t) ** 2 - R**2), rel=2e-2)
    # the inner surface is at radius R: all its vertices are
    x = compat.geometry_x(sm.mesh)
    r = np.hypot(x[:, 1], x[:, 2])
    assert r.min() == pytest.approx(R, rel=1e-9)


@pytest.mark.parametrize("name, params, key", [
    ("membrane", dict(thickness=-0.01), "thickness"),
    ("membrane", dict(shape="triangle"), "shape"),
    ("hopper", dict(outlet_radius=0.6, top_radius=0.5), "outlet_radius"),
    ("silo", dict(bottom="round"), "bottom"),
    ("drum", dict(h=0.0), "h"),
    ("drum", dict(diameter=1.0), "diameter"),
    ("tank", dict(), "structure.mesh"),
])
def test_bad_parameters_raise_one_line_errors(name, params, key):
    with pytest.raises(GsiInputError) as err:
        meshes.build(name, **params)
    msg = str(err.value)
    assert key in msg and "\n" not in msg


def test_registry_lists_the_builders():
    assert {"membrane", "hopper", "silo", "drum"} <= set(meshes.BUILDERS)


def test_shell_tags_areas_layers_and_size_estimate():
    R, H, t, hc, r0, h = 0.5, 1.0, 0.01, 0.4, 0.1, 0.12
    sm = meshes.build("shell", radius=R, height=H, thickness=t, hopper_height=hc,
                      outlet_radius=r0, h=h, n_thickness=2)
    assert {"contact", "support", "outer", "top", "volume"} <= set(sm.tags)
    cone = math.pi * (R + r0) * math.hypot(R - r0, hc)
    assert _area(sm, "contact") == pytest.approx(2 * math.pi * R * H + cone, rel=2e-2)
    # structured wall, revolved: on the cylinder every vertex lies on r = R, R + t/2 or R + t
    x = compat.geometry_x(sm.mesh)
    r = np.hypot(x[:, 0], x[:, 1])[x[:, 2] > 0.05]
    assert np.unique(np.round(r, 9)) == pytest.approx([R, R + t / 2, R + t], abs=1e-9)
    p = Elasticity(sm, "steel", degree=2)
    est = shell.estimate_dofs(radius=R, height=H, hopper_height=hc, outlet_radius=r0, h=h,
                              n_thickness=2)
    assert p.n_dofs == pytest.approx(est, rel=0.02)
    assert shell.estimate_dofs(h=shell.h_for_dofs(1e5, n_thickness=1), n_thickness=1) \
        == pytest.approx(1e5, rel=0.02)
