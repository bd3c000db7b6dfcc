"""Case files: every bad input gives one line naming the key, the value and the fix; the
TOML is a thin layer over the Python parts; ``gsi check`` finds what it can before a run."""
import copy
import pathlib
import subprocess
import sys
import tomllib

import pytest

from gsi.case import (Case, CaseInfo, Dem, Material, Output, ParticleSource, Region, Run, Size,
                      Wall, case_from_table, case_to_table, load_case, merge_tables)
from gsi.case.case import validated
from gsi.config.schema import describe
from gsi.errors import GsiInputError

ROOT = pathlib.Path(__file__).resolve().parents[2]
POUR = ROOT / "demos" / "pour.toml"
DEMO_CASES = sorted(ROOT.glob("demos/*.toml"))


@pytest.fixture
def table():
    with POUR.open("rb") as fh:
        return tomllib.load(fh)


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
    ("particles.0.count", 2.5, "particles[0].count = 2.5: must be an integer"),
    ("particles.0.material", "steel",
     "particles[0].material = 'steel': not a [materials.X] table; defined: glass"),
    ("output.interval", 5.0, "output.interval = 5.0: must be <= run.duration = 0.6 (s)"),
    ("materials.glass.e", 1.5, "materials.glass.e = 1.5: must be in (0.0, 1.0] (-)"),
    ("run.duration", _DELETE, "run.duration: missing; give simulated time (s)"),
    ("dem.rolling", "yes", "dem.rolling = 'yes': must be true or false"),
    ("case.name", "../x",
     "case.name = '../x': use letters, digits, '_', '-' or '.' only (it becomes a directory "
     "name)"),
]


@pytest.mark.parametrize("key,value,message", BAD, ids=[b[0] for b in BAD])
def test_bad_input_message(table, key, value, message):
    with pytest.raises(GsiInputError) as err:
        case_from_table(_set(table, key, value))
    text = str(err.value)
    assert "\n" not in text
    assert text == message


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


def test_duplicate_names_are_refused(table):
    bad = copy.deepcopy(table)
    bad["walls"].append(dict(bad["walls"][0]))
    with pytest.raises(GsiInputError, match=r"^walls\[1\]\.name = 'box': already used by walls\[0\]"):
        case_from_table(bad)


@pytest.mark.parametrize("path", DEMO_CASES, ids=[p.stem for p in DEMO_CASES])
def test_shipped_cases_round_trip_through_the_api(path):
    """TOML -> objects -> table -> objects gives the same case (the TOML is a thin layer)."""
    case = load_case(path)
    again = case_from_table(case_to_table(case), base_dir=case.base_dir)
    assert case_to_table(again) == case_to_table(case)
    assert case.check() > 0                          # gsi check passes on every shipped case


def test_python_parts_are_checked_like_toml():
    """A case built in Python goes through the same schema as its TOML twin."""
    case = Case(case=CaseInfo(name="box"), run=Run(duration=0.1),
                dem=Dem(domain_lo=(0, 0, 0), domain_hi=(0.1, 0.1, 0.2)),
                materials={"glass": Material(E=5e6, nu=0.3, rho=2500)},
                particles=[ParticleSource(material="glass", count=10,
                                          size=Size(radius=-2e-3),
                                          region=Region(kind="box", lo=(0, 0, 0.05),
                                                        hi=(0.1, 0.1, 0.2)))],
                walls=[Wall(kind="box", material="glass", lo=(0, 0, 0), hi=(0.1, 0.1, 0.2))],
                output=Output(interval=0.05))
    with pytest.raises(GsiInputError, match=r"^particles\[0\]\.size\.radius = -0\.002: must be > 0"):
        validated(case)


def test_quick_overrides_merge_arrays_of_tables_by_position():
    base = {"run": {"duration": 2.0}, "particles": [{"count": 10, "material": "a"},
                                                   {"count": 5}]}
    out = merge_tables(base, {"run": {"duration": 0.5}, "particles": [{"count": 2}]})
    assert out == {"run": {"duration": 0.5}, "particles": [{"count": 2, "material": "a"},
                                                          {"count": 5}]}
    case = load_case(ROOT / "demos" / "hopper_membrane.toml")
    q = case.quick_variant()
    assert q.particles[0].count == 400 and case.particles[0].count == 2000
    assert [e.t for e in q.walls[1].motion.events] == [0.45, 0.55]
    assert q.run.duration == 1.5 and q.structures[0].name == "membrane"


