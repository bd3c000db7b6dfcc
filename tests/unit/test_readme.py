"""The README stays true and short: its case file passes ``gsi check``, the commands it
shows exist (Makefile targets, ``gsi`` subcommands and options), every relative link and
image points to a file in the repository, and it fits on a few screens."""
import pathlib
import re
import subprocess
import sys
import tomllib

import pytest

from gsi.case import case_from_table
from gsi.run.cli import parser

ROOT = pathlib.Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()


def _between(tag):
    m = re.search(rf"<!-- {tag}:start -->(.*?)<!-- {tag}:end -->", README, re.S)
    assert m, f"README has no {tag} section"
    return m.group(1)


def test_readme_is_short_and_has_no_dated_logs():
    lines = README.splitlines()
    assert len(lines) <= 160
    assert max(len(line) for line in lines) <= 200
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b", README), "dated logs go to benchmarks/results/"


def test_case_file_passes_check(tmp_path):
    blocks = re.findall(r"```toml\n(.*?)```", _between("readme-case"), re.S)
    assert len(blocks) == 1
    assert len(blocks[0].splitlines()) <= 45
    case = case_from_table(tomllib.loads(blocks[0]), base_dir=ROOT / "demos")
    assert case.check() > 0
    path = tmp_path / "case.toml"
    path.write_text(blocks[0])
    r = subprocess.run([sys.executable, "-m", "gsi.cli", "check", str(path)],
                       capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    assert ": ok (case 'pour'" in r.stdout


def test_gsi_commands_exist():
    block = _between("readme-commands")
    commands = re.findall(r"^gsi (\w+)(.*?)(?:#|$)", block, re.M)
    assert {c for c, _ in commands} >= {"run", "check", "info"}
    sub = next(a for a in parser()._actions if a.dest == "command")
    for name, rest in commands:
        command = sub.choices[name]
        known = {o for a in command._actions for o in a.option_strings}
        for opt in re.findall(r"--[\w-]+", rest):
            assert opt in known, f"gsi {name} has no {opt}"


def test_make_targets_exist():
    targets = set(re.findall(r"^([\w-]+):", (ROOT / "Makefile").read_text(), re.M))
    used = set(re.findall(r"\bmake ([\w-]+)", README))
    assert {"demo", "test", "docs"} <= used
    assert used <= targets, used - targets


@pytest.mark.parametrize("link", sorted(set(re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", README))))
def test_relative_links_point_to_files(link):
    if re.match(r"\w+://", link):
        pytest.skip("external")
    assert (ROOT / link).exists(), link


def test_tested_versions_are_named():
    for word in ("Debian 12", "dolfinx 0.5.2", "numba 0.56", "numpy 1.24", "gmsh 4.8",
                 "petsc4py 3.18"):
        assert word in README
