"""Checkpoint/restart: a resumed run is bit-identical to an uninterrupted one.

The case (data/coupled_small.toml): a stream of hot particles (insertion and the random
generator), a moving gate (a mesh wall with a schedule), heat conduction, and a dynamic
thermo-elastic plate coupled in mode "both" (Newmark, heat, records, energy baseline).
A finished run with a checkpoint every 0.006 s is rewound by dropping its newest
checkpoint: the resume starts from the older one with the finished run's later outputs
still on disk, so it must also cut every series back (no duplicate, no stale entry).
Compared bitwise: the final state of every rank (DEM arrays, FE fields, records without
their wall-clock columns, monitor series) and every output file (see
``_util.assert_same_files`` for the three exceptions). Among them the ``energy``
monitor's series: the resumed run continues the uninterrupted run's energy book (its
start, the removed particles' energy and the walls' accumulators are in the checkpoint,
docs/design.md, "Energy audit"), so its drift after ``--resume`` is bitwise the same.
"""
import importlib.util
import json
import pathlib
import re
import subprocess
import sys

import numpy as np
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


def test_resume_under_mpirun_restores_bitwise_and_continues(tmp_path):
    """Under mpirun -n 2 the restore is exact (the state right after ``--resume`` equals
    the checkpoint on both ranks) and the continued run is bit-identical to the
    uninterrupted one, state and files. This rests on a reproducible mesh partition
    (``gsi.fem.compat._deterministic_partitioning``): with PT-Scotch's default threads
    two uninterrupted runs differed by up to 1.2e-9 of a field's size."""
    ref = tmp_path / "ref"
    driver(ref / "out", "--checkpoint-every", EVERY, "--dump", str(ref / "final"), ranks=2)
    manifest = json.loads(sorted((ref / "out" / "checkpoints").glob("*.json"))[-1].read_text())
    assert manifest["n_ranks"] == 2 and len(manifest["sizes"]) == 2
    step = rewind(ref / "out", tmp_path / "out")
    driver(tmp_path / "out", "--resume", "--dump-restored", str(tmp_path / "restored"),
           ranks=2)
    saved = {f"rank{r}": dict(np.load(tmp_path / "out" / "checkpoints" /
                                      f"ckpt_{step:010d}.rank{r}.npz")) for r in (0, 1)}
    assert_same_state(saved, dumps(tmp_path / "restored"))
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


# ---------------------------------------------------------------------- kill -9 and signals
def _interrupt(out, sig, *, delay, ranks=None, target="process", case=None):
    """Start ``gsi run``, wait for its first checkpoint and ``delay`` s more, send ``sig``
    (to the process, its process group, or -- under mpirun -- to the ranks)."""
    import os
    import time
    proc = cli(out, "--checkpoint-every", EVERY, ranks=ranks, case=case,
               start_new_session=True)
    _util.wait_for("checkpoints/ckpt_*.json", out, proc=proc)
    time.sleep(delay)
    if target == "group":
        os.killpg(proc.pid, sig)
    elif target == "ranks":
        kids = subprocess.run(["pgrep", "-P", str(proc.pid)], capture_output=True,
                              text=True).stdout.split()
        assert len(kids) == ranks
        for pid in kids:
            os.kill(int(pid), sig)
    else:
        os.kill(proc.pid, sig)
    stdout, stderr = proc.communicate(timeout=300)
    return proc.returncode, stdout, stderr


def _resume(out, ranks=None, case=None):
    proc = cli(out, "--checkpoint-every", EVERY, "--resume", ranks=ranks, case=case)
    stdout, stderr = proc.communicate(timeout=600)
    assert proc.returncode == 0, stdout[-2000:] + stderr[-3000:]
    return stdout


@pytest.mark.parametrize("delay", [0.0, 0.2])
def test_kill_9_leaves_readable_files_and_resumes_bitwise(reference, tmp_path, delay):
    import signal
    out = tmp_path / "out"
    code, _, _ = _interrupt(out, signal.SIGKILL, delay=delay)
    assert code == -signal.SIGKILL
    _util.assert_files_open(out)
    assert "resumed at t = " in _resume(out)
    assert_same_files(reference / "out", out)


