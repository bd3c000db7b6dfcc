"""Ensembles: how gsi judges a chaotic flow, and how their members run side by side.

A granular flow is chaotic: a change in the last bit of one position (another CPU's
floating-point summation order, another thread count) grows to a different trajectory
within a fraction of a second. A claim about such a flow is a claim about the
distribution of its trajectories, so it is judged on an *ensemble*: ``M`` realisations of
the same case that differ only by sub-nanometre start perturbations (:func:`perturb`),
the claim made on the ensemble mean with a bound set by its standard error
(``tests/validation/conftest.py``, docs/design.md "Chaotic cases: ensembles").

The members of an ensemble are independent, so :func:`run_ensemble` runs them in a pool
of worker processes, one member per worker at a time, each worker with one numba thread.
A small system (below :class:`gsi.dem.Simulation`'s ``parallel_min_n``) steps on one
thread anyway, so on a machine with two cores two members run in about the time of one.
Shared set-up (a settling before the members diverge) is done once by the caller and
passed to every member as plain arrays (:meth:`gsi.dem.Simulation.state`).

Choices (costs measured in :func:`run_ensemble`'s docstring):

- **start method ``spawn``** (default; ``forkserver`` is accepted): a worker is a fresh
  interpreter that imports gsi and loads the cached numba engines itself. ``fork`` is
  refused: after numba's threading layer (TBB/OpenMP/workqueue) has started in the parent,
  a forked child inherits its locks but not its threads and can hang in its first
  parallel region; MPI (dolfinx) in a forked child is equally unsafe.
- **one numba thread per worker**: ``NUMBA_NUM_THREADS=1`` is set in each worker before
  numba is imported there, so two workers do not oversubscribe two cores; a member below
  ``parallel_min_n`` runs the same serial code in a worker as in-process, so its result is
  bitwise the same (tests/unit/test_ensemble.py).
- **what crosses the process boundary**: the member function and its arguments are
  pickled (a module-level function: tests define theirs at module level), and so is its
  return value; a member returns only the arrays its test needs, not the simulation.
- **errors**: the first member that raises stops the ensemble: the members not yet
  started are cancelled and :class:`EnsembleError` names the member and carries the
  worker's traceback; a worker that dies (a crash, not an exception) raises the same
  error, never a hang.
"""
from __future__ import annotations

import os
from typing import Callable, Iterable, Sequence

import numpy as np

__all__ = ["EnsembleError", "SHIFT", "default_workers", "perturb", "run_ensemble"]

#: sub-nanometre start perturbation per member index (m): member k moves every particle
#: by up to k x SHIFT per coordinate (:func:`perturb`)
SHIFT = 0.5e-9

#: start methods that are safe after numba's threading layer or MPI have started
SAFE_START_METHODS = ("spawn", "forkserver")


class EnsembleError(RuntimeError):
    """A member of an ensemble failed (its index in :attr:`member`)."""

    def __init__(self, member: int, message: str):
        super().__init__(f"ensemble member {member} failed: {message}")
        self.member = member


def perturb(x: np.ndarray, k: int, plane: str = "xyz", shift: float = SHIFT) -> None:
    """Move positions ``x`` (n, 3), in place, by member ``k``'s perturbation: ``k`` x
    ``shift`` times a uniform random number in [-1, 1] per coordinate of ``plane`` (numpy
    generator seeded ``k``; the other coordinates stay, so a quasi-2D case keeps its
    plane). Member 0 is the case as it is. 0.5 nm is far below any physical scale of a
    granular flow yet far above round-off, so the members are independent samples."""
    if k == 0:
        return
    rng = np.random.default_rng(k)
    d = shift * k * rng.uniform(-1.0, 1.0, x.shape)
    for axis in range(3):
        if "xyz"[axis] not in plane:
            d[:, axis] = 0.0
    x += d


def default_workers() -> int:
    """``GSI_ENSEMBLE_WORKERS`` if set (``1``: every member in-process, e.g. to time or
    debug them), else ``NUMBA_NUM_THREADS`` if set (the cores this process was given),
    else ``os.cpu_count()``."""
    for key in ("GSI_ENSEMBLE_WORKERS", "NUMBA_NUM_THREADS"):
        env = os.environ.get(key, "").strip()
        if env.isdigit() and int(env) > 0:
            return int(env)
    return max(1, os.cpu_count() or 1)


#: the environment of every worker (set while the workers start, inherited by them)
WORKER_ENV = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}


def _worker_init(parent: int) -> None:
    """Runs first in every worker: it dies with ``parent`` (:func:`_die_with`), and runs
    one numba thread even if numba was imported before the environment took effect (a
    ``__main__`` that imports gsi.dem)."""
    import sys
    _die_with(parent)
    if "numba" in sys.modules:
        sys.modules["numba"].set_num_threads(1)


def _die_with(parent: int) -> None:
    """On Linux, have the kernel kill this worker when the process that started it dies
    (``prctl(PR_SET_PDEATHSIG, SIGKILL)``): a killed ensemble must not leave workers
    running inside a numba call, where Python's own checks for a lost parent never run
    (they ran on for minutes). ``parent`` is that process's id (0: not checked, as for
    forkserver, whose workers' parent is the server): a parent already gone ends the
    worker at once."""
    import signal
    import sys
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes
        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL), 0, 0, 0)
    except (OSError, AttributeError):
        return
    if parent and os.getppid() != parent:
        os._exit(1)


