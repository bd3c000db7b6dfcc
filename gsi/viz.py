"""Pictures: off-screen pyvista snapshots, matplotlib time plots and GIF animations.

Everything here renders without a display. pyvista is optional: without it the snapshot
functions print one warning and return ``None`` (the run's data files are unaffected).
"""
from __future__ import annotations

import os
import pathlib
import sys
import warnings
from typing import Iterable, Sequence

import numpy as np

# Use VTK's OSMesa window when there is no X display (no 'bad X server' warnings).
if not os.environ.get("DISPLAY"):
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")


def _preload_vtk() -> bool:
    """Import pyvista now if dolfinx is not loaded yet; True when that succeeded.

    VTK's wheel and Debian's dolfinx bring different C++ runtimes: when dolfinx's extension
    is loaded first, VTK's scalar bars abort the process (``std::bad_alloc`` in
    ``std::regex``); with VTK loaded first both work. Drivers import this module before
    dolfinx, so their pictures render in-process.
    """
    if "dolfinx" in sys.modules:
        return False
    try:
        import pyvista  # noqa: F401
    except Exception:
        return False
    return True


#: True when VTK was loaded before dolfinx in this process (in-process rendering is safe)
VTK_BEFORE_DOLFINX = _preload_vtk()


def _pyvista():
    try:
        import pyvista as pv
    except Exception as exc:  # optional dependency
        warnings.warn(f"pyvista not available ({exc}); skipping pictures", stacklevel=3)
        return None
    pv.OFF_SCREEN = True
    return pv


def particles_polydata(pv, x: np.ndarray, radius: np.ndarray, scalars: dict[str, np.ndarray]):
    """Points with radius and scalars, glyphed as spheres scaled by diameter."""
    cloud = pv.PolyData(np.ascontiguousarray(x, dtype=float))
    cloud["diameter"] = 2.0 * np.asarray(radius, dtype=float)
    for name, value in scalars.items():
        cloud[name] = np.asarray(value)
    return cloud.glyph(scale="diameter", geom=pv.Sphere(theta_resolution=10, phi_resolution=10),
                       orient=False)


def snapshot(path: str | pathlib.Path, **job) -> pathlib.Path | None:
    """Render particles over triangle surfaces to a PNG (see :func:`_snapshot_here`).

    Safe in any process: when dolfinx is loaded it renders in a spawned interpreter
    (:func:`render_snapshots`).
    """
    return render_snapshots([dict(job, path=path)])[0]


def _snapshot_here(path: str | pathlib.Path, *, x: np.ndarray, radius: np.ndarray,
             color_by: str = "speed", values: np.ndarray | None = None, clim=None,
             surfaces: Sequence[dict] = (), camera: dict | None = None,
             box: tuple | None = None,
             title: str = "", window_size=(1024, 768)) -> pathlib.Path | None:
    """Render particles (coloured by ``values``) over triangle surfaces to a PNG.

    Parameters
    ----------
    surfaces : list of dict with ``points`` (n,3), ``triangles`` (m,3), optional ``values`` (n,)
        and ``name`` (scalar bar title), ``opacity``, ``clim``, ``cmap``.
    camera : dict with ``position``, ``focal_point``, ``up`` (m), or None for an isometric view.
    box : (lo, hi), optional
        Corners of a box drawn as a grey outline (walls of a container) (m).
    """
    pv = _pyvista()
    if pv is None:
        return None
    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    plotter.set_background("white")
    for s in surfaces:
        faces = np.hstack([np.full((len(s["triangles"]), 1), 3), s["triangles"]]).ravel()
        mesh = pv.PolyData(np.asarray(s["points"], dtype=float), faces)
        kw = dict(opacity=s.get("opacity", 1.0), show_edges=s.get("show_edges", False))
        if s.get("values") is not None:
            mesh[s.get("name", "value")] = np.asarray(s["values"])
            bar = {"title": s.get("name", "value"), "vertical": True, "color": "black"}
            if s.get("bar_x") is not None:
                bar["position_x"] = s["bar_x"]
            plotter.add_mesh(mesh, scalars=s.get("name", "value"), cmap=s.get("cmap", "viridis"),
                             clim=s.get("clim"), scalar_bar_args=bar, **kw)
        else:
            plotter.add_mesh(mesh, color=s.get("color", "lightgrey"), **kw)
    if box is not None:
        (x0, y0, z0), (x1, y1, z1) = box
        plotter.add_mesh(pv.Box(bounds=(x0, x1, y0, y1, z0, z1)).outline(), color="grey",
                         line_width=2)
    if len(x):
        glyphs = particles_polydata(pv, x, radius, {color_by: values if values is not None
                                                    else np.zeros(len(x))})
        plotter.add_mesh(glyphs, scalars=color_by, cmap="plasma", clim=clim,
                         scalar_bar_args={"title": color_by, "color": "black",
                                           "vertical": True, "position_x": 0.05})
    if title:
        plotter.add_text(title, font_size=10, color="black")
    if camera:
        plotter.camera_position = [camera["position"], camera["focal_point"], camera["up"]]
    else:
        plotter.view_isometric()
    path = pathlib.Path(path)
    plotter.screenshot(str(path))
    plotter.close()
    return path


