"""A file that meshio or gmsh cannot read is one ``error:`` line naming the key and the
file, exit status 2 -- never meshio's ``Error: Couldn't read file`` and its
``sys.exit(1)`` (a ``SystemExit`` that passes ``except Exception``), never a traceback.

Each case is a shipped demo with one file replaced by a broken one: random bytes or a
cut-off XML header as a ``.vtu`` particle file or mesh wall, random bytes as an ``.stl``
wall, random bytes and a cut-off ``$Nodes`` section as a ``.msh`` structure, a ``.geo``
script with a syntax error.
"""
import os
import pathlib
import subprocess
import sys

import pytest

from gsi.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[2]
DEMOS = ROOT / "demos"
RANDOM = bytes((i * 7919 + 13) % 251 for i in range(3000))      # no text, no XML
CUT_VTU = b'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid"><Unstr'
CUT_MSH = b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n"
BAD_GEO = b"Point(1) = {0, 0, 0};\nLine(1) = {1, 2;\n"


def _particle_case(tmp, data: bytes, name="beads.vtu"):
    (tmp / name).write_bytes(data)
    text = (DEMOS / "pour.toml").read_text().replace(
        'fill = "random"\ncount = 2000', f'fill = "file"\nfile = "{name}"\n# count = 2000')
    text = "\n".join(line for line in text.splitlines()
                     if not line.startswith(("size = ", "region = ", "velocity = ")))
    (tmp / "case.toml").write_text(text + "\n")
    return tmp / "case.toml", "particles[0].file", name


def _wall_case(tmp, data: bytes, name="drum.vtu"):
    (tmp / name).write_bytes(data)
    text = (DEMOS / "drum.toml").read_text().replace('file = "data/drum.stl"',
                                                     f'file = "{name}"')
    (tmp / "case.toml").write_text(text)
    return tmp / "case.toml", "walls[0].file", name


def _structure_case(tmp, data: bytes, name="belt.msh"):
    (tmp / name).write_bytes(data)
    text = (DEMOS / "belt_hopper.toml").read_text().replace('file = "../meshes/belt.geo"',
                                                            f'file = "{name}"')
    (tmp / "case.toml").write_text(text)
    return tmp / "case.toml", "structures[0]", name


CASES = {
    "particles_random_vtu": (_particle_case, RANDOM, "beads.vtu"),
    "particles_cut_vtu": (_particle_case, CUT_VTU, "beads.vtu"),
    "wall_random_vtu": (_wall_case, RANDOM, "drum.vtu"),
    "wall_cut_vtu": (_wall_case, CUT_VTU, "drum.vtu"),
    "wall_random_stl": (_wall_case, RANDOM, "drum.stl"),
    "structure_random_msh": (_structure_case, RANDOM, "belt.msh"),
    "structure_cut_msh": (_structure_case, CUT_MSH, "belt.msh"),
    "structure_bad_geo": (_structure_case, BAD_GEO, "belt.geo"),
}


def _assert_one_line(rc, out, err, key, name):
    assert rc == 2, (rc, out, err)
    assert "Traceback" not in err and "Couldn't read" not in err + out, err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert key in lines[0] and name in lines[0], lines[0]


@pytest.mark.parametrize("which", sorted(CASES))
def test_gsi_check_names_the_key_and_the_file(tmp_path, capsys, which):
    make, data, name = CASES[which]
    case, key, name = make(tmp_path, data, name)
    rc = main(["check", str(case)])
    out, err = capsys.readouterr()
    assert out == ""
    _assert_one_line(rc, out, err, key, name)


@pytest.mark.parametrize("which", ["particles_random_vtu", "wall_cut_vtu"])
def test_the_gsi_command_prints_one_line(tmp_path, which):
    """Through the real command (a new interpreter: meshio's ``sys.exit`` would end it)."""
    make, data, name = CASES[which]
    case, key, name = make(tmp_path, data, name)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-m", "gsi.cli", "check", str(case)],
                          capture_output=True, text=True, env=env, timeout=300)
    assert proc.stdout == ""
    _assert_one_line(proc.returncode, proc.stdout, proc.stderr, key, name)