def test_kill_9_under_mpirun_leaves_readable_files_and_resumes_bitwise(tmp_path):
    """kill -9 of ``mpirun -n 2`` and both ranks (its process group) once a checkpoint
    exists: every file opens, and the 2-rank resume ends with files bit-identical to an
    uninterrupted 2-rank run."""
    import signal
    ref = tmp_path / "ref"
    driver(ref / "out", "--checkpoint-every", EVERY, ranks=2)
    out = tmp_path / "out"
    code, _, _ = _interrupt(out, signal.SIGKILL, delay=0.2, ranks=2, target="group")
    assert code == -signal.SIGKILL
    _util.assert_files_open(out)
    assert "resumed at t = " in _resume(out, ranks=2)
    assert_same_files(ref / "out", out)


@pytest.mark.parametrize("name, code", [("SIGINT", 130), ("SIGTERM", 143)])
def test_a_signal_checkpoints_prints_one_line_and_resumes_bitwise(reference, tmp_path, name,
                                                                  code):
    import signal
    out = tmp_path / "out"
    rc, _, stderr = _interrupt(out, getattr(signal, name), delay=0.0)
    assert rc == code, stderr
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    assert re.fullmatch(r"interrupted at t = [0-9.e-]+ s; checkpoint written; resume with "
                        r"gsi run \S+coupled_small.toml --out \S+ --no-pictures "
                        r"--checkpoint-every 0.006 --resume", lines[0]), lines[0]
    t = float(lines[0].split()[4])
    manifest = json.loads(sorted((out / "checkpoints").glob("*.json"))[-1].read_text())
    assert manifest["time"] == pytest.approx(t, rel=1e-5)     # the newest is the signal's
    _util.assert_files_open(out)
    _resume(out)
    assert_same_files(reference / "out", out)


@pytest.mark.parametrize("target", ["group", "ranks"])
def test_a_signal_under_mpirun_checkpoints_on_every_rank(tmp_path, target):
    """Ctrl-C of ``mpirun -n 2`` (SIGINT to its process group: Open MPI's mpirun sends
    the ranks SIGCONT, SIGTERM one second later and SIGKILL one more second later, and
    exits with 1) or SIGTERM to the ranks alone (mpirun passes their status on: 143): one
    line from rank 0, a checkpoint of both ranks, a clean resume. The ranks must be gone
    within the second after SIGTERM: they leave with ``os._exit`` once the checkpoint is
    written (with the interpreter's and MPI's teardown they often missed it). The case runs
    0.15 s here (10,000 steps): the ranks get the signal one second after mpirun, and the
    0.024 s case can end within that second on a fast machine (measured: 1.0 s from the
    first checkpoint to its end, idle), when there is nothing left to interrupt."""
    import signal
    out = tmp_path / "out"
    case = _util.longer_case(tmp_path, 0.15)
    sig = signal.SIGINT if target == "group" else signal.SIGTERM
    rc, _, stderr = _interrupt(out, sig, delay=0.0, ranks=2, target=target, case=case)
    assert rc == (1 if target == "group" else 143), stderr
    ours = [line for line in stderr.splitlines() if line.startswith("interrupted at t = ")]
    assert len(ours) == 1 and "Traceback" not in stderr, stderr
    assert ours[0].endswith("resume with mpirun -n 2 gsi run " + ours[0].split(" gsi run ")[1])
    manifest = json.loads(sorted((out / "checkpoints").glob("*.json"))[-1].read_text())
    assert manifest["n_ranks"] == 2
    assert manifest["time"] == pytest.approx(float(ours[0].split()[4]), rel=1e-5)
    _util.assert_files_open(out)
    assert "resumed at t = " in _resume(out, ranks=2, case=case)


def test_the_quick_hopper_demo_resumes_bitwise(tmp_path, monkeypatch):
    """The shipped demo (--quick): cone and gate mesh walls, rolling resistance, a P2
    generalized-alpha membrane; rewound to its checkpoint at 0.5 s."""
    monkeypatch.setattr(_util, "CASE", _util.ROOT / "demos" / "hopper_membrane.toml")
    driver(tmp_path / "ref", "--quick", "--checkpoint-every", "0.5", "--dump",
           str(tmp_path / "ref_final"))
    assert rewind(tmp_path / "ref", tmp_path / "res") == 1570
    proc = driver(tmp_path / "res", "--quick", "--resume", "--checkpoint-every", "0.5",
                  "--dump", str(tmp_path / "res_final"))
    assert "resumed at t = 0.500152 s (step 1570)" in proc.stdout
    assert_same_state(dumps(tmp_path / "ref_final"), dumps(tmp_path / "res_final"))
    assert_same_files(tmp_path / "ref", tmp_path / "res")
