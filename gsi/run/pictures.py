"""Pictures of a run: the snapshot job of one output, the monitors' plot, the rendered
frames, the last frame and the animation."""
from __future__ import annotations

import pathlib

import numpy as np

from gsi import viz  # before dolfinx: pictures render in-process (gsi.viz.VTK_BEFORE_DOLFINX)


def picture_job(case, sim, handles: dict, structures: list, out: pathlib.Path, t: float,
                k: int) -> dict:
    """The snapshot job (a dict for :func:`gsi.viz.render_snapshots`) of frame ``k`` at
    time ``t``: particles coloured by ``output.color_by``, mesh walls, structures."""
    color = case.output.color_by
    values = {"speed": lambda: np.linalg.norm(sim.v, axis=1),
              "temperature": lambda: sim.T.copy(),
              "radius": lambda: sim.radius.copy()}[color]()
    surfaces = []
    for w in case.walls:
        for h in handles[w.name]:
            if hasattr(h, "triangles"):
                surfaces.append(dict(points=h.vertices, triangles=h.triangles,
                                     opacity=0.3, color="lightsteelblue"))
    for j, st in enumerate(structures):    # the DEM wall follows the FE surface
        x = st.wall.vertices
        if color == "temperature" and st.wall.vertex_temperature is not None:
            surfaces.append(dict(points=x, triangles=st.wall.triangles,
                                 values=st.wall.vertex_temperature, opacity=0.7,
                                 name=f"{st.name} T (K)", cmap="inferno",
                                 bar_x=0.88 - 0.14 * j))
            continue
        u = np.linalg.norm(x - st.interface.x0, axis=1)
        surfaces.append(dict(points=x, triangles=st.wall.triangles, values=1e3 * u,
                             name=f"{st.name} |u| (mm)", cmap="viridis",
                             bar_x=0.88 - 0.14 * j))
    (out / "pictures").mkdir(exist_ok=True)
    return dict(camera=_camera(case), path=out / "pictures" / f"frame_{k:04d}.png",
                x=sim.x.copy(), radius=sim.radius.copy(), color_by=color, values=values,
                surfaces=surfaces, title=f"{case.case.name}  t = {t:.3f} s",
                box=(case.dem.domain_lo, case.dem.domain_hi) if not surfaces else None)


def _camera(case) -> dict | None:
    """The camera of ``output.view`` (None: the isometric default)."""
    if case.output.view == "iso":
        return None
    lo, hi = np.asarray(case.dem.domain_lo), np.asarray(case.dem.domain_hi)
    c = 0.5 * (lo + hi)
    d = np.zeros(3)
    d["xyz".index(case.output.view[1])] = 1.0 if case.output.view[0] == "+" else -1.0
    up = (0.0, 0.0, 1.0) if case.output.view[1] != "z" else (0.0, 1.0, 0.0)
    return dict(position=tuple(c - 2.5 * float((hi - lo).max()) * d), focal_point=tuple(c),
                up=up)


def monitor_plot(out: pathlib.Path, name: str, monitors: dict) -> list:
    """``out/monitors.png``: up to 12 monitor columns against time; returns its path (or
    nothing if no column has two samples)."""
    series = {}
    for mname, rec in monitors.items():
        for c, v in rec.items():
            # no panel for a column without a finite value (a structure without heat
            # has no T_mean)
            if c != "time_s" and len(v) > 1 and np.isfinite(np.asarray(v, float)).any():
                label, _, unit = c.rpartition("_") if "_" in c else (c, "", "")
                series[f"{mname}: {label}"] = (rec["time_s"], v, unit)
    if not series:
        return []
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    keys = list(series)[:12]
    fig, axes = plt.subplots(len(keys), 1, figsize=(7, 1.9 * len(keys)), sharex=True,
                             squeeze=False)
    for ax, key in zip(axes[:, 0], keys):
        t, v, unit = series[key]
        ax.plot(t, v, lw=1.4)
        ax.set_ylabel(f"{key}\n({unit})" if unit else key, fontsize=8)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time (s)")
    axes[0, 0].set_title(f"{name}: monitors")
    fig.tight_layout()
    fig.savefig(out / "monitors.png", dpi=100)
    plt.close(fig)
    return [out / "monitors.png"]


def render_frames(out: pathlib.Path, name: str, frames: list) -> list:
    """Render the picture jobs; the frames, ``<name>.png`` (the last) and ``<name>.gif``."""
    files = [p for p in viz.render_snapshots(frames) if p is not None]
    if files:
        last = out / f"{name}.png"
        last.write_bytes(pathlib.Path(files[-1]).read_bytes())
        gif = viz.animation(out / f"{name}.gif", files, fps=6)
        files.append(last)
        if gif:
            files.append(gif)
    return files
