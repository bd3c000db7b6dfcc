"""What a careful but hurried user types wrong: values in another unit (sane ranges per
quantity in the schema), names that are paths, duplicate pairs and unused monitor keys,
byte-order marks and short CSV rows, the heat bound known before the run, size estimates,
and the case fingerprint that ``gsi run --resume`` compares."""
import copy
import dataclasses
import pathlib
import tomllib
import typing
import warnings

import pytest

from gsi import checkpoint as ck
from gsi.case import Case, case_from_table, load_case
from gsi.case.fingerprint import changes, check_resume, fingerprint
from gsi.case.sizes import MAX_QUICK_STEPS, check_sizes, estimate
from gsi.cli import main
from gsi.config.schema import SANE
from gsi.errors import GsiInputError

ROOT = pathlib.Path(__file__).resolve().parents[3]
POUR = ROOT / "demos" / "pour.toml"
SILO = ROOT / "demos" / "thermal_silo.toml"


def _table(path=POUR):
    with path.open("rb") as fh:
        return tomllib.load(fh)


def _with(table, edit):
    t = copy.deepcopy(table)
    edit(t)
    return t


def _error(table) -> str:
    with pytest.raises(GsiInputError) as exc:
        case = case_from_table(table, base_dir=ROOT / "demos")
        case.check()
    msg = str(exc.value)
    assert "\n" not in msg
    return msg


# ---------------------------------------------------------------- sane ranges
@pytest.mark.parametrize("path,value,words", [
    ("materials.glass.E", 200.0, "did you give GPa? (200 GPa = 2e+11 Pa)"),
    ("materials.glass.E", 5.0, "outside 10000 to 1e+13 Pa"),
    ("materials.glass.E", 5e15, "outside 10000 to 1e+13 Pa for a Young's modulus"),
    ("materials.glass.rho", 2.5, "did you give g/cm^3? (2.5 g/cm^3 = 2500 kg/m^3)"),
    ("materials.glass.cp", 0.84, "did you give kJ/(kg K)? (0.84 kJ/(kg K) = 840 J/(kg K))"),
    ("materials.glass.k", 1e6, "outside 0.001 to 10000 W/(m K)"),
    ("particles.0.temperature", 8e4, "outside 1 to 5000 K for a temperature"),
])
def test_a_value_in_another_unit_is_refused_naming_key_and_unit(path, value, words):
    def edit(t):
        node = t
        keys = path.split(".")
        for k in keys[:-1]:
            node = node[int(k)] if k.isdigit() else node[k]
        node[keys[-1]] = value
    msg = _error(_with(_table(), edit))
    shown = path.replace(".0.", "[0].")
    assert msg.startswith(f"{shown} = "), msg
    assert words in msg


def test_a_temperature_below_200_K_warns_about_celsius():
    t = _table(SILO)
    t["structures"][0]["thermal"]["convection"][0]["T_ambient"] = 20.0
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        case_from_table(t, base_dir=ROOT / "demos")
    said = [str(w.message) for w in got]
    assert any(s.startswith("structures[0].thermal.convection[0].T_ambient = 20.0: below 200 K;"
                            " did you give \u00b0C? (20 \u00b0C = 293.15 K)") for s in said), said


def _scalar_fields(cls, seen=None):
    """Every (class, field) of the case schema, nested tables included."""
    seen = set() if seen is None else seen
    if cls in seen:
        return
    seen.add(cls)
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        if not f.init:
            continue
        yield cls, f
        for arg in [hints[f.name], *typing.get_args(hints[f.name])]:
            for inner in [arg, *typing.get_args(arg)]:
                if dataclasses.is_dataclass(inner):
                    yield from _scalar_fields(inner, seen)


