"""Checkpoint files and crash-safe writes.

A checkpoint of a run (``gsi run ... --checkpoint-every S``, ``run.checkpoint_interval``,
``run.checkpoint_minutes``, or a SIGINT/SIGTERM) lives under ``DIR/checkpoints/``:

* ``ckpt_<step:010d>.rank<r>.npz``: one per MPI rank, plain numpy arrays (no pickles),
  written to a temporary name, fsync'ed and renamed (``os.replace``);
* ``ckpt_<step:010d>.json``: the manifest, written the same way by rank 0 only after
  every rank's file is complete: step, time (s), number of ranks, the case's DEM time
  step and each rank file's size. A checkpoint without its manifest, or whose files do
  not match it, is never "the newest valid" one.

The last two checkpoints are kept (older manifests are removed first, then their rank
files). :func:`newest` finds the newest valid checkpoint.

Crash-safe writes (:func:`write_atomic`): a file is written to ``<name>.tmp<pid>``,
fsync'ed and renamed over ``<name>``, so after a kill -9 at any moment it holds either its
old or its new contents. CSV series are appended one flushed row at a time; on resume
:func:`truncate_csv` cuts them back to the checkpoint's row count.
"""
from __future__ import annotations

import json
import os
import pathlib
import re

import numpy as np

__all__ = ["write_atomic", "write_npz", "read_npz", "write_manifest", "newest", "prune",
           "truncate_csv", "pack", "unpack", "KEEP"]

#: checkpoints kept
KEEP = 2
_MANIFEST = re.compile(r"^ckpt_(\d{10})\.json$")


def _fsync_dir(directory) -> None:
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def write_atomic(path, data, *, fsync: bool = True) -> None:
    """Write ``data`` (str or bytes) to ``path`` through a temporary file and a rename."""
    path = pathlib.Path(path)
    tmp = path.with_name(f"{path.name}.tmp{os.getpid()}")
    try:
        with open(tmp, "wb") as fh:
            fh.write(data.encode() if isinstance(data, str) else data)
            if fsync:
                fh.flush()
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    if fsync:
        _fsync_dir(path.parent)


def rank_file(directory, step: int, rank: int) -> pathlib.Path:
    return pathlib.Path(directory) / f"ckpt_{step:010d}.rank{rank}.npz"


def manifest_file(directory, step: int) -> pathlib.Path:
    return pathlib.Path(directory) / f"ckpt_{step:010d}.json"


def write_npz(path, arrays: dict) -> int:
    """Write ``arrays`` (name -> numpy array) as an uncompressed ``.npz`` atomically
    (:func:`write_atomic`: tmp + fsync + rename); returns its size in bytes."""
    import io
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    write_atomic(path, buf.getbuffer())
    return pathlib.Path(path).stat().st_size


def read_npz(path) -> dict:
    """The arrays of an ``.npz`` (no pickles allowed)."""
    with np.load(path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def write_manifest(directory, step: int, info: dict) -> None:
    """The manifest of checkpoint ``step`` (rank 0, after every rank file is complete)."""
    write_atomic(manifest_file(directory, step), json.dumps(dict(info, step=step), indent=1))


def _valid(directory, path) -> dict | None:
    try:
        info = json.loads(path.read_text())
        for r, size in enumerate(info["sizes"]):
            if rank_file(directory, info["step"], r).stat().st_size != size:
                return None
        return info
    except (OSError, ValueError, KeyError, TypeError):
        return None


def newest(directory) -> dict | None:
    """The manifest (dict) of the newest valid checkpoint under ``directory``, or None."""
    directory = pathlib.Path(directory)
    if not directory.is_dir():
        return None
    steps = sorted((int(m.group(1)), p) for p in directory.iterdir()
                   if (m := _MANIFEST.match(p.name)))
    for _, path in reversed(steps):
        info = _valid(directory, path)
        if info is not None:
            return info
    return None


def prune(directory, *, keep: int = KEEP) -> None:
    """Remove all but the newest ``keep`` checkpoints, and rank files and temporaries
    that belong to no manifest and are older than the newest one (rank 0)."""
    directory = pathlib.Path(directory)
    steps = sorted(int(m.group(1)) for p in directory.iterdir()
                   if (m := _MANIFEST.match(p.name)))
    kept = set(steps[-keep:])
    for s in steps[:-keep]:
        manifest_file(directory, s).unlink(missing_ok=True)
    newest_step = steps[-1] if steps else None
    for p in directory.iterdir():
        m = re.match(r"^ckpt_(\d{10})\.", p.name)
        if m is None:
            continue
        s = int(m.group(1))
        if s in kept and ".tmp" not in p.name:
            continue
        if newest_step is not None and s <= newest_step:
            p.unlink(missing_ok=True)


def clear_newer(directory, step: int) -> None:
    """Remove files of checkpoints after ``step`` (incomplete ones) and temporaries."""
    directory = pathlib.Path(directory)
    for p in directory.iterdir():
        m = re.match(r"^ckpt_(\d{10})\.", p.name)
        if m is not None and (int(m.group(1)) > step or ".tmp" in p.name):
            p.unlink(missing_ok=True)


def truncate_csv(path, n_rows: int) -> None:
    """Keep the header and the first ``n_rows`` complete rows of a CSV (atomically)."""
    path = pathlib.Path(path)
    if not path.exists():
        return
    lines = path.read_bytes().split(b"\n")
    keep = lines[: 1 + n_rows]
    if len(keep) < 1 + n_rows:
        raise OSError(f"{path}: holds {len(lines) - 1} rows, the checkpoint expects {n_rows}")
    write_atomic(path, b"\n".join(keep) + b"\n")


def pack(obj, arrays: dict, prefix: str):
    """A JSON-able skeleton of a nested dict/list of arrays, numbers, strings, paths and
    None; the arrays go to ``arrays[prefix + i]`` (for picture jobs in checkpoints)."""
    if isinstance(obj, dict):
        return {"d": {str(k): pack(v, arrays, prefix) for k, v in obj.items()}}
    if isinstance(obj, (list, tuple)):
        return {"l": [pack(v, arrays, prefix) for v in obj]}
    if isinstance(obj, np.ndarray):
        key = f"{prefix}{len(arrays)}"
        while key in arrays:
            key += "_"
        arrays[key] = obj
        return {"a": key}
    if isinstance(obj, np.generic):
        return {"v": obj.item()}
    if isinstance(obj, pathlib.PurePath):
        return {"p": str(obj)}
    return {"v": obj}


def unpack(skeleton, arrays: dict):
    """Inverse of :func:`pack`."""
    (kind, v), = skeleton.items()
    if kind == "d":
        return {k: unpack(x, arrays) for k, x in v.items()}
    if kind == "l":
        return [unpack(x, arrays) for x in v]
    if kind == "a":
        return arrays[v]
    if kind == "p":
        return pathlib.Path(v)
    return v
