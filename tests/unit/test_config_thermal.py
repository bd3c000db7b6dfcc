"""The thermal_silo case file: the shipped case is valid, bad input gives one line."""
import copy
import functools
import pathlib
import tomllib

import pytest

from gsi.config.case import case_from_table, load_case
from gsi.drivers import check_case
from gsi.errors import GsiInputError

ROOT = pathlib.Path(__file__).resolve().parents[2]
CASE = ROOT / "demos" / "thermal_silo.toml"


@pytest.fixture
def table():
    with CASE.open("rb") as fh:
        return tomllib.load(fh)


DELETE = object()


def _set(table, dotted, value):
    """A deep copy of ``table`` with the key path ``a.b.c`` set to ``value`` (or deleted)."""
    *parents, last = dotted.split(".")
    t = copy.deepcopy(table)
    node = functools.reduce(lambda d, k: d.setdefault(k, {}), parents, t)
    node.pop(last) if value is DELETE else node.__setitem__(last, value)
    return t


def test_shipped_case_is_valid():
    case = load_case(CASE)
    assert case.case.kind == "thermal_silo"
    assert case.thermal.time_scale == 200.0 and case.thermal.cooled == ["outer"]
    assert case.structure.mesh == "silo" and case.coupling.n_sub == 50
    check_case(case)


def test_defaults():
    t = {"run": {"duration": 1.0, "output_interval": 0.1},
         "dem": {"domain_lo": [0, 0, 0], "domain_hi": [1, 1, 1]},
         "materials": {"a": {"E": 1e7, "nu": 0.3, "rho": 1000.0}}, "thermal": {}}
    th = case_from_table(t).thermal
    assert (th.T_ref, th.T_ambient, th.h, th.theta, th.time_scale) == (293.15, 293.15, 10.0,
                                                                       1.0, 1.0)
    assert th.T_wall_initial is None and th.cooled == ["outer"]


SCHEMA_BAD = [
    ("thermal.h", -5.0, "thermal.h = -5.0: must be >= 0 (W/(m^2 K))"),
    ("thermal.theta", 0.3, "thermal.theta = 0.3: must be in [0.5, 1.0] (-)"),
    ("thermal.time_scale", 0.0, "thermal.time_scale = 0.0: must be > 0 (-)"),
    ("thermal.T_ref", -1.0, "thermal.T_ref = -1.0: must be > 0 (K)"),
    ("thermal.cooled", "outer", "thermal.cooled = 'outer': must be a list"),
    ("case.kind", "thermal", "case.kind = 'thermal': must be one of 'pour', "),
]


@pytest.mark.parametrize("key,value,message", SCHEMA_BAD)
def test_schema_errors_name_the_key(table, key, value, message):
    with pytest.raises(GsiInputError) as err:
        case_from_table(_set(table, key, value))
    assert str(err.value).startswith(message)
    assert "\n" not in str(err.value)


def test_unknown_thermal_key_suggests_the_right_one(table):
    t = _set(table, "thermal.hh", 3.0)
    with pytest.raises(GsiInputError, match=r"^thermal.hh: unknown key; did you mean 'h'\?"):
        case_from_table(t)


DRIVER_BAD = [
    ("materials.steel.k", 1.0, "materials.steel.k = 1.0: must equal the structure's "
                               "conductivity 53.3 (W/(m K))"),
    ("dem.heat", "none", "dem.heat = 'none': a thermal_silo case needs a particle conduction"),
    ("coupling.n_sub", DELETE, "coupling.n_sub: missing; a thermal_silo case needs"),
    ("thermal", DELETE, "thermal: missing; a thermal_silo case needs a [thermal] table"),
]


@pytest.mark.parametrize("key,value,message", DRIVER_BAD)
def test_driver_checks_name_the_key(table, key, value, message):
    case = case_from_table(_set(table, key, value))
    with pytest.raises(GsiInputError) as err:
        check_case(case)
    assert str(err.value).startswith(message)


def test_gsi_check_accepts_the_case(capsys):
    from gsi.cli import main
    assert main(["check", str(CASE)]) == 0
    assert "ok (thermal_silo case 'thermal_silo')" in capsys.readouterr().out