def test_every_scalar_key_of_a_physical_unit_has_its_sane_range():
    found = {u: 0 for u in SANE}
    for cls, f in _scalar_fields(Case):
        unit = f.metadata.get("unit")
        if unit in SANE and f.metadata.get("length") is None:
            # a servo's target stress is a stress, not a modulus: any positive value
            exempt = (cls.__name__, f.name) in {("Halves", "below"), ("Halves", "above"),
                                                ("Motion", "stress")}
            assert (f.metadata.get("sane") is SANE[unit]) != exempt, (cls.__name__, f.name)
            found[unit] += 1
    assert found["Pa"] >= 2 and found["kg/m^3"] >= 2 and found["K"] >= 8, found


def test_shipped_demos_are_inside_every_sane_range():
    for path in sorted((ROOT / "demos").rglob("*.toml")):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            load_case(path)


# ---------------------------------------------------------------- names
HOSTILE = ["../../escaped", "", "a/b", "/tmp/abs", "..", ".hidden", "a\\b", "x" * 101]
NAMED = {"case": lambda t, v: t["case"].__setitem__("name", v),
         "particles[0]": lambda t, v: t["particles"][0].__setitem__("name", v),
         "walls[0]": lambda t, v: (t["walls"][0].__setitem__("name", v),
                                   t["monitors"][0].__setitem__("target", v)),
         "monitors[0]": lambda t, v: t["monitors"][0].__setitem__("name", v),
         "monitors[1]": lambda t, v: t["monitors"][1].__setitem__("name", v)}


@pytest.mark.parametrize("name", HOSTILE)
@pytest.mark.parametrize("where", list(NAMED))
def test_every_output_name_is_checked_like_the_case_name(where, name):
    msg = _error(_with(_table(), lambda t: NAMED[where](t, name)))
    assert msg.startswith(f"{where}.name = {name!r}:"), msg


@pytest.mark.parametrize("name", HOSTILE)
def test_a_structure_name_that_is_a_path_is_refused(name):
    t = _table(SILO)
    t["structures"][0]["name"] = name
    t["monitors"][1]["target"] = name
    assert _error(t).startswith(f"structures[0].name = {name!r}:")


def test_gsi_run_with_a_hostile_name_writes_nothing_anywhere(tmp_path, capsys):
    text = POUR.read_text().replace('name = "bed"', 'name = "../../escaped"')
    work = tmp_path / "a" / "b"
    work.mkdir(parents=True)
    (work / "case.toml").write_text(text)
    rc = main(["run", str(work / "case.toml"), "--out", str(work / "out"), "--no-pictures"])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("error: monitors[1].name = '../../escaped'")
    assert sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*")) == \
        ["a", "a/b", "a/b/case.toml"]


def test_a_wall_and_a_structure_may_not_share_a_name():
    t = _table(SILO)
    t["walls"] = [dict(name="bin", kind="plane", material="steel", point=[0.0, 0.0, -0.02],
                       normal=[0.0, 0.0, 1.0])]
    assert _error(t).startswith("structures[0].name = 'bin': already used by walls[0].name")


# ---------------------------------------------------------------- duplicates, unused keys
def test_a_pair_given_twice_in_either_order_is_refused():
    t = _table()
    t["materials"]["steel"] = dict(E=2e11, nu=0.3, rho=7800.0)
    t["pairs"] = [dict(materials=["glass", "steel"], mu=0.3),
                  dict(materials=["steel", "glass"], mu=0.6)]
    assert _error(t).startswith("pairs[1].materials = ['steel', 'glass']: the same pair as "
                                "pairs[0]")


@pytest.mark.parametrize("key,value", [("region", dict(kind="box", lo=[0, 0, 0], hi=[1, 1, 1])),
                                       ("group", "beads"), ("cells", [2, 2, 2]),
                                       ("normal", [0.0, 0.0, 1.0])])
def test_a_key_the_monitor_kind_ignores_is_refused(key, value):
    t = _table()
    t["monitors"][0][key] = value           # a 'wall' monitor
    assert _error(t).startswith(f"monitors[0].{key}: a 'wall' monitor does not use it")


