"""A stop request is honoured within seconds, whatever the output interval.

The case (data/long_chunk.toml): 1,500 beads poured into a box, DEM only, ONE output
interval for the whole run, so the steps between two outputs are one chunk. The runner
steps the DEM in blocks of about a quarter second of wall time and checks for a signal
between blocks (gsi.run.stepping); the split must not change the results.

* ``Simulation.step(a); step(b)`` is bit-identical to ``step(a + b)`` (DEM state), for
  this case and for the restart case (a stream inserter, a moving mesh wall, heat);
* with the run 100 s long (five million steps: hours of wall time, one chunk), SIGINT
  and SIGTERM stop ``gsi run`` within 5 s with the one-line message and a checkpoint of
  the step it stopped at (serially and under ``mpirun -n 2``);
* a run stopped in the middle of its only chunk (0.4 s long, so that the signal lands
  inside it on a fast host too) resumes to a final state and files
  bit-identical to the uninterrupted run.
"""
import importlib.util
import json
import os
import pathlib
import re
import signal
import time

import numpy as np
import pytest

_spec = importlib.util.spec_from_file_location(
    "gsi_tests_reliability_util", pathlib.Path(__file__).resolve().parent / "_util.py")
_util = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_util)

CASE = _util.HERE / "data" / "long_chunk.toml"
LIMIT = 5.0          # s from the signal to the end of the process
RESUMED = 0.4        # s of the run stopped and resumed: 4 s of wall time on a fast host,
                     # so the signal (0.5 s in) lands mid-chunk on a host 8 x faster too


def _long_case(directory, duration):
    text = CASE.read_text()
    assert "duration = 0.1\n" in text and "interval = 0.1\n" in text
    path = pathlib.Path(directory) / CASE.name
    path.write_text(text.replace("duration = 0.1\n", f"duration = {duration!r}\n")
                    .replace("interval = 0.1\n", f"interval = {duration!r}\n"))
    return path


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted run of data/long_chunk.toml (it also compiles the engine, so
    that the stop tests below do not wait for the compiler)."""
    base = tmp_path_factory.mktemp("long_chunk")
    _util.driver(base / "out", "--dump", str(base / "final"), case=_long_case(base, RESUMED))
    return base


@pytest.mark.parametrize("path, steps", [(CASE, 600), (_util.CASE, 800)],
                         ids=["long_chunk", "coupled_small"])
def test_steps_in_blocks_are_bitwise_one_call(path, steps):
    from gsi.case import load_case
    from gsi.case.build_dem import build_simulation
    case = load_case(path)

    def run(blocks):
        sim, _, _ = build_simulation(case, dt=case.check())
        done = 0
        for n in blocks:
            sim.step(n)
            done += n
        assert done == steps
        return sim.state(), sim.n_rebuilds
    one, rebuilds = run([steps])
    assert rebuilds > 1                       # the lists were rebuilt inside the call
    rng = np.random.default_rng(5)
    cuts = np.sort(rng.choice(np.arange(1, steps), size=12, replace=False))
    blocks = np.diff(np.concatenate([[0], cuts, [steps]])).tolist()
    split, again = run([1] * 7 + [steps - 7])
    assert again == rebuilds
    for state in (split, run(blocks)[0]):
        assert state.keys() == one.keys()
        for k in one:
            assert np.asarray(one[k]).tobytes() == np.asarray(state[k]).tobytes(), k


def _stop(out, case, sig, *, delay, ranks=None):
    """Start ``gsi run``, wait until its loop runs (the t = 0 output is written) and
    ``delay`` s more, send ``sig`` (under mpirun: to the ranks); returns (exit status,
    stderr, seconds from the signal to the end of the process)."""
    proc = _util.cli(out, ranks=ranks, case=case, start_new_session=True)
    _util.wait_for("particles/particles_000000.vtu", out, proc=proc)
    time.sleep(delay)
    if ranks:
        import subprocess
        pids = subprocess.run(["pgrep", "-P", str(proc.pid)], capture_output=True,
                              text=True).stdout.split()
        assert len(pids) == ranks
    else:
        pids = [proc.pid]
    t0 = time.perf_counter()
    for pid in pids:
        os.kill(int(pid), sig)
    _, stderr = proc.communicate(timeout=300)
    return proc.returncode, stderr, time.perf_counter() - t0


def _check_stopped(out, rc, stderr, seconds, sig, duration, ranks=1):
    assert rc == 128 + sig, stderr
    lines = [line for line in stderr.splitlines() if line.startswith("interrupted at t = ")]
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    assert seconds < LIMIT, f"stopped {seconds:.2f} s after the signal"
    t = float(lines[0].split()[4])
    assert 0 < t < duration                    # in the middle of the only chunk
    manifest = json.loads(sorted((out / "checkpoints").glob("*.json"))[-1].read_text())
    assert manifest["time"] == pytest.approx(t, rel=1e-5) and manifest["n_ranks"] == ranks
    assert not (out / "gsi.lock").exists()     # the lock went with the run
    print(f"\n{signal.Signals(sig).name} ({ranks} rank(s)): stopped {seconds:.2f} s after "
          f"the signal, at t = {t:g} s of {duration:g} s")


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_run_of_hours_in_one_chunk_stops_within_seconds(reference, tmp_path, sig):
    case = _long_case(tmp_path, 100.0)
    rc, stderr, seconds = _stop(tmp_path / "out", case, sig, delay=1.0)
    _check_stopped(tmp_path / "out", rc, stderr, seconds, sig, 100.0)
    assert re.search(r"resume with gsi run \S+long_chunk.toml --out \S+ --no-pictures "
                     r"--resume$", stderr.strip())


def test_under_mpirun_every_rank_stops_within_seconds(reference, tmp_path):
    case = _long_case(tmp_path, 100.0)
    rc, stderr, seconds = _stop(tmp_path / "out", case, signal.SIGTERM, delay=1.0, ranks=2)
    _check_stopped(tmp_path / "out", rc, stderr, seconds, signal.SIGTERM, 100.0, ranks=2)


def test_a_stop_in_the_middle_of_a_chunk_resumes_bitwise(reference, tmp_path):
    out = tmp_path / "out"
    case = reference / CASE.name               # the same file: the summary names it
    rc, stderr, seconds = _stop(out, case, signal.SIGTERM, delay=0.5)
    _check_stopped(out, rc, stderr, seconds, signal.SIGTERM, RESUMED)
    proc = _util.driver(out, "--resume", "--dump", str(tmp_path / "final"), case=case)
    assert "resumed at t = " in proc.stdout
    _util.assert_same_state(_util.dumps(reference / "final"), _util.dumps(tmp_path / "final"))
    _util.assert_same_files(reference / "out", out)
