"""Particle and wall output as VTK XML files that ParaView opens (no VTK dependency).

- :class:`PvdSeries` is a ParaView time series ``<prefix>.pvd`` of ``<prefix>_<k>.vtu``
  files (rewritten atomically after every file; an earlier run's continued with ``times``).
- :class:`ParticleWriter` writes one ``<prefix>_<k>.vtu`` per call of ``write(sim)`` (an
  UnstructuredGrid of vertex cells) with point data radius, velocity, speed, omega,
  temperature, type, contact_count, id, and rewrites ``<prefix>.pvd`` (the time series)
  after every write (atomically), so a crash loses nothing already written.
- :func:`write_wall_vtu` writes the triangles of a mesh wall with point data
  vertex_velocity, vertex_impulse, vertex_heat (and vertex_temperature) and cell data
  triangle_force.
- :func:`write_surface_vtu` writes any triangulation (e.g. ``Wall.surface()`` of a case
  wall, planes included) with optional point data.

Arrays are written inline as base64 binary (``format="binary"``, UInt64 headers).
"""
import base64
import os
import pathlib
import re

import numpy as np

_VTK_TYPES = {np.dtype(np.float64): "Float64", np.dtype(np.float32): "Float32",
              np.dtype(np.int32): "Int32", np.dtype(np.int64): "Int64",
              np.dtype(np.uint8): "UInt8"}


def _data_array(name, arr):
    arr = np.ascontiguousarray(arr)
    if arr.dtype not in _VTK_TYPES:
        arr = arr.astype(np.float64)
    ncomp = "" if arr.ndim == 1 else f'NumberOfComponents="{arr.shape[1]}" '
    raw = arr.tobytes()
    payload = base64.b64encode(np.uint64(len(raw)).tobytes() + raw).decode("ascii")
    return (f'<DataArray type="{_VTK_TYPES[arr.dtype]}" Name="{name}" '
            f'{ncomp}format="binary">{payload}</DataArray>')


def _unstructured(points, conn, offsets, types, point_data, cell_data):
    pd = "".join(_data_array(k, v) for k, v in point_data.items())
    cd = "".join(_data_array(k, v) for k, v in cell_data.items())
    return (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
        'header_type="UInt64">\n<UnstructuredGrid>\n'
        f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{len(types)}">\n'
        f'<PointData>{pd}</PointData>\n<CellData>{cd}</CellData>\n'
        f'<Points>{_data_array("Points", np.asarray(points, np.float64).reshape(-1, 3))}</Points>\n'
        '<Cells>'
        f'{_data_array("connectivity", np.asarray(conn, np.int64))}'
        f'{_data_array("offsets", np.asarray(offsets, np.int64))}'
        f'{_data_array("types", np.asarray(types, np.uint8))}'
        '</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n')


def write_text_atomic(path, text):
    """Write ``text`` to ``path`` through a temporary file ``<path>.tmp<pid>``."""
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w") as fh:
        fh.write(text)
    os.replace(tmp, path)


def write_particles_vtu(path, sim):
    """One snapshot of the particles of ``sim`` as a .vtu file."""
    n = sim.n
    pd = {
        "radius": sim.radius, "velocity": sim.v, "speed": np.linalg.norm(sim.v, axis=1),
        "omega": sim.omega, "temperature": sim.T, "type": sim.type.astype(np.int32),
        "contact_count": sim.ncontact.astype(np.int32), "id": sim.ids.astype(np.int64),
    }
    write_text_atomic(path, _unstructured(sim.x, np.arange(n), np.arange(1, n + 1),
                                      np.ones(n, np.uint8), pd, {}))