def test_quick_longer_than_the_run_is_refused(table):
    bad = copy.deepcopy(table)
    bad["quick"] = {"run": {"duration": 5.0}}
    case = case_from_table(bad)
    with pytest.raises(GsiInputError, match=r"^quick\.run\.duration = 5\.0: longer than run\.duration"):
        case.check()


def test_keys_list_every_table_and_unit():
    lines = describe(Case)
    text = "\n".join(lines)
    for key in ("run.duration (required) [s]", "materials.NAME.E (required) [Pa]",
                "particles[].region.axis", "walls[].motion.events[].t (required) [s]",
                "structures[].contact.mode", "structures[].thermal.convection[].h",
                "monitors[].kind (required)", "pairs[].materials (required)",
                "output.interval (required) [s]"):
        assert key in text, key


def _gsi(*args):
    return subprocess.run([sys.executable, "-m", "gsi.cli", *args], capture_output=True,
                          text=True)


def test_cli_prints_one_line_and_exits_2(tmp_path):
    case = tmp_path / "bad.toml"
    case.write_text(POUR.read_text().replace("min = 0.0018", "min = -0.0018"))
    res = _gsi("check", str(case))
    assert res.returncode == 2 and res.stdout == ""
    assert res.stderr == "error: particles[0].size.min = -0.0018: must be > 0 (m)\n"

    broken = tmp_path / "broken.toml"
    broken.write_text("[run\nduration = 1")
    res = _gsi("check", str(broken))
    assert res.returncode == 2 and res.stderr.startswith("error: ") and "not valid TOML" in res.stderr
    assert res.stderr.count("\n") == 1

    latin = tmp_path / "latin.toml"
    latin.write_bytes(POUR.read_bytes().replace(b"Glass beads", b"Gl\xe4ss beads"))
    res = _gsi("check", str(latin))
    assert res.returncode == 2 and "not UTF-8" in res.stderr and res.stderr.count("\n") == 1

    res = _gsi("run", str(tmp_path / "none.toml"))
    assert res.returncode == 2 and "no such case file" in res.stderr


