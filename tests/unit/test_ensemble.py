"""gsi.studies.ensemble: ensemble members run in worker processes give bitwise what they
give in this process, and a failing member surfaces as one clear error (not a hang)."""
import os
import pathlib

import numpy as np
import pytest

from gsi.errors import GsiInputError
from gsi.studies.ensemble import EnsembleError, default_workers, perturb, run_ensemble

CASE5 = pathlib.Path(__file__).resolve().parents[2] / "demos" / "graded" / "case5_hot_block.toml"


def _dem_member(k, start, steps):
    """Member k of seed 001 case 5 (49 particles falling, conducting): positions,
    temperatures and the numba thread count after ``steps`` steps from ``start``."""
    import numba
    from gsi.case import load_case
    from gsi.case.build_dem import build_simulation
    case = load_case(CASE5)
    sim, _, _ = build_simulation(case, dt=case.check())
    sim.set_state(start)
    perturb(sim.x, k, "xz")
    sim.step(steps)
    return dict(x=sim.x.copy(), T=sim.T.copy(), threads=numba.get_num_threads(), pid=os.getpid())


def _fails(k):
    if k == 1:
        raise ValueError("member one is broken")
    return k


def _dies(k):
    if k == 1:
        os._exit(3)                 # a crash, not an exception
    return k


@pytest.fixture(scope="module")
def start():
    from gsi.case import load_case
    from gsi.case.build_dem import build_simulation
    case = load_case(CASE5)
    sim, _, _ = build_simulation(case, dt=case.check())
    sim.step(200)                    # the shared set-up stays in the parent
    return sim.state()


def test_a_member_in_a_worker_is_bitwise_the_member_in_process(start):
    here = run_ensemble(_dem_member, [0, 1, 2], args=(start, 1500), workers=1)
    # member 0 in this process, 1 and 2 in one worker (or 2 taken over by this process)
    mixed = run_ensemble(_dem_member, [0, 1, 2], args=(start, 1500), workers=2, here=[0])
    for a, c in zip(here, mixed):
        assert np.array_equal(a["x"], c["x"]) and np.array_equal(a["T"], c["T"])
    assert mixed[0]["pid"] == os.getpid() and mixed[1]["pid"] != os.getpid()
    assert mixed[1]["threads"] == 1
    # the members are distinct realisations of the same flow (1500 steps from one state)
    assert not np.array_equal(here[0]["x"], here[2]["x"])
    assert np.abs(here[0]["x"] - here[2]["x"]).max() < 1e-3


@pytest.mark.parametrize("workers", [1, 2])
def test_a_failing_member_is_one_clear_error(workers):
    with pytest.raises(EnsembleError, match="member 1 failed: ValueError: member one is broken"):
        run_ensemble(_fails, 3, workers=workers)
    assert run_ensemble(_fails, [0, 2, 3], workers=workers) == [0, 2, 3]


def test_a_crashed_worker_is_an_error_not_a_hang():
    # the member named is the first whose future broke: member 1, or member 0 when its
    # worker was still starting as the pool broke (it did under load)
    with pytest.raises(EnsembleError, match=r"member [01] failed: BrokenProcessPool.*a worker died"):
        run_ensemble(_dies, 3, workers=2)


def test_fork_is_refused_and_workers_default_to_the_cores(monkeypatch):
    with pytest.raises(GsiInputError, match="start_method = 'fork'"):
        run_ensemble(_fails, 2, start_method="fork")
    monkeypatch.setenv("NUMBA_NUM_THREADS", "3")
    assert default_workers() == 3
    monkeypatch.delenv("NUMBA_NUM_THREADS")
    assert default_workers() == max(1, os.cpu_count() or 1)


_ORPHAN_SCRIPT = """
import os, sys, time
from gsi.studies.ensemble import run_ensemble

def member(k, out):
    open(os.path.join(out, f"{k}.pid"), "w").write(str(os.getpid()))
    time.sleep(120)

if __name__ == "__main__":
    run_ensemble(member, 2, args=(sys.argv[1],), workers=2)
"""


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return pathlib.Path(f"/proc/{pid}/stat").read_text().split()[2] != "Z"


@pytest.mark.skipif(not os.sys.platform.startswith("linux"), reason="prctl is Linux's")
def test_workers_die_with_a_killed_parent(tmp_path):
    """A killed ensemble leaves no worker behind (they die with their parent, even inside
    a long call), so a killed test or study does not load the machine for minutes."""
    import signal
    import subprocess
    import sys
    import time
    script = tmp_path / "orphans.py"
    script.write_text(_ORPHAN_SCRIPT)
    parent = subprocess.Popen([sys.executable, str(script), str(tmp_path)],
                              cwd=pathlib.Path(__file__).resolve().parents[2])
    try:
        deadline = time.time() + 120
        while len(list(tmp_path.glob("*.pid"))) < 2 and time.time() < deadline:
            time.sleep(0.2)
        pids = [int(p.read_text()) for p in tmp_path.glob("*.pid")]
        assert len(pids) == 2 and all(_alive(p) for p in pids)
    finally:
        parent.send_signal(signal.SIGKILL)
        parent.wait()
    deadline = time.time() + 10
    while any(_alive(p) for p in pids) and time.time() < deadline:
        time.sleep(0.1)
    assert not any(_alive(p) for p in pids)