def write_wall_vtu(path, wall):
    """A mesh wall's triangles and their coupling data as a .vtu file."""
    tri = wall.triangles
    pd = {"vertex_velocity": wall.vertex_velocity, "vertex_impulse": wall.vertex_impulse,
          "vertex_heat": wall.vertex_heat}
    if wall.vertex_temperature is not None:
        pd["vertex_temperature"] = wall.vertex_temperature
    write_text_atomic(path, _unstructured(wall.vertices, tri.ravel(), 3 * np.arange(1, len(tri) + 1),
                                      np.full(len(tri), 5, np.uint8), pd,
                                      {"triangle_force": wall.triangle_force}))


def write_surface_vtu(path, vertices, triangles, *, point_data=None):
    """Triangles (nt, 3) over ``vertices`` (nv, 3) (m) as a .vtu file, with optional
    ``point_data`` {name: (nv,) or (nv, k) array}."""
    tri = np.asarray(triangles, np.int64)
    write_text_atomic(path, _unstructured(vertices, tri.ravel(), 3 * np.arange(1, len(tri) + 1),
                                      np.full(len(tri), 5, np.uint8), dict(point_data or {}), {}))


class PvdSeries:
    """A ParaView series ``<directory>/<prefix>.pvd`` of ``<prefix>_<k>.vtu`` files.

    ``times`` (optional): continue an earlier run's series, keeping its first len(times)
    entries and removing its later files (and temporaries); else start an empty one.
    """

    def __init__(self, directory, prefix: str, *, times=None):
        self.dir = pathlib.Path(directory)
        self.dir.mkdir(parents=True, exist_ok=True)
        self.prefix = prefix
        self.pvd = self.dir / f"{prefix}.pvd"
        self.entries = []
        if times is None:
            self.write_pvd()
        else:
            self.restore(times)

    def next_path(self) -> pathlib.Path:
        """The path of the next file of the series."""
        return self.dir / f"{self.prefix}_{len(self.entries):06d}.vtu"

    def add(self, t: float, path) -> None:
        """Enter the written file ``path`` at time ``t`` (s) and rewrite the .pvd."""
        self.entries.append((float(t), pathlib.Path(path).name))
        self.write_pvd()

    def times(self):
        """The times (s) of the entries so far."""
        return np.array([t for t, _ in self.entries], np.float64)

    def restore(self, times) -> None:
        """Keep the first len(times) entries of an earlier series; remove later files."""
        times = [float(t) for t in times]
        self.entries = [(t, f"{self.prefix}_{i:06d}.vtu") for i, t in enumerate(times)]
        pattern = re.compile(rf"^{re.escape(self.prefix)}_(\d{{6}})\.vtu")
        for p in self.dir.iterdir():
            m = pattern.match(p.name)
            if (m is not None and int(m.group(1)) >= len(times)) or re.search(r"\.tmp\d+$",
                                                                               p.name):
                p.unlink(missing_ok=True)
        self.write_pvd()

    def write_pvd(self) -> None:
        """Rewrite ``<prefix>.pvd`` from the entries (atomically)."""
        rows = "".join(f'<DataSet timestep="{t:.12g}" part="0" file="{f}"/>\n'
                       for t, f in self.entries)
        write_text_atomic(self.pvd, '<?xml version="1.0"?>\n<VTKFile type="Collection" '
                          f'version="0.1">\n<Collection>\n{rows}</Collection>\n</VTKFile>\n')


class ParticleWriter(PvdSeries):
    """Series of particle snapshots ``<out_dir>/<prefix>_<k>.vtu`` and ``<prefix>.pvd``.

    Parameters
    ----------
    out_dir : str or path
        Directory (created).
    prefix : str, default "particles"
    times : sequence of float, optional
        Continue an earlier series (see :class:`PvdSeries`).
    """

    def __init__(self, out_dir, prefix="particles", *, times=None):
        super().__init__(out_dir, prefix, times=times)

    def write(self, sim):
        """Write a snapshot at ``sim.time`` and update the .pvd; returns the .vtu path."""
        path = self.next_path()
        write_particles_vtu(path, sim)
        self.add(sim.time, path)
        return path

    def close(self):
        """Finish the series (the .pvd is already complete after every write)."""
        self.write_pvd()