def test_a_float_where_a_count_is_meant_is_refused():
    t = _table()
    t["monitors"].append(dict(name="mix", kind="mixing", group="beads", cells=[2.5, 2, 2],
                              region=dict(kind="box", lo=[0, 0, 0], hi=[0.06, 0.06, 0.05])))
    assert _error(t).startswith("monitors[2].cells = [2.5, 2, 2]: must be a list of integers")


# ---------------------------------------------------------------- files
def test_a_byte_order_mark_is_read_in_case_and_particle_files(tmp_path):
    (tmp_path / "heap.csv").write_bytes(b"\xef\xbb\xbfx,y,z,radius\n0.02,0.02,0.05,0.002\n")
    text = POUR.read_text().replace(
        'fill = "random"\ncount = 2000\nvelocity = [0.0, 0.0, -0.5]\nsize = { kind = "uniform", '
        'min = 0.0018, max = 0.0022 }\nregion = { kind = "box", lo = [0.0, 0.0, 0.05], hi = '
        '[0.06, 0.06, 0.15] }', 'fill = "file"\nfile = "heap.csv"')
    (tmp_path / "case.toml").write_bytes(b"\xef\xbb\xbf" + text.encode())
    case = load_case(tmp_path / "case.toml")
    assert case.particles[0].file == "heap.csv" and case.check() > 0


def test_a_T_column_that_rows_lack_is_refused(tmp_path):
    from gsi.case.sources import read_particle_file
    f = tmp_path / "p.csv"
    f.write_text("x,y,z,radius,T\n0,0,0,0.01\n1,1,1,0.01\n2,2,2,0.01\n3,3,3,0.01\n4,4,4,0.01\n")
    with pytest.raises(GsiInputError, match=r"^k = '.*p.csv': data row 1 has 4 values but the "
                                            r"header names 5 columns \(x,y,z,radius,T\)"):
        read_particle_file(f, key="k")


# ---------------------------------------------------------------- heat bound
def test_the_heat_bound_is_refused_by_check_with_the_toml_keys():
    t = _table(SILO)
    t["run"]["heat_time_scale"] = 1e9
    msg = _error(t)
    assert msg.startswith("run.heat_time_scale = 1e+09: the explicit heat update is unstable")
    assert "dem.force_dt = true" in msg and "force_dt=True" not in msg
    t["dem"]["force_dt"] = True
    case_from_table(t, base_dir=ROOT / "demos").check()      # forced: the run decides


# ---------------------------------------------------------------- sizes
def test_the_estimate_counts_steps_outputs_and_checkpoints():
    t = _table()
    t["run"]["dt"] = 1e-5
    t["run"]["checkpoint_interval"] = 0.1
    case = case_from_table(t, base_dir=ROOT / "demos")
    est = estimate(case, case.check())
    assert est["steps"] == pytest.approx(0.6 / 1e-5)
    assert est["outputs"] == pytest.approx(30) and est["checkpoints"] == pytest.approx(6)
    assert est["particles"] == 2000


def test_quick_steps_above_the_limit_are_refused_with_the_estimate():
    t = _table()
    t["run"]["dt"] = 1e-9
    msg = _error(t)
    assert msg.startswith("quick.run.dt: 2.5e+08 DEM steps of 1e-09 s over 0.25 s (limit "
                          f"{MAX_QUICK_STEPS:.0e} for --quick")


