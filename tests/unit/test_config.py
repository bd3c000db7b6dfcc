"""Case files: every bad input gives one line naming the key, the value and the fix."""
import copy
import pathlib
import subprocess
import sys
import tomllib

import pytest

from gsi.config.case import case_from_table, load_case
from gsi.errors import GsiInputError

ROOT = pathlib.Path(__file__).resolve().parents[2]
POUR = ROOT / "demos" / "pour.toml"


@pytest.fixture
def table():
    with POUR.open("rb") as fh:
        return tomllib.load(fh)


def test_shipped_case_is_valid():
    case = load_case(POUR)
    assert case.case.kind == "pour"
    assert case.particles[0].size.kind == "uniform"
    assert case.dem.gravity == (0.0, 0.0, -9.81)


def _set(table, dotted, value):
    t = copy.deepcopy(table)
    node = t
    keys = dotted.split(".")
    for k in keys[:-1]:
        node = node[int(k)] if k.isdigit() else node[k]
    if value is _DELETE:
        del node[keys[-1]]
    else:
        node[keys[-1]] = value
    return t


_DELETE = object()

BAD = [
    # (key to change, new value, the whole expected message)
    ("particles.0.size.min", -0.001, "particles[0].size.min = -0.001: must be > 0 (m)"),
    ("materials.glass.nu", 0.7, "materials.glass.nu = 0.7: must be in (-1.0, 0.5) (-)"),
    ("materials.glass.E", "5e6", "materials.glass.E = '5e6': must be a number (Pa)"),
    ("dem.contact", "hertzian", "dem.contact = 'hertzian': must be one of 'hertz', 'linear'"),
    ("run.duration", 0, "run.duration = 0: must be > 0 (s)"),
    ("dem.gravity", [0.0, -9.81], "dem.gravity = [0.0, -9.81]: must have 3 components (m/s^2)"),
    ("particles.0.count", 2.5, "particles.0.count = 2.5: must be an integer"),
    ("particles.0.material", "steel",
     "particles[0].material = 'steel': not a [materials.X] table; defined: glass"),
    ("run.output_interval", 5.0,
     "run.output_interval = 5.0: must be <= run.duration = 0.6 (s)"),
    ("particles.0.size.max", 0.001,
     "particles[0].size.max = 0.001: must be >= particles[0].size.min = 0.0018 (m)"),
    ("materials.glass.e", 1.5, "materials.glass.e = 1.5: must be in (0.0, 1.0] (-)"),
    ("run.duration", _DELETE, "run.duration: missing; give simulated time (s)"),
    ("dem.rolling", "yes", "dem.rolling = 'yes': must be true or false"),
]


@pytest.mark.parametrize("key,value,message", BAD, ids=[b[0] for b in BAD])
def test_bad_input_message(table, key, value, message):
    bad = _set(table, key, value)
    with pytest.raises(GsiInputError) as err:
        case_from_table(bad)
    text = str(err.value)
    assert "\n" not in text
    # list indices are shown as [i]: normalise the expected text of the count case
    assert text == message.replace("particles.0.count", "particles[0].count")


def test_unknown_key_suggests(table):
    bad = copy.deepcopy(table)
    bad["dem"]["contcat"] = "hertz"
    with pytest.raises(GsiInputError, match=r"^dem\.contcat: unknown key; did you mean 'contact'\?"):
        case_from_table(bad)
    bad = copy.deepcopy(table)
    bad["materials"]["glass"]["youngs"] = 1.0
    with pytest.raises(GsiInputError, match=r"^materials\.glass\.youngs: unknown key; \(allowed: E, nu"):
        case_from_table(bad)
    bad = copy.deepcopy(table)
    bad["partciles"] = bad.pop("particles")
    with pytest.raises(GsiInputError, match="did you mean 'particles'"):
        case_from_table(bad)


def test_missing_mesh_file(table, tmp_path):
    bad = copy.deepcopy(table)
    bad["walls"].append({"kind": "mesh", "material": "glass", "file": "nope.stl"})
    with pytest.raises(GsiInputError, match=r"^walls\[1\]\.file = 'nope.stl': no such file"):
        case_from_table(bad, base_dir=tmp_path)


def test_cli_prints_one_line_and_exits_2(tmp_path):
    text = POUR.read_text().replace("min = 0.0018", "min = -0.0018")
    case = tmp_path / "bad.toml"
    case.write_text(text)
    res = subprocess.run([sys.executable, "-m", "gsi.cli", "check", str(case)],
                         capture_output=True, text=True)
    assert res.returncode == 2
    assert res.stdout == ""
    assert res.stderr == "error: particles[0].size.min = -0.0018: must be > 0 (m)\n"

    broken = tmp_path / "broken.toml"
    broken.write_text("[run\nduration = 1")
    res = subprocess.run([sys.executable, "-m", "gsi.cli", "check", str(broken)],
                         capture_output=True, text=True)
    assert res.returncode == 2 and res.stderr.startswith("error: ") and "not valid TOML" in res.stderr
    assert res.stderr.count("\n") == 1

    res = subprocess.run([sys.executable, "-m", "gsi.cli", "run", str(tmp_path / "none.toml")],
                         capture_output=True, text=True)
    assert res.returncode == 2 and "no such case file" in res.stderr


def test_cli_version_and_info():
    res = subprocess.run([sys.executable, "-m", "gsi.cli", "--version"], capture_output=True, text=True)
    assert res.returncode == 0 and res.stdout.startswith("gsi 0.")
    res = subprocess.run([sys.executable, "-m", "gsi.cli", "info"], capture_output=True, text=True)
    assert res.returncode == 0
    for name in ("dolfinx", "numba", "petsc4py", "gmsh", "pyvista", "MPI", "threads"):
        assert name in res.stdout
    assert "0.5.2" in res.stdout  # the dolfinx this was built and tested with


def test_time_step_above_rayleigh_time_is_refused(tmp_path):
    base = POUR.read_text()
    case = tmp_path / "dt.toml"
    case.write_text(base.replace("seed = 7", "seed = 7\ndt = 0.01"))
    res = subprocess.run([sys.executable, "-m", "gsi.cli", "check", str(case)],
                         capture_output=True, text=True)
    assert res.returncode == 2
    assert res.stderr.startswith("error: run.dt = 0.01: must be <= the Rayleigh time 0.00022 s")
    assert "dem.force_dt = true" in res.stderr and res.stderr.count("\n") == 1
    # between 0.3 t_R and t_R: accepted with a warning
    case.write_text(base.replace("seed = 7", "seed = 7\ndt = 0.0001"))
    res = subprocess.run([sys.executable, "-m", "gsi.cli", "check", str(case)],
                         capture_output=True, text=True)
    assert res.returncode == 0 and "0.3 x the Rayleigh time" in res.stderr
