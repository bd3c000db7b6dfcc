"""The output directory of a run: owned by one run at a time (its lock,
:mod:`gsi.run.lock`), refused when it holds an earlier run's outputs, unless
``overwrite`` (removed first) or ``resume`` (continued)."""
from __future__ import annotations

import pathlib
import shutil

from gsi.errors import GsiInputError

#: what a run writes in its output directory: these directories (any one of them, or
#: summary.txt, marks an earlier run) and these top-level files; ``--overwrite`` removes
#: them and nothing else (a user's own files there stay)
OUTPUT_DIRS = ("particles", "walls", "monitors", "pictures", "checkpoints")
OUTPUT_FILES = ("summary.txt", "*.xdmf", "*.h5", "*_coupling.csv", "*_energy.csv",
                "history.csv", "*.pvd", "*.png", "*.gif")


def previous_outputs(out: pathlib.Path) -> list[pathlib.Path]:
    """The files and directories of an earlier run in ``out`` (none if ``out`` holds no
    OUTPUT_DIRS and no summary.txt: then it is not a run's directory)."""
    dirs = [out / d for d in OUTPUT_DIRS if (out / d).is_dir()]
    if not dirs and not (out / "summary.txt").is_file():
        return []
    files = sorted({f for pattern in OUTPUT_FILES for f in out.glob(pattern) if f.is_file()})
    return dirs + files


def output_dir(out, comm, *, overwrite: bool = False, resume: bool = False) -> pathlib.Path:
    """Create the output directory (rank 0) or raise a one-line error on every rank.

    A directory holding an earlier run's outputs (:func:`previous_outputs`) is refused
    unless ``overwrite``, which removes those outputs first (other files stay), so that no
    stale file of the earlier run is left in a series, or ``resume``, which continues them
    (the runner truncates each series to the checkpoint). No lock: see :func:`claim`."""
    return _output_dir(out, comm, overwrite=overwrite, resume=resume, lock=False)[0]


def claim(out, comm, *, overwrite: bool = False, resume: bool = False):
    """:func:`output_dir` under the directory's lock (:mod:`gsi.run.lock`), taken on rank 0
    before anything there is looked at or removed: returns ``(out, lock)``, the lock
    (:class:`gsi.run.lock.OutputLock`) on rank 0 and None elsewhere; release it when the
    run ends. A directory another live run owns is refused (one line, every rank)."""
    return _output_dir(out, comm, overwrite=overwrite, resume=resume, lock=True)


def _output_dir(out, comm, *, overwrite: bool, resume: bool, lock: bool):
    msg = held = None
    if out is None or str(out).strip() == "":
        msg = "--out = '': give an output directory"
    else:
        out = pathlib.Path(out)
        if comm.rank == 0:
            msg, held = _prepare(out, comm.rank, overwrite=overwrite, resume=resume,
                                 lock=lock)
    if comm.size > 1:
        msg = comm.bcast(msg, root=0)
    if msg:
        raise GsiInputError(msg)
    return out, held


def _prepare(out: pathlib.Path, rank: int, *, overwrite: bool, resume: bool, lock: bool):
    """Make ``out`` ready on rank 0: (the one-line error or None, the lock or None)."""
    from gsi.run.lock import LockRefused, acquire
    held = None
    try:
        out.mkdir(parents=True, exist_ok=True)
        if resume and overwrite:
            return "--resume and --overwrite: give one (continue or start again)", None
        if lock:
            held = acquire(out)
        old = previous_outputs(out)
        if old and not overwrite and not resume:
            msg = (f"--out = {str(out)!r}: holds the outputs of an earlier run "
                   f"({', '.join(f.name for f in old[:3])}{', ...' if len(old) > 3 else ''}); "
                   "add --overwrite to replace them or give another directory")
            return msg, _released(held)
        for f in old if overwrite and not resume else ():
            if f.is_dir():
                shutil.rmtree(f)
            else:
                f.unlink()
        probe = out / f".gsi-write-test-{rank}"
        probe.write_text("")
        probe.unlink()
        return None, held
    except LockRefused as exc:
        return str(exc), None
    except FileExistsError:
        msg = f"--out = {str(out)!r}: a file of that name exists; give a directory"
    except NotADirectoryError:
        msg = f"--out = {str(out)!r}: a parent is a file, not a directory"
    except PermissionError:
        msg = f"--out = {str(out)!r}: not writable; choose another directory"
    except OSError as exc:
        msg = f"--out = {str(out)!r}: cannot write there ({exc.strerror})"
    except BaseException:
        _released(held)
        raise
    return msg, _released(held)


def _released(lock) -> None:
    if lock is not None:
        lock.release()
    return None


def remove_temporaries(out) -> None:
    """Remove the ``<file>.tmp<pid>`` files a failed atomic write left under ``out``."""
    try:
        for f in pathlib.Path(out).rglob("*.tmp[0-9]*"):
            if f.is_file():
                f.unlink()
    except OSError:
        pass
