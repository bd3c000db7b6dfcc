"""The [structure], [coupling] and [hopper] tables: one-line errors naming key, value, fix."""
import copy
import pathlib
import tomllib

import pytest

from gsi.config.case import case_from_table, load_case
from gsi.errors import GsiInputError

ROOT = pathlib.Path(__file__).resolve().parents[2]
DEMO = ROOT / "demos" / "hopper_membrane.toml"


@pytest.fixture
def table():
    with DEMO.open("rb") as fh:
        return tomllib.load(fh)


def _set(table, dotted, value):
    t = copy.deepcopy(table)
    node = t
    keys = dotted.split(".")
    for k in keys[:-1]:
        node = node[k]
    node[keys[-1]] = value
    return t


def test_shipped_demo_case_is_valid():
    case = load_case(DEMO)
    assert case.case.kind == "hopper_membrane"
    assert case.structure.degree == 2 and case.structure.supports == ["support"]
    assert case.structure.material_spec() == "rubber"
    assert case.structure.mesh_params()["shape"] == "circle"
    assert case.coupling.n_sub is None and case.coupling.steps_per_period == 20.0
    assert case.hopper.outlet_radius < case.hopper.top_radius


BAD = [
    ("structure.degree", 3, "structure.degree = 3: must be one of 1, 2"),
    ("structure.scheme", "euler",
     "structure.scheme = 'euler': must be one of 'static', 'newmark', 'generalized_alpha'"),
    ("structure.mesh", "sphere",
     "structure.mesh = 'sphere': must be one of box, drum, hopper, membrane, silo"),
    ("structure.rayleigh", [-1.0, 0.0], "structure.rayleigh = [-1.0, 0.0]: must be >= 0 (1/s, s)"),
    ("structure.geometry", {"radius": 0.3, "thikness": 0.01},
     "structure.geometry.thikness = 0.01: not a parameter of the 'membrane' builder; allowed: "
     "shape, length_x, length_y, radius, thickness, h, n_thickness"),
    ("structure.supports", [], "structure.supports = []: give at least one clamped surface tag"),
    ("coupling.n_sub", 2.5, "coupling.n_sub = 2.5: must be an integer"),
    ("coupling.n_sub", 0, "coupling.n_sub = 0: must be > 0"),
    ("coupling.relaxation", 0.0, "coupling.relaxation = 0.0: must be in (0.0, 1.0] (-)"),
    ("coupling.wall_material", "glass",
     "coupling.wall_material = 'glass': not a [materials.X] table; defined: rubber, softwood, steel"),
    ("hopper.outlet_radius", 0.3, "hopper.outlet_radius = 0.3: must be < top_radius = 0.24 (m)"),
    ("hopper.gate_speed", 0, "hopper.gate_speed = 0: must be > 0 (m/s)"),
]


@pytest.mark.parametrize("key, value, message", BAD, ids=[b[0] for b in BAD])
def test_bad_value_gives_one_line_message(table, key, value, message):
    with pytest.raises(GsiInputError) as err:
        case_from_table(_set(table, key, value))
    # the builder's parameter list may grow: compare up to the end of the expected text
    assert str(err.value).startswith(message)
    assert "\n" not in str(err.value)


def test_misspelt_coupling_key_suggests_the_right_one(table):
    t = copy.deepcopy(table)
    t["coupling"]["stepsperperiod"] = 20
    with pytest.raises(GsiInputError, match=r"coupling.stepsperperiod: unknown key; did you "
                                            r"mean 'steps_per_period'\?"):
        case_from_table(t)


def test_hopper_membrane_case_needs_its_tables(table):
    from gsi.drivers import check_case
    t = copy.deepcopy(table)
    del t["hopper"]
    with pytest.raises(GsiInputError, match=r"^hopper: missing; a hopper_membrane case needs "
                                            r"a \[hopper\] table$"):
        check_case(case_from_table(t))
