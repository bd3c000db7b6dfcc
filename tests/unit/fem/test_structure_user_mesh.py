"""A user's own gmsh .msh with differently named physical groups works once the tags are
mapped in TOML (issue acceptance 3), and every wrong name is a one-line input error that
names the key and lists the groups the mesh has. Also: the wall material the structure
gives the DEM, and the "wall k = structure k" rule of thermal contact."""
import tomllib

import numpy as np
import pytest
from mpi4py import MPI

from gsi.case.structure import Structure
from gsi.config.schema import load
from gsi.dem import Material
from gsi.errors import GsiInputError

L, W, T = 0.2, 0.05, 0.01


@pytest.fixture(scope="module")
def msh(tmp_path_factory):
    """A plate written with the gmsh API, groups named the user's way."""
    import gmsh
    path = tmp_path_factory.mktemp("user") / "plate.msh"
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("plate")
    gmsh.model.occ.addBox(0, 0, 0, L, W, T)
    gmsh.model.occ.synchronize()
    ends, top = [], []
    for dim, tag in gmsh.model.getBoundary([(3, 1)], oriented=False):
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(dim, tag)
        if x1 - x0 < 1e-6:
            ends.append(tag)
        elif z0 > T - 1e-6:
            top.append(tag)
    gmsh.model.addPhysicalGroup(2, ends, 7)
    gmsh.model.setPhysicalName(2, 7, "clamped_ends")
    gmsh.model.addPhysicalGroup(2, top, 8)
    gmsh.model.setPhysicalName(2, 8, "top_face")
    gmsh.model.addPhysicalGroup(3, [1], 9)
    gmsh.model.setPhysicalName(3, 9, "solid")
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.02)
    gmsh.model.mesh.generate(3)
    gmsh.write(str(path))
    gmsh.finalize()
    return path


TOML = """
[[structures]]
name = "plate"
file = "plate.msh"
tags = { support = "clamped_ends", contact = "top_face" }
material = "steel"
degree = 1
scheme = "static"
supports = ["support"]
loads = [{ tag = "contact", traction = [0.0, 0.0, -1000.0] }]
contact = { tags = ["contact"], n_sub = 1 }
"""


def _structure(**over):
    table = tomllib.loads(TOML)["structures"][0]
    table.update(over)
    return load(Structure, table, "structures[0]")


def test_mapped_user_msh_builds_and_carries_its_load(msh):
    st = _structure()
    st.check(base_dir=msh.parent)
    cs = st.build(comm=MPI.COMM_WORLD, dt_dem=1e-5, base_dir=msh.parent)
    assert cs.mesh.tags["support"] == 7 and cs.mesh.tags["contact"] == 8
    assert cs.mesh.volumes == {"solid": 9}
    cs.elasticity.solve()
    # the clamped ends carry the pressure on the top face
    assert cs.elasticity.reaction("support") == pytest.approx([0, 0, 1000.0 * L * W], rel=1e-9,
                                                              abs=1e-9)
    assert cs.interface.surface.area() == pytest.approx(L * W, rel=1e-12)
    # the file's own names work as well and give the same structure
    st2 = _structure(tags={}, supports=["clamped_ends"],
                     loads=[dict(tag="top_face", traction=[0.0, 0.0, -1000.0])],
                     contact=dict(tags=["top_face"], n_sub=1))
    cs2 = st2.build(comm=MPI.COMM_WORLD, dt_dem=1e-5, base_dir=msh.parent)
    cs2.elasticity.solve()
    assert np.array_equal(cs2.elasticity.u.x.array, cs.elasticity.u.x.array)


def _one_line_error(fn, match):
    with pytest.raises(GsiInputError, match=match) as exc:
        fn()
    assert "\n" not in str(exc.value)
    return str(exc.value)


def test_unmapped_tag_is_a_one_line_error_listing_the_groups(msh):
    st = _structure(tags={})
    msg = _one_line_error(lambda: st.check(base_dir=msh.parent),
                          r"^structures\[0\]\.contact\.tags\[0\] = 'contact': not a surface "
                          r"group of plate\.msh")
    assert "clamped_ends, top_face" in msg
    # the build (collective) says the same
    _one_line_error(lambda: st.build(comm=MPI.COMM_WORLD, dt_dem=1e-5, base_dir=msh.parent),
                    r"^structures\[0\]\.contact\.tags\[0\] = 'contact'")


def test_missing_group_in_the_mapping_is_a_one_line_error(msh):
    st = _structure(tags=dict(support="clamped", contact="top_face"))
    msg = _one_line_error(lambda: st.check(base_dir=msh.parent),
                          r"^structures\[0\]\.tags\.support = 'clamped': no physical surface "
                          r"group of that name in plate\.msh; its groups: ")
    assert msg.endswith("clamped_ends, top_face")


def test_missing_file_and_geometry_of_a_msh_are_input_errors(msh, tmp_path):
    _one_line_error(lambda: _structure().check(base_dir=tmp_path),
                    r"^structures\[0\]\.file = 'plate\.msh': no such file")
    _one_line_error(lambda: _structure(geometry={"length": 1.0}).check(base_dir=msh.parent),
                    r"geometry = \{\.\.\.\}: parameters apply to a \.geo script only")
    _one_line_error(lambda: _structure(mesh="membrane"), r"give exactly one")


def test_unknown_geo_parameter_names_the_script_constants():
    from gsi import meshes
    st = _structure(file="belt.geo", geometry={"lenght": 1.0})
    msg = _one_line_error(lambda: st.check(base_dir=meshes.DIR),
                          r"^structures\[0\]\.geometry\.lenght = 1\.0: not a DefineConstant")
    assert "h, layers, length, thickness, width" in msg


def test_wall_material_derived_or_checked_for_heat():
    st = _structure()
    name, m = st.dem_wall_material({"ore": Material(E=1e7, nu=0.3, rho=3000.0)})
    assert name == "plate_wall"
    assert (m.E, m.nu, m.rho, m.k, m.cp, m.e, m.mu, m.mu_r) == (210e9, 0.3, 7850.0, 53.3, 440.0,
                                                                0.5, 0.5, 0.0)
    hot = _structure(contact=dict(tags=["contact"], mode="both", wall_material="steel",
                                  n_sub=1))
    bad = {"steel": Material(E=210e9, nu=0.3, rho=7850.0, k=50.0)}
    _one_line_error(lambda: hot.dem_wall_material(bad),
                    r"^materials\.steel\.k = 50\.0: must equal structures\[0\]\.k")
    good = {"steel": Material(E=210e9, nu=0.3, rho=7850.0, k=53.3)}
    assert hot.dem_wall_material(good) == ("steel", good["steel"])
    _one_line_error(lambda: hot.dem_wall_material({}),
                    r"^structures\[0\]\.contact\.wall_material = 'steel': not a")


def test_thermal_table_needs_heat_contact():
    _one_line_error(lambda: _structure(thermal={"T_ref": 300.0}),
                    r"^structures\[0\]\.contact\.mode = 'mechanical': the \[thermal\] table")
