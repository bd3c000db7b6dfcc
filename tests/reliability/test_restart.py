"""Checkpoint/restart: a resumed run is bit-identical to an uninterrupted one.

The case (data/coupled_small.toml): a stream of hot particles (insertion and the random
generator), a moving gate (a mesh wall with a schedule), heat conduction, and a dynamic
thermo-elastic plate coupled in mode "both" (Newmark, heat, records, energy baseline).
A finished run with a checkpoint every 0.006 s is rewound by dropping its newest
checkpoint: the resume starts from the older one with the finished run's later outputs
still on disk, so it must also cut every series back (no duplicate, no stale entry).
Compared bitwise: the final state of every rank (DEM arrays, FE fields, records without
their wall-clock columns, monitor series) and every output file (see
``_util.assert_same_files`` for the three exceptions).
"""
import importlib.util
import json
import pathlib
import subprocess
import sys

import pytest

_spec = importlib.util.spec_from_file_location(
    "gsi_tests_reliability_util", pathlib.Path(__file__).resolve().parent / "_util.py")
_util = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_util)
CASE, EVERY, cli, driver, dumps, env, rewind = (
    _util.CASE, _util.EVERY, _util.cli, _util.driver, _util.dumps, _util.env, _util.rewind)
assert_same_files, assert_same_state = _util.assert_same_files, _util.assert_same_state


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted serial run (one numba thread)."""
    base = tmp_path_factory.mktemp("reference")
    driver(base / "out", "--checkpoint-every", EVERY, "--dump", str(base / "final"))
    return base


@pytest.mark.parametrize("threads", [1, 2])
def test_resume_is_bitwise_serial(reference, tmp_path, threads):
    if threads == 1:
        ref = reference
    else:       # 2 threads, parallel kernels even for a few particles: its own reference
        ref = tmp_path / "ref"
        driver(ref / "out", "--checkpoint-every", EVERY, "--dump", str(ref / "final"),
               "--parallel-min-n", "0", threads=2)
    step = rewind(ref / "out", tmp_path / "out")
    assert step == 800
    extra = ["--parallel-min-n", "0"] if threads == 2 else []
    proc = driver(tmp_path / "out", "--resume", "--checkpoint-every", EVERY, "--dump",
                  str(tmp_path / "final"), *extra, threads=threads)
    assert "resumed at t = 0.012 s (step 800)" in proc.stdout
    assert_same_state(dumps(ref / "final"), dumps(tmp_path / "final"))
    assert_same_files(ref / "out", tmp_path / "out")


def test_resume_is_bitwise_under_mpirun(tmp_path):
    ref = tmp_path / "ref"
    driver(ref / "out", "--checkpoint-every", EVERY, "--dump", str(ref / "final"), ranks=2)
    manifest = json.loads(sorted((ref / "out" / "checkpoints").glob("*.json"))[-1].read_text())
    assert manifest["n_ranks"] == 2 and len(manifest["sizes"]) == 2
    rewind(ref / "out", tmp_path / "out")
    driver(tmp_path / "out", "--resume", "--checkpoint-every", EVERY, "--dump",
           str(tmp_path / "final"), ranks=2)
    assert_same_state(dumps(ref / "final"), dumps(tmp_path / "final"))
    assert_same_files(ref / "out", tmp_path / "out")
    # a different number of ranks is refused with one line
    proc = cli(tmp_path / "out", "--resume")
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 2
    assert err.strip().splitlines() == [
        f"error: --resume: the checkpoint at t = 0.018 s was written by 2 MPI rank(s), this "
        f"run has 1; resume with mpirun -n 2 (or serially for 1)"]


def test_resume_without_a_checkpoint_is_refused(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "gsi.cli", "run", str(CASE), "--out",
                           str(tmp_path), "--resume"], env=env(), capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.strip().splitlines()[-1].startswith(
        "error: --resume: no complete checkpoint under")
