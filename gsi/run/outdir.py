"""The output directory of a run: refused when it holds an earlier run's outputs, unless
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
    (the runner truncates each series to the checkpoint)."""
    msg = None
    if out is None or str(out).strip() == "":
        msg = "--out = '': give an output directory"
    else:
        out = pathlib.Path(out)
        if comm.rank == 0:
            msg = _prepare(out, comm.rank, overwrite=overwrite, resume=resume)
    if comm.size > 1:
        msg = comm.bcast(msg, root=0)
    if msg:
        raise GsiInputError(msg)
    return out


def _prepare(out: pathlib.Path, rank: int, *, overwrite: bool, resume: bool) -> str | None:
    """Make ``out`` ready on rank 0; the one-line error, or None."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        old = previous_outputs(out)
        if resume and overwrite:
            return "--resume and --overwrite: give one (continue or start again)"
        if old and not overwrite and not resume:
            return (f"--out = {str(out)!r}: holds the outputs of an earlier run "
                    f"({', '.join(f.name for f in old[:3])}{', ...' if len(old) > 3 else ''}); "
                    "add --overwrite to replace them or give another directory")
        for f in old if overwrite and not resume else ():
            if f.is_dir():
                shutil.rmtree(f)
            else:
                f.unlink()
        probe = out / f".gsi-write-test-{rank}"
        probe.write_text("")
        probe.unlink()
    except FileExistsError:
        return f"--out = {str(out)!r}: a file of that name exists; give a directory"
    except NotADirectoryError:
        return f"--out = {str(out)!r}: a parent is a file, not a directory"
    except PermissionError:
        return f"--out = {str(out)!r}: not writable; choose another directory"
    except OSError as exc:
        return f"--out = {str(out)!r}: cannot write there ({exc.strerror})"
    return None


def remove_temporaries(out) -> None:
    """Remove the ``<file>.tmp<pid>`` files a failed atomic write left under ``out``."""
    try:
        for f in pathlib.Path(out).rglob("*.tmp[0-9]*"):
            if f.is_file():
                f.unlink()
    except OSError:
        pass
