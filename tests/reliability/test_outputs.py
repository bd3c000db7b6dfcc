"""``--out`` problems and write failures give one line, never a traceback:

* an ``--out`` that is a file, under a file, read-only, or empty: exit 2 before any work;
* an ``--out`` holding an earlier run's outputs: refused unless ``--overwrite``, which
  removes them first (no stale ``particles_*.vtu`` in the series), other files stay;
* a full disk during the run: exit 3, ``run stopped: cannot write ...``, no ``*.tmp<pid>``
  file left behind. Measured on a 1 MiB tmpfs (mounted when root may), and with an injected
  ENOSPC (always).

Runs go through :func:`gsi.cli.main` in this process (the ``gsi`` command's code path; one
JIT compile for the whole module); the read-only ``--out`` also through the command.
"""
import errno
import os
import pathlib
import re
import subprocess
import sys
import uuid

import pytest

from gsi.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def tiny(tmp_path) -> pathlib.Path:
    """The pour demo shrunk to 30 beads and 0.01 s (7 particle outputs; --quick: 4)."""
    text = (ROOT / "demos" / "pour.toml").read_text()
    for old, new in (("count = 2000", "count = 30"), ("duration = 0.6 ", "duration = 0.01 "),
                     ("interval = 0.02 ", "interval = 0.002 "),
                     ("run = { duration = 0.25 }", "run = { duration = 0.004 }")):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "tiny.toml"
    path.write_text(text)
    return path


def _mount(where: pathlib.Path, options: str) -> bool:
    where.mkdir(parents=True, exist_ok=True)
    res = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(where)],
                         capture_output=True)
    return res.returncode == 0


@pytest.fixture
def tmpfs(tmp_path):
    """A mount factory (tmpfs with the given options); unmounted at the end. Skips when
    this process may not mount (not root, or no CAP_SYS_ADMIN)."""
    mounted = []

    def make(options: str) -> pathlib.Path:
        where = tmp_path / f"mnt-{uuid.uuid4().hex[:6]}"
        if not _mount(where, options):
            pytest.skip("cannot mount a tmpfs here (needs root and CAP_SYS_ADMIN)")
        mounted.append(where)
        return where

    yield make
    for where in mounted:
        subprocess.run(["umount", "-l", str(where)], capture_output=True)


def _one_line(err: str, start: str) -> str:
    assert "Traceback" not in err, err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith(start), err
    return lines[0]


def _vtus(out: pathlib.Path) -> list[str]:
    return sorted(p.name for p in (out / "particles").glob("particles_*.vtu"))


def test_a_second_run_is_refused_and_overwrite_leaves_no_stale_files(tiny, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["run", str(tiny), "--no-pictures", "--out", str(out)]) == 0
    first = _vtus(out)
    assert len(first) == 7
    (out / "notes.txt").write_text("mine")          # not gsi's: must survive --overwrite
    capsys.readouterr()

    assert main(["run", str(tiny), "--quick", "--no-pictures", "--out", str(out)]) == 2
    line = _one_line(capsys.readouterr().err, "error: --out = ")
    assert "earlier run" in line and "--overwrite" in line
    assert _vtus(out) == first                      # nothing touched

    assert main(["run", str(tiny), "--quick", "--no-pictures", "--overwrite",
                 "--out", str(out)]) == 0
    now = _vtus(out)
    listed = re.findall(r'file="(particles_\d+\.vtu)"',
                        (out / "particles" / "particles.pvd").read_text())
    assert now == sorted(listed) and len(now) < len(first)  # this run's files only
    assert (out / "notes.txt").read_text() == "mine"


def test_overwrite_removes_only_gsi_outputs(tmp_path):
    from mpi4py import MPI
    from gsi.run.outdir import output_dir
    from gsi.errors import GsiInputError
    out = tmp_path / "o"
    for d in ("particles", "walls", "monitors", "pictures"):
        (out / d).mkdir(parents=True)
        (out / d / "x.vtu").write_text("")
    for f in ("membrane.xdmf", "membrane.h5", "membrane_coupling.csv", "bin_energy.csv",
              "summary.txt", "pour.gif", "pour.png", "case.toml", "data.txt", "heap.csv"):
        (out / f).write_text("")
    (out / "data").mkdir()
    (out / "data" / "heap.csv").write_text("")
    with pytest.raises(GsiInputError, match="--overwrite"):
        output_dir(out, MPI.COMM_WORLD)
    output_dir(out, MPI.COMM_WORLD, overwrite=True)
    assert sorted(p.name for p in out.iterdir()) == ["case.toml", "data", "data.txt",
                                                     "heap.csv"]
    assert (out / "data" / "heap.csv").exists()
    output_dir(out, MPI.COMM_WORLD)                # nothing of a run left: accepted
    (out / "pour.png").write_text("")               # a user's picture alone: not a run
    output_dir(out, MPI.COMM_WORLD)
    assert (out / "pour.png").exists()


