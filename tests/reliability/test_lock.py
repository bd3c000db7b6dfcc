"""One run owns its output directory (``<out>/gsi.lock``, gsi.run.lock).

* While a run is in its loop, a second ``gsi run`` into the same ``--out`` (the same case
  or another, with ``--overwrite`` or ``--resume`` too) is refused: exit status 2, one
  line naming the holder's PID and host, and the first run's files untouched.
* A run killed with ``kill -9`` leaves its lock; the next run (``--resume``) replaces it
  with one warning line and completes; a lock left by a process that no longer exists
  is replaced the same way. A normal end and a stop by a signal remove the lock.
* Under ``mpirun -n 2`` rank 0 alone locks: a serial run is refused naming rank 0's PID,
  and a second ``mpirun -n 2`` run is refused with one line, every rank stopping (no hang).
"""
import importlib.util
import json
import os
import pathlib
import signal
import socket
import subprocess
import sys

import pytest

_spec = importlib.util.spec_from_file_location(
    "gsi_tests_reliability_util", pathlib.Path(__file__).resolve().parent / "_util.py")
_util = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_util)

CASE = _util.HERE / "data" / "long_chunk.toml"
OTHER = _util.CASE                                   # another case (coupled_small)


def _hours_case(directory):
    path = pathlib.Path(directory) / CASE.name
    path.write_text(CASE.read_text().replace("duration = 0.1\n", "duration = 100.0\n")
                    .replace("interval = 0.1\n", "interval = 100.0\n"))
    return path


def _start(out, case, *extra, ranks=None):
    """A run in its loop (its t = 0 output written)."""
    proc = _util.cli(out, *extra, ranks=ranks, case=case, start_new_session=True)
    _util.wait_for("particles/particles_000000.vtu", out, proc=proc)
    return proc


def _second(out, case, *extra, ranks=None):
    proc = _util.cli(out, *extra, ranks=ranks, case=case)
    stdout, stderr = proc.communicate(timeout=300)
    return proc.returncode, stderr


def _holder(out):
    return json.loads((out / "gsi.lock").read_text())


def _assert_refused(rc, stderr, out, pid, mpi=False):
    """One line (under mpirun: one line of ours, mpirun's own report of the exit status
    follows)."""
    assert rc == 2, stderr
    lines = stderr.strip().splitlines()
    if mpi:
        lines = [line for line in lines if line.startswith(("error", "warning", "Trace"))]
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    assert lines[0].startswith(f"error: --out = {str(out)!r}: in use by another gsi run "
                               f"(pid {pid} on host {socket.gethostname()}, started "), lines[0]


def _stop(proc, pids=None):
    for pid in pids or [proc.pid]:
        os.kill(int(pid), signal.SIGTERM)
    _, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 143, stderr


def test_a_second_run_into_a_locked_directory_is_refused(tmp_path):
    out = tmp_path / "out"
    case = _hours_case(tmp_path)
    first = _start(out, case, "--checkpoint-every", "0")
    try:
        holder = _holder(out)
        assert holder["pid"] == first.pid and holder["host"] == socket.gethostname()
        before = sorted(p.relative_to(out) for p in out.rglob("*"))
        for c, extra in [(case, ()), (OTHER, ()), (OTHER, ("--overwrite",)),
                         (case, ("--resume",))]:
            rc, stderr = _second(out, c, *extra)
            _assert_refused(rc, stderr, out, first.pid)
        assert sorted(p.relative_to(out) for p in out.rglob("*")) == before
        assert _holder(out) == holder
    finally:
        _stop(first)
    assert not (out / "gsi.lock").exists()


def test_a_killed_runs_lock_is_replaced_with_a_warning(tmp_path):
    out = tmp_path / "out"
    proc = _util.cli(out, "--checkpoint-every", "0.01", case=CASE, start_new_session=True)
    _util.wait_for("checkpoints/ckpt_*.json", out, proc=proc)
    proc.send_signal(signal.SIGKILL)
    proc.communicate(timeout=60)
    assert _holder(out)["pid"] == proc.pid          # left behind
    rc, stderr = _second(out, CASE, "--checkpoint-every", "0.01", "--resume")
    assert rc == 0, stderr
    assert stderr.strip().splitlines() == [
        f"warning: --out = {str(out)!r}: a stale lock (pid {proc.pid} on host "
        f"{socket.gethostname()}, started {_started(stderr)}; no process holds it) replaced"]
    assert not (out / "gsi.lock").exists()


def _started(stderr):
    return stderr.split(", started ", 1)[1].split(";", 1)[0]


def test_a_lock_of_a_process_that_is_gone_is_replaced(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()
    (out / "gsi.lock").write_text(json.dumps(dict(pid=int(gone), host=socket.gethostname(),
                                                  started="yesterday", command="gsi")))
    rc, stderr = _second(out, CASE)
    assert rc == 0, stderr
    assert stderr.strip().splitlines() == [
        f"warning: --out = {str(out)!r}: a stale lock (pid {gone} on host "
        f"{socket.gethostname()}, started yesterday; no process holds it) replaced"]
    assert not (out / "gsi.lock").exists()


def test_the_lock_in_the_python_api(tmp_path):
    """A Runner holds the lock from its creation until run() ends (or close())."""
    from gsi.case import load_case
    from gsi.errors import GsiInputError
    from gsi.run import Runner
    case = load_case(CASE)
    out = tmp_path / "out"
    a = Runner(case, out=out, verbose=False)
    assert _holder(out)["pid"] == os.getpid()
    with pytest.raises(GsiInputError, match=r"in use by another gsi run \(pid "
                                            rf"{os.getpid()} on host"):
        Runner(case, out=out, verbose=False)
    a.close()
    assert not (out / "gsi.lock").exists()
    b = Runner(case, out=out, verbose=False)
    b.close()
    with pytest.raises(GsiInputError, match="checkpoint-every"):   # refused before locking
        Runner(case, out=out, verbose=False, checkpoint_every=-1.0)
    assert not (out / "gsi.lock").exists()


def test_under_mpirun_rank_0_locks_and_every_rank_learns(tmp_path):
    out = tmp_path / "out"
    case = _hours_case(tmp_path)
    first = _start(out, case, ranks=2)
    ranks = subprocess.run(["pgrep", "-P", str(first.pid)], capture_output=True,
                           text=True).stdout.split()
    try:
        assert len(ranks) == 2
        pid = _holder(out)["pid"]
        assert str(pid) in ranks                     # one of the ranks: rank 0
        rc, stderr = _second(out, case)
        _assert_refused(rc, stderr, out, pid)
        rc, stderr = _second(out, case, "--resume", ranks=2)
        _assert_refused(rc, stderr, out, pid, mpi=True)
    finally:
        _stop(first, ranks)
    assert not (out / "gsi.lock").exists()