def _render_jobs(jobs: list[dict]) -> list[str | None]:
    """Render snapshot jobs in this process (the worker of :func:`render_snapshots`)."""
    out = [_snapshot_here(**job) for job in jobs]
    return [str(p) if p is not None else None for p in out]


def render_snapshots(jobs: Sequence[dict]) -> list[pathlib.Path | None]:
    """Render many :func:`snapshot` jobs (keyword dicts); returns their PNG paths.

    When dolfinx was loaded before VTK (see :func:`_preload_vtk`) the jobs are rendered in
    a spawned interpreter that never imports dolfinx; if that process fails, the pictures
    are skipped with a warning and the run's data files are unaffected.
    """
    jobs = list(jobs)
    if not jobs:
        return []
    if VTK_BEFORE_DOLFINX or "dolfinx" not in sys.modules:
        return [pathlib.Path(p) if p else None for p in _render_jobs(jobs)]
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor
    try:   # a worker that dies raises BrokenProcessPool here instead of hanging
        with ProcessPoolExecutor(1, mp_context=mp.get_context("spawn")) as pool:
            paths = pool.submit(_render_jobs, jobs).result()
    except Exception as exc:
        warnings.warn(f"snapshots skipped: the rendering process failed ({exc})", stacklevel=2)
        return [None] * len(jobs)
    return [pathlib.Path(p) if p else None for p in paths]


def plot_series(path: str | pathlib.Path, t: np.ndarray, series: dict[str, tuple[np.ndarray, str]],
                *, xlabel: str = "time (s)", title: str = "") -> pathlib.Path:
    """One stacked subplot per entry of ``series`` = {label: (values, unit)}; PNG."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(series), 1, figsize=(7, 2.2 * len(series)), sharex=True,
                             squeeze=False)
    for ax, (label, (values, unit)) in zip(axes[:, 0], series.items()):
        ax.plot(t, values, lw=1.5)
        ax.set_ylabel(f"{label}\n({unit})" if unit else label)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel(xlabel)
    if title:
        axes[0, 0].set_title(title)
    fig.tight_layout()
    path = pathlib.Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def animation(path: str | pathlib.Path, frames: Iterable[str | pathlib.Path], *,
              fps: float = 8.0) -> pathlib.Path | None:
    """Join PNG frames into a looping GIF (imageio); returns None without imageio."""
    try:
        import imageio.v2 as imageio
    except Exception as exc:
        warnings.warn(f"imageio not available ({exc}); no animation", stacklevel=2)
        return None
    frames = [pathlib.Path(f) for f in frames if f is not None]
    if not frames:
        return None
    path = pathlib.Path(path)
    images = [imageio.imread(f) for f in frames]
    imageio.mimsave(path, images, duration=1.0 / fps, loop=0)
    return path