def test_check_prints_the_estimate(capsys):
    assert main(["check", str(POUR)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[1].startswith("  estimate: 2e+03 particles, 1.36e+04 DEM steps, 30 outputs, "
                             "0 checkpoints; about ")


def test_n_sub_longer_than_the_run_is_refused():
    t = _table(SILO)
    t["structures"][0]["contact"]["n_sub"] = 10 ** 9
    assert _error(t).startswith("structures[0].contact.n_sub = 1000000000: the FE step")
    case = case_from_table(_table(SILO), base_dir=ROOT / "demos")
    assert check_sizes(case, 3e-5) == []


# ---------------------------------------------------------------- fingerprint
def test_the_fingerprint_lists_the_changed_keys_only():
    a = fingerprint(load_case(POUR))
    t = _table()
    t["materials"]["glass"]["mu"] = 0.9
    t["particles"][0]["count"] = 1000
    t["run"]["threads"] = 1                 # free: does not change the physics
    t["output"]["pictures"] = False
    b = fingerprint(case_from_table(t))
    assert changes(a, b) == ["materials.glass.mu: 0.5 -> 0.9", "particles[0].count: 2000 -> 1000"]


def test_resume_of_a_changed_case_is_refused_unless_allowed(tmp_path):
    case = load_case(POUR)
    d = tmp_path / "checkpoints"
    d.mkdir()
    ck.write_manifest(d, 100, dict(time=0.01, n_ranks=1, dt=1e-4, case="pour", quick=False,
                                   sizes=[], fingerprint=fingerprint(case)))
    assert check_resume(case, tmp_path, quick=False, allow=False) == []
    t = _table()
    t["materials"]["glass"]["mu"] = 0.9
    changed = case_from_table(t)
    with pytest.raises(GsiInputError, match=r"^--resume: the case changed since the checkpoint "
                                            r"at t = 0.01 s: materials.glass.mu: 0.5 -> 0.9; "):
        check_resume(changed, tmp_path, quick=False, allow=False)
    with pytest.warns(UserWarning, match="--allow-changes: resuming at t = 0.01 s with 1 changed"):
        assert check_resume(changed, tmp_path, quick=False, allow=True) == \
            ["materials.glass.mu: 0.5 -> 0.9"]


def test_gsi_run_resume_of_a_changed_case_is_refused_before_it_starts(tmp_path, capsys):
    case_file = tmp_path / "pour.toml"
    case_file.write_text(POUR.read_text().replace("mu = 0.5", "mu = 0.9"))
    out = tmp_path / "out"
    (out / "checkpoints").mkdir(parents=True)
    ck.write_manifest(out / "checkpoints", 10, dict(
        time=0.001, n_ranks=1, dt=1e-4, case="pour", quick=False, sizes=[],
        fingerprint=fingerprint(load_case(POUR))))
    rc = main(["run", str(case_file), "--out", str(out), "--resume", "--no-pictures"])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("error: --resume: the case changed since the checkpoint at "
                                      "t = 0.001 s: materials.glass.mu: 0.5 -> 0.9; ")
    assert err.rstrip().endswith("or add --allow-changes to continue with the changes")
    rc = main(["run", str(case_file), "--out", str(out), "--allow-changes", "--no-pictures"])
    assert rc == 2 and capsys.readouterr().err == "error: --allow-changes: only with --resume\n"


DRUM = ROOT / "demos" / "drum.toml"


@pytest.mark.parametrize("mu,dt,refused", [(100.0, 1e-4, True), (30.0, 1e-4, True),
                                           (10.0, 1e-4, False), (100.0, 7e-5, False)])
def test_friction_beyond_the_stable_range_is_refused_with_the_reason(mu, dt, refused):
    """The measured drum runs (dt = 1e-4 s = 0.23 t_R): mu_pp = 100 and 30 blew up,
    10 ran, and 100 ran at dt = 7e-5 s."""
    t = _table(DRUM)
    t["materials"]["grain"]["mu"] = mu
    t["run"]["dt"] = dt
    if not refused:
        assert case_from_table(t, base_dir=ROOT / "demos").check() == dt
        return
    msg = _error(t)
    assert msg.startswith(f"materials.grain.mu = {mu:g}: above 10 the Coulomb cap no longer "
                          "bounds the sticking contacts of particles[0]")
    assert "use run.dt <= 7.45e-05 or mu <= 10" in msg
    t["dem"]["force_dt"] = True
    assert case_from_table(t, base_dir=ROOT / "demos").check() == dt