def test_full_disk_stops_in_one_line_without_temporary_files(tiny, tmpfs, capsys):
    disk = tmpfs("size=1m")
    ballast = disk / "ballast"
    with open(ballast, "wb") as fh:                 # leave ~16 KiB: the run fills it
        fh.write(b"\0" * (1024 * 1024 - 16 * 1024))
    out = disk / "out"
    rc = main(["run", str(tiny), "--no-pictures", "--out", str(out)])
    line = _one_line(capsys.readouterr().err, "run stopped: cannot write")
    assert rc == 3 and "No space left on device" in line and "--overwrite" in line
    assert not [p for p in out.rglob("*") if ".tmp" in p.name]


def test_injected_write_failure_stops_in_one_line_without_temporary_files(tiny, tmp_path,
                                                                          monkeypatch, capsys):
    """The same without a mount: the third particle file fails half-written (ENOSPC)."""
    import gsi.dem.output as output
    real = output.write_text_atomic
    calls = {"n": 0}

    def failing(path, text):
        if str(path).endswith(".vtu") and "particles_" in str(path):
            calls["n"] += 1
            if calls["n"] == 3:
                tmp = f"{path}.tmp{os.getpid()}"
                pathlib.Path(tmp).write_text(text[: len(text) // 2])
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), tmp)
        real(path, text)

    monkeypatch.setattr(output, "write_text_atomic", failing)
    out = tmp_path / "out"
    rc = main(["run", str(tiny), "--no-pictures", "--out", str(out)])
    line = _one_line(capsys.readouterr().err, "run stopped: cannot write")
    assert rc == 3 and "No space left on device" in line
    assert not [p for p in out.rglob("*") if ".tmp" in p.name]
    assert len(_vtus(out)) == 2                     # what was written before stays


def test_read_only_out_is_refused_by_the_command(tiny, tmpfs):
    ro = tmpfs("ro,size=64k")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-m", "gsi.cli", "run", str(tiny), "--no-pictures",
                          "--out", str(ro / "out")], capture_output=True, text=True, env=env,
                         timeout=300)
    assert res.returncode == 2
    line = _one_line(res.stderr, "error: --out = ")
    assert "Read-only file system" in line


def test_unwritable_out_is_refused(tiny, tmp_path, monkeypatch, capsys):
    """Root writes into a chmod 0555 directory, so the PermissionError a user sees is
    injected here: the probe write of ``output_dir`` fails."""
    real = pathlib.Path.write_text

    def denied(self, *a, **kw):
        if self.name.startswith(".gsi-write-test"):
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(self))
        return real(self, *a, **kw)

    monkeypatch.setattr(pathlib.Path, "write_text", denied)
    assert main(["run", str(tiny), "--out", str(tmp_path / "locked")]) == 2
    line = _one_line(capsys.readouterr().err, "error: --out = ")
    assert "not writable" in line


@pytest.mark.parametrize("kind", ["file", "under_file", "empty"])
def test_bad_out_paths_are_refused_in_one_line(kind, tiny, tmp_path, capsys):
    afile = tmp_path / "afile"
    afile.write_text("x")
    out, words = {"file": (str(afile), "a file of that name exists"),
                  "under_file": (str(afile / "sub"), "a parent is a file"),
                  "empty": ("", "give an output directory")}[kind]
    assert main(["run", str(tiny), "--out", out]) == 2
    assert words in _one_line(capsys.readouterr().err, "error: --out = ")


def test_out_of_memory_at_set_up_stops_in_one_line(tiny, tmp_path, monkeypatch, capsys):
    """A MemoryError (injected: the checks refuse the counts that would raise it) becomes
    ``run stopped: out of memory; ...`` with exit status 3."""
    import gsi.run.runner

    def no_memory(case, *, dt):
        raise MemoryError

    monkeypatch.setattr(gsi.run.runner, "build_simulation", no_memory)
    assert main(["run", str(tiny), "--out", str(tmp_path / "out")]) == 3
    line = _one_line(capsys.readouterr().err, "run stopped: out of memory")
    assert "particles[].count" in line