def _call(member: Callable, k: int, args: tuple, kwargs: dict):
    return member(k, *args, **kwargs)


def run_ensemble(member: Callable, indices: Iterable[int] | int, *, args: Sequence = (),
                 kwargs: dict | None = None, workers: int | None = None,
                 here: Sequence[int] = (), start_method: str = "spawn") -> list:
    """``[member(k, *args, **kwargs) for k in indices]``, the members run side by side.

    Parameters
    ----------
    member : callable
        A module-level function (it is pickled by name into the workers) of the member
        index ``k`` and ``args``/``kwargs``; it returns what the caller needs of member
        ``k`` (plain arrays and numbers: the return value is pickled back).
    indices : iterable of int, or int
        The member indices (an int M means ``range(M)``).
    args, kwargs
        Passed to every member (pickled once per member): the shared set-up, e.g. a
        simulation's :meth:`~gsi.dem.Simulation.state` after a settling.
    workers : int, optional
        Worker processes (default :func:`default_workers`, at most one per member).
        ``workers=1`` runs the members here, one after the other, in this process.
    here : sequence of int
        Members run in this process (while the workers run the others; the workers
        count this process as one of them): their results are not pickled, so they may
        hold what cannot cross a process boundary (a runner with its FE structures).
    start_method : {"spawn", "forkserver"}
        How workers start (module docstring: ``fork`` is not safe after numba's threads).

    Returns
    -------
    list
        The members' results in the order of ``indices``.

    Raises
    ------
    EnsembleError
        The first member that failed (the others are cancelled), with its traceback.

    Cost, measured on a 2-core machine at load 4-8 (other jobs): a pool of two spawned
    workers running an empty member costs 0.8 s; importing gsi's case and DEM packages
    and loading the cached engine adds 4-5 s per worker (once per worker, not per
    member; about 2.7 s of it is the import). Paired runs of the same tests with 1 and 2
    workers at load 4: seed 001 case 5 (5 members of about 3 s) 20.1 -> 10.7 s; the
    grate demo's 3 fills 10.8 -> 9.9 s; cases 6/7 (6 members) 124 -> 120 s; the quick
    drum (4 members of about 28 s CPU) 115 -> 119 s at load 3, where the two workers got
    101 % of a core between them (120.7 s CPU): the gain needs a second core that other
    jobs leave free; the price is the workers' start, about 5 s of CPU each.
    """
    ks = list(range(indices)) if isinstance(indices, (int, np.integer)) else list(indices)
    kwargs = dict(kwargs or {})
    if start_method not in SAFE_START_METHODS:
        from gsi.errors import GsiInputError
        raise GsiInputError(f"start_method = {start_method!r}: use one of "
                            f"{', '.join(SAFE_START_METHODS)} (fork is unsafe once numba's "
                            "threading layer or MPI has started)")
    n = default_workers() if workers is None else int(workers)
    n = max(1, min(n, len(ks)))
    local = [k for k in ks if n == 1 or k in set(here)]
    remote = [k for k in ks if k not in set(local)]
    pool_size = min(len(remote), n - 1 if local else n)
    if pool_size == 0:
        local, remote = list(ks), []
    results = {}
    pool, futures = (_start(member, remote, args, kwargs, pool_size, start_method)
                     if remote else (None, []))
    try:
        while local:
            k = local.pop(0)
            try:
                results[k] = member(k, *args, **kwargs)
            except Exception as exc:
                raise EnsembleError(k, f"{type(exc).__name__}: {exc}") from exc
            # then take over a member the workers have not started (this process is free)
            for i in range(len(futures) - 1, -1, -1):
                if futures[i].cancel():
                    local.append(remote.pop(i))
                    futures.pop(i)
                    break
        if futures:
            from concurrent.futures import FIRST_EXCEPTION, wait
            wait(futures, return_when=FIRST_EXCEPTION)
            for k, f in zip(remote, futures):
                if f.done() and f.exception() is not None:
                    exc = f.exception()
                    raise EnsembleError(k, f"{type(exc).__name__}: {exc}{_hint(exc)}") from exc
            results.update((k, f.result()) for k, f in zip(remote, futures))
    finally:
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)
    return [results[k] for k in ks]


def _hint(exc) -> str:
    """What a worker that died usually means (a spawned worker re-imports the calling
    script: run at its top level, ``run_ensemble`` starts again inside the worker)."""
    from concurrent.futures.process import BrokenProcessPool
    if not isinstance(exc, BrokenProcessPool):
        return ""
    return ("; a worker died: if this is a script, put its top-level code under "
            "`if __name__ == \"__main__\":` (workers re-import it), or run with "
            "GSI_ENSEMBLE_WORKERS=1 to see the member's own error")


def _start(member, ks, args, kwargs, n, start_method):
    """A pool of ``n`` workers with the members ``ks`` submitted: (pool, futures)."""
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor
    pool = ProcessPoolExecutor(n, mp_context=mp.get_context(start_method),
                               initializer=_worker_init,
                               initargs=(os.getpid() if start_method == "spawn" else 0,))
    saved = {key: os.environ.get(key) for key in WORKER_ENV}
    os.environ.update(WORKER_ENV)          # the workers start in submit() and inherit it
    try:
        futures = [pool.submit(_call, member, k, tuple(args), kwargs) for k in ks]
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    finally:
        for key, v in saved.items():
            if v is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = v
    return pool, futures
