"""Particle files of a ``fill = "file"`` source: CSV or VTU of positions, radii and
optionally velocities and temperatures (:func:`read_particle_file`)."""
from __future__ import annotations

import csv
import pathlib

import numpy as np

from gsi.errors import GsiInputError


def read_particle_file(path, *, key: str = "file", shown: str | None = None) -> dict:
    """Particles of a CSV or VTU file (see the module docstring); errors name ``key`` and
    the file as ``shown`` (default: ``path``).

    Returns
    -------
    dict
        ``x`` (k, 3) m, ``radius`` (k,) m, ``v`` (k, 3) m/s or None, ``T`` (k,) or None.
    """
    path = pathlib.Path(path)
    key = f"{key} = '{path if shown is None else shown}'"
    if not path.is_file():
        raise GsiInputError(f"{key}: no such file (looked in {path.parent.resolve()})")
    suffix = path.suffix.lower()
    if suffix == ".csv":
        out = _read_csv(path, key)
    elif suffix == ".vtu":
        out = _read_vtu(path, key)
    else:
        raise GsiInputError(f"{key}: must end in .csv or .vtu")
    x, r = out["x"], out["radius"]
    if len(x) == 0:
        raise GsiInputError(f"{key}: holds no particles")
    if not (np.isfinite(x).all() and np.isfinite(r).all() and (r > 0).all()):
        raise GsiInputError(f"{key}: positions must be finite and radii > 0 (m)")
    if out["T"] is not None and len(out["T"]):
        from gsi.config.schema import SANE
        for T in (float(np.min(out["T"])), float(np.max(out["T"]))):
            found = SANE["K"].verdict(T, "K") if T > 0 else ("error", "must be > 0 (K)")
            if found is not None and found[0] == "error":
                raise GsiInputError(f"{key}: column T holds {T:g}: {found[1]}")
    return out


def _read_csv(path, key) -> dict:
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:   # a BOM (Excel) is read
            rows = list(csv.reader(row for row in fh if row.strip() and not row.startswith("#")))
    except (OSError, UnicodeDecodeError) as exc:
        raise GsiInputError(f"{key}: cannot read ({exc})") from None
    if not rows:
        raise GsiInputError(f"{key}: empty; needs a header x,y,z,radius")
    head = [h.strip() for h in rows[0]]
    missing = [c for c in ("x", "y", "z", "radius") if c not in head]
    if missing:
        raise GsiInputError(f"{key}: header {head} lacks {', '.join(missing)}; "
                            "columns x,y,z,radius (m) and optional vx,vy,vz,T")
    for k, row in enumerate(rows[1:]):
        if len(row) != len(head) or any(not v.strip() for v in row):
            given = sum(1 for v in row if v.strip())
            raise GsiInputError(f"{key}: data row {k + 1} has {given} values but the header "
                                f"names {len(head)} columns ({','.join(head)}); give every "
                                f"row all of them, or drop the column from the header")
    try:
        data = np.array([[float(v) for v in row] for row in rows[1:]], float).reshape(-1, len(head))
    except ValueError as exc:
        raise GsiInputError(f"{key}: not numbers after the header ({exc})") from None
    col = {h: data[:, i] for i, h in enumerate(head)}
    has_v = all(c in col for c in ("vx", "vy", "vz"))
    return {"x": np.column_stack([col["x"], col["y"], col["z"]]), "radius": col["radius"],
            "v": np.column_stack([col["vx"], col["vy"], col["vz"]]) if has_v else None,
            "T": col.get("T")}


def _read_vtu(path, key) -> dict:
    import meshio

    from gsi.readers import ReadFailed, guarded
    try:
        m = guarded(meshio.read, path)
    except ReadFailed as exc:      # meshio raises many kinds, SystemExit included
        raise GsiInputError(f"{key}: meshio cannot read it ({exc})") from None
    pd = m.point_data
    if "radius" not in pd:
        raise GsiInputError(f"{key}: no point data 'radius' (has: "
                            f"{', '.join(pd) or 'none'})")
    T = pd.get("T", pd.get("temperature"))
    v = pd.get("velocity")
    return {"x": np.asarray(m.points, float)[:, :3], "radius": np.asarray(pd["radius"], float).ravel(),
            "v": None if v is None else np.asarray(v, float).reshape(-1, 3),
            "T": None if T is None else np.asarray(T, float).ravel()}
