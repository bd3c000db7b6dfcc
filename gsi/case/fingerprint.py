"""The fingerprint of a case, stored in every checkpoint's manifest, and the keys a resumed
case changed (``gsi run --resume`` refuses a changed case unless ``--allow-changes``).

The fingerprint is the case as flat ``{key path: value}`` (``materials.glass.mu: 0.3``,
``particles[0].count: 2000``), without the keys that do not change the physics of the
remaining run (:data:`FREE`: progress lines, threads, checkpoint and picture options, the
description). The files the case references (``.file`` keys: particle files, mesh walls,
gmsh structures, with the files a ``.geo`` includes or merges) count by their contents:
``<key> (contents)`` holds the file's SHA-256, so
an edited file is a change although its name is the same. A checkpoint written before the
contents were fingerprinted lacks those keys; they are not compared then."""
from __future__ import annotations

import hashlib
import json
import pathlib
import re

__all__ = ["fingerprint", "changes", "check_resume", "FREE", "CONTENTS"]

#: keys a resumed run may change freely
FREE = ("case.description", "run.progress", "run.threads", "run.checkpoint_interval",
        "run.checkpoint_minutes", "output.pictures", "output.picture_every",
        "output.color_by", "output.view", "quick")


def _flat(value, prefix: str, out: dict) -> None:
    if isinstance(value, dict):
        for k, v in value.items():
            _flat(v, f"{prefix}.{k}" if prefix else str(k), out)
    elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
        for i, v in enumerate(value):
            _flat(v, f"{prefix}[{i}]", out)
    else:
        out[prefix] = json.loads(json.dumps(value, default=str))


def fingerprint(case) -> dict:
    """``{key path: value}`` of ``case`` (module docstring); JSON-serialisable."""
    from gsi.case.case import case_to_table
    out: dict = {}
    _flat(case_to_table(case), "", out)
    out = {k: v for k, v in out.items()
           if not any(k == f or k.startswith(f + ".") or k.startswith(f + "[") for f in FREE)}
    base = pathlib.Path(getattr(case, "base_dir", "."))
    for k, v in list(out.items()):
        if (k == "file" or k.endswith(".file")) and isinstance(v, str):
            out[k + CONTENTS] = _digest(base / v)
    return out


#: suffix of the key that holds a referenced file's digest
CONTENTS = " (contents)"


#: the files a gmsh script reads: ``Include "x.geo";``, ``Merge "y.step";``
_GEO_READS = re.compile(rb'^\s*(?:Include|Merge)\s*"([^"]+)"', re.MULTILINE)


def _digest(path: pathlib.Path, depth: int = 0) -> str:
    """``sha256:<hex>`` of a file's bytes (a ``.geo``: with the files it includes or
    merges, to 3 levels), or ``(no such file)``."""
    h = hashlib.sha256()
    try:
        with path.open("rb") as fh:
            data = fh.read()
    except OSError:
        return "(no such file)"
    h.update(data)
    if path.suffix.lower() == ".geo" and depth < 3:
        for name in _GEO_READS.findall(data):
            h.update(_digest(path.parent / name.decode("utf-8", "replace"), depth + 1).encode())
    return "sha256:" + h.hexdigest()


def changes(old: dict, new: dict) -> list[str]:
    """``key: old -> new`` for every key that differs (added or removed keys too)."""
    out = []
    for k in sorted(set(old) | set(new)):
        a, b = old.get(k, "(unset)"), new.get(k, "(unset)")
        if k.endswith(CONTENTS):
            if k in old and k in new and a != b:      # an older manifest lacks them
                said = ["(a file)" if x.startswith("sha256:") else x for x in (a, b)]
                out.append(f"{k}: the file was edited" if said == ["(a file)"] * 2 else
                           f"{k}: {said[0]} -> {said[1]}")
        elif a != b:
            out.append(f"{k}: {a} -> {b}")
    return out


def check_resume(case, out, *, quick: bool, allow: bool) -> list[str]:
    """Before ``gsi run --resume``: the keys of ``case`` (its quick form with ``quick``)
    changed since the newest checkpoint under ``out``; a one-line error listing them,
    or with ``allow`` a warning that lists them. Returns the changes (none when there is
    no checkpoint or it predates fingerprints: the resume reports those itself)."""
    import pathlib
    import warnings

    from gsi import checkpoint as ck
    from gsi.errors import GsiInputError
    info = ck.newest(pathlib.Path(out) / "checkpoints")
    if not info or not info.get("fingerprint"):
        return []
    now = fingerprint(case.quick_variant() if quick else case)
    found = changes(info["fingerprint"], now)
    if not found:
        return []
    listed = "; ".join(found[:8]) + (f"; and {len(found) - 8} more" if len(found) > 8 else "")
    if not allow:
        err = GsiInputError(f"--resume: the case changed since the checkpoint at t = "
                            f"{info['time']:.6g} s: {listed}; resume with the case that wrote "
                            f"it, or add --allow-changes to continue with the changes")
        err.agreed = True
        raise err
    warnings.warn(f"--allow-changes: resuming at t = {info['time']:.6g} s with {len(found)} "
                  f"changed key(s): {listed}", stacklevel=2)
    return found