def test_cli_refuses_bad_output_directories(tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("x")
    for out, words in ((str(afile), "a file of that name exists"),
                       (str(afile / "sub"), "a parent is a file"),
                       ("", "give an output directory")):
        res = _gsi("run", str(POUR), "--quick", "--out", out)
        assert res.returncode == 2, out
        assert words in res.stderr and res.stderr.count("\n") == 1, res.stderr


def test_cli_version_info_and_keys():
    res = _gsi("--version")
    assert res.returncode == 0 and res.stdout.startswith("gsi 0.")
    res = _gsi("info")
    assert res.returncode == 0
    for name in ("dolfinx", "numba", "petsc4py", "gmsh", "pyvista", "MPI", "threads"):
        assert name in res.stdout
    assert "0.5.2" in res.stdout  # the dolfinx this was built and tested with
    res = _gsi("check", "--keys")
    assert res.returncode == 0 and res.stdout.splitlines() == describe(Case)


def test_time_step_rule(tmp_path):
    base = POUR.read_text()
    case = tmp_path / "dt.toml"
    case.write_text(base.replace("seed = 7", "seed = 7\ndt = 0.01"))
    res = _gsi("check", str(case))
    assert res.returncode == 2
    assert res.stderr.startswith("error: run.dt = 0.01: above 1 x the Rayleigh time t_R = "
                                 "0.00022 s; use run.dt <= 4.41e-05")
    assert "dem.force_dt = true" in res.stderr and res.stderr.count("\n") == 1
    # between 0.3 t_R and t_R: accepted with a warning that gives the safe step
    case.write_text(base.replace("seed = 7", "seed = 7\ndt = 0.0001"))
    res = _gsi("check", str(case))
    assert res.returncode == 0 and "above 0.3 x the Rayleigh time" in res.stderr
    assert "run.dt <= 4.41e-05 s is safe" in res.stderr


# ---------------------------------------------------------------------- issue 11: bad inputs
def _pour_case(table, **dem):
    table = copy.deepcopy(table)
    table["dem"].update(dem)
    return case_from_table(table, base_dir=POUR.parent)


def test_one_time_step_rule_in_bands(table):
    """dt <= 0.3 t_R silent; (0.3, 0.5] t_R a warning; above 0.5 t_R refused unless
    force_dt, which runs with a warning saying the results are not to be trusted."""
    import warnings
    t_R = min(_pour_case(table).rayleigh_times())
    for frac, outcome in ((0.25, None), (0.4, "coarsely"), (0.7, "above 0.5 x"),
                          (1.5, "above 1 x")):
        t = copy.deepcopy(table)
        t["run"]["dt"] = frac * t_R
        case = _pour_case(t)
        with warnings.catch_warnings(record=True) as got:
            warnings.simplefilter("always")
            if outcome is not None and outcome.startswith("above"):
                with pytest.raises(GsiInputError, match=f"^run.dt = .*: {outcome} the Rayleigh "
                                   r"time .*dem.force_dt = true"):
                    case.time_step()
                forced = _pour_case(t, force_dt=True)
                assert forced.time_step() == pytest.approx(frac * t_R)
                assert any(str(w.message).startswith("dem.force_dt = true: run.dt")
                           and "not to be trusted" in str(w.message) for w in got)
                continue
            assert case.time_step() == pytest.approx(frac * t_R)
        assert [str(w.message) for w in got if outcome is None] == []
        if outcome:
            assert any(outcome in str(w.message) for w in got)


def test_shipped_demos_pass_every_check_without_a_warning():
    import warnings
    for path in DEMO_CASES:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            load_case(path).check()


def test_first_overlap_finds_the_first_pair():
    from gsi.case.sources import first_overlap
    import numpy as np
    x = np.array([[0.0, 0, 0], [1.0, 0, 0], [0.0196, 0, 0], [1.0198, 0, 0]])
    r = np.full(4, 0.01)
    assert first_overlap(x, r, 0.05) is None                 # 0.04 r and 0.02 r overlaps
    a, b, f = first_overlap(x, r, 0.01)
    assert (a, b) == (0, 2) and f == pytest.approx(0.04)
    assert first_overlap(x[:2], r[:2], 0.05, other_x=x[2:] - [0.01, 0, 0],
                         other_r=r[2:])[:2] == (0, 0)
    assert first_overlap(x[:1], r[:1], 0.05) is None


def test_force_dt_turns_the_overlap_refusal_into_a_warning(table, tmp_path):
    import warnings
    (tmp_path / "pile.csv").write_text("x,y,z,radius\n0.03,0.03,0.05,0.002\n"
                                       "0.0304,0.03,0.05,0.002\n")
    t = copy.deepcopy(table)
    t["particles"] = [{"material": "glass", "fill": "file", "file": "pile.csv"}]
    t.pop("quick")
    case = case_from_table(t, base_dir=tmp_path)
    with pytest.raises(GsiInputError, match=r"^particles\[0\].file = 'pile.csv': rows 0 and 1 "
                       r"overlap by 1.8 x"):
        case.check()
    t["dem"]["force_dt"] = True
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        case_from_table(t, base_dir=tmp_path).check()
    assert any("rows 0 and 1 overlap" in str(w.message) for w in got)


def test_skin_softness_and_stream_rate_limits(table):
    """The limits sit where the demos pass: a skin of 4 radii passes, 10 m does not; E at
    the limit where the impact overlap reaches half a radius."""
    t = copy.deepcopy(table)
    t["dem"]["skin"] = 4 * 0.0022
    case_from_table(t, base_dir=POUR.parent).check()
    t["dem"]["skin"] = 4.01 * 0.0022
    with pytest.raises(GsiInputError, match=r"^dem.skin = "):
        case_from_table(t, base_dir=POUR.parent).check()
    t = copy.deepcopy(table)
    t["materials"]["glass"]["E"] = 1.0e5
    with pytest.raises(GsiInputError, match=r"^materials.glass.E = 100000: too soft"):
        case_from_table(t, base_dir=POUR.parent).check()
    t["materials"]["glass"]["E"] = 1.0e6
    case_from_table(t, base_dir=POUR.parent).check()


def test_cli_warnings_are_one_line(tmp_path):
    case = tmp_path / "dt.toml"
    case.write_text(POUR.read_text().replace("seed = 7", "seed = 7\ndt = 0.00009"))
    res = _gsi("check", str(case))
    assert res.returncode == 0
    assert res.stderr.startswith("warning: run.dt = 9e-05 s is above 0.3 x the Rayleigh")
    assert res.stderr.count("\n") == 1
