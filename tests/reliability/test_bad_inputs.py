"""The bad-input corpus (``cases/*.toml``, made by ``make_corpus.py``): every broken case
file gives exit status 2 and ONE stderr line ``error: ...`` that names the key, never a
traceback.

Cases marked ``warn`` pass ``gsi check`` with one ``warning:`` line naming the key; cases
marked ``ok`` are valid inputs next to the broken ones and pass silently.

The "check" cases run through :func:`gsi.cli.main` in this process (the same code path as
the ``gsi`` command, minus the interpreter start); a representative subset, and every case
that only ``gsi run`` can find (set-up), run through the ``gsi`` command in a subprocess.
"""
import os
import pathlib
import subprocess
import sys

import pytest

from gsi.cli import main

HERE = pathlib.Path(__file__).parent
CASES = sorted((HERE / "cases").glob("*.toml"))
ROOT = HERE.parents[1]


def _header(path: pathlib.Path) -> tuple[str, str]:
    """(expected key, 'check' or 'run') from the file's first line."""
    first = path.read_bytes().split(b"\n", 1)[0].decode("utf-8").lstrip("\ufeff")
    assert first.startswith("# expect: "), path.name
    parts = [p.strip() for p in first[2:].split(" | ")]
    return parts[0].removeprefix("expect: "), parts[1].removeprefix("via: ")


CHECK = [c for c in CASES if _header(c)[1] == "check"]
RUN = [c for c in CASES if _header(c)[1] == "run"]
WARN = [c for c in CASES if _header(c)[1] == "warn"]
OK = [c for c in CASES if _header(c)[1] == "ok"]
#: through the real command as well (a new interpreter; the issue's "tracebacks" items)
SUBPROCESS = ["non_utf8", "count_1e9", "count_float_1e9", "E_1Pa", "structure_geometry_string",
              "structure_geo_string", "dt_0p7_rayleigh", "stream_rate_1e12", "skin_10m",
              "case_name_dotdot", "particle_file_overlap", "not_toml",
              "geo_h_tiny"]


def _assert_one_error_line(rc, err: str, key: str, name: str) -> None:
    assert "Traceback" not in err, f"{name}: {err}"
    assert rc == 2, f"{name}: exit {rc}: {err}"
    lines = err.splitlines()
    assert len(lines) == 1 and err.endswith("\n"), f"{name}: {err!r}"
    assert lines[0].startswith("error: "), f"{name}: {err!r}"
    assert key in lines[0], f"{name}: expected key {key!r} in {lines[0]!r}"


def test_the_corpus_is_large_and_covers_the_issue():
    assert len(CASES) >= 60
    names = {c.stem for c in CASES}
    for needed in ("non_utf8", "count_1e9", "E_1Pa", "structure_geometry_string", "skin_10m",
                   "stream_rate_1e12", "case_name_dotdot", "particle_file_overlap",
                   "dt_0p7_rayleigh", "dt_linear_above_tc", "quick_longer", "plane_rotates",
                   "thermal_contact_without_heat", "structure_tags_missing_group",
                   "structure_tag_not_in_mesh", "mesh_wall_missing_file",
                   "particle_file_missing", "structure_missing_file", "radius_in_mm",
                   "schedule_after_end", "random_fill_too_dense", "region_outside_domain"):
        assert needed in names
    for section in ("case", "run", "dem", "materials.glass", "particles[0]",
                    "particles[0].size", "particles[0].region", "walls[0]", "walls[0].motion",
                    "monitors[0]", "output", "pairs[0]", "structures[0]", "quick.run"):
        assert any(_header(c)[0].startswith(section + ".") for c in CASES
                   if c.stem.startswith("unknown_")), section


@pytest.mark.parametrize("path", CHECK, ids=[c.stem for c in CHECK])
def test_gsi_check_refuses_in_one_line(path, capsys):
    key, _ = _header(path)
    rc = main(["check", str(path)])
    out, err = capsys.readouterr()
    assert out == ""
    _assert_one_error_line(rc, err, key, path.name)


def _gsi(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "gsi.cli", *args], capture_output=True,
                          text=True, env=env, cwd=cwd, timeout=300)


@pytest.mark.parametrize("name", SUBPROCESS)
def test_gsi_check_command_refuses_in_one_line(name):
    path = HERE / "cases" / f"{name}.toml"
    key, via = _header(path)
    assert via == "check"
    res = _gsi("check", str(path))
    assert res.stdout == ""
    _assert_one_error_line(res.returncode, res.stderr, key, name)
    assert "MemoryError" not in res.stderr and "TypeError" not in res.stderr


@pytest.mark.parametrize("path", RUN, ids=[c.stem for c in RUN])
def test_set_up_errors_of_gsi_run_are_one_line(path, tmp_path):
    """What only the set-up finds (positions drawn at the start): ``gsi check`` passes,
    ``gsi run --quick`` stops before the first step with one line, exit 2."""
    key, _ = _header(path)
    assert _gsi("check", str(path)).returncode == 0
    res = _gsi("run", str(path), "--quick", "--no-pictures", "--out", str(tmp_path / "out"))
    _assert_one_error_line(res.returncode, res.stderr, key, path.name)


def test_the_corpus_has_every_outcome():
    assert len(CHECK) >= 150 and len(WARN) >= 4 and len(OK) >= 8 and RUN


@pytest.mark.parametrize("path", WARN, ids=[c.stem for c in WARN])
def test_gsi_check_accepts_with_a_warning_naming_the_key(path, capsys):
    key, _ = _header(path)
    rc = main(["check", str(path)])
    out, err = capsys.readouterr()
    assert rc == 0, err
    assert "Traceback" not in err
    warned = [ln for ln in err.splitlines() if ln.startswith("warning: ")]
    assert len(warned) == 1 and key in warned[0], err
    assert "estimate: " in out


@pytest.mark.parametrize("path", OK, ids=[c.stem for c in OK])
def test_valid_inputs_pass_silently(path, capsys):
    rc = main(["check", str(path)])
    out, err = capsys.readouterr()
    assert rc == 0 and err == "", err
    assert ": ok (case " in out and "estimate: " in out
