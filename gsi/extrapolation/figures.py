"""The pictures of a case's extrapolation (:class:`gsi.extrapolation.driver.CaseExtrapolation`,
``ex``, after its ``finish``): the temperature fields, the group means, the Voronoi-cell
error map, and for an FE wall the mean temperatures against hours."""
from __future__ import annotations

import numpy as np

from gsi.extrapolation.metrics import cell_means


def pictures(ex, name="case", view="iso"):
    """The temperature fields at t0, t1 and the last t_n (full DEM and extrapolated,
    projected along the axis of ``view`` -- "+y" looks along y -- or, for "iso", the
    axis the bed spreads least over), the group means against time, and the
    Voronoi-cell error map at the last t_n; returns the files."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    log, res, cols = ex.log, ex.res, ex.cols
    if log is None:
        return []
    full = ex.n_cmp > 0 and len(ex.dem_T) == ex.n_cmp + 1
    x0, T0 = ex.t0_state
    drop = "xyz".index(view[1]) if view[0] in "+-" else int(np.argmin(np.ptp(log.x1, 0)))
    u, v = [d for d in range(3) if d != drop]
    files = []
    last = ex.n_cmp if full else len(res["x"]) - 1
    label = res.get("stored_periods", range(len(res["x"])))[last] + 1
    lo = min(T0.min(), log.T1.min())
    hi = max(T0.max(), log.T1.max())
    panels = [("full DEM, t0", x0, T0), ("full DEM, t1", log.x1, log.T1)]
    if full:
        panels.append((f"full DEM, t{last + 1}", ex.dem_x[last], ex.dem_T[last]))
    panels += [("extrapolated, t0 (= DEM)", x0, T0), ("extrapolated, t1 (= DEM)", log.x1,
                                                      log.T1),
               (f"extrapolated, t{label}", res["x"][last], res["T"][last])]
    ncol = 3
    fig, axes = plt.subplots(2 if full else 1, ncol, figsize=(4 * ncol, 3.8 * (2 if full
                                                                               else 1)),
                             squeeze=False)
    if not full:
        panels = panels[2:]
    allx = np.vstack([p[1] for p in panels])
    pad = 0.03 * np.ptp(allx, axis=0)
    for ax, (title, x, T) in zip(axes.ravel(), panels):
        sc = ax.scatter(x[:, u], x[:, v], c=T, s=6, cmap="coolwarm", vmin=lo, vmax=hi)
        ax.set_title(title, fontsize=9)
        ax.set_xlim(allx[:, u].min() - pad[u], allx[:, u].max() + pad[u])
        ax.set_ylim(allx[:, v].min() - pad[v], allx[:, v].max() + pad[v])
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.colorbar(sc, ax=axes.ravel().tolist(), shrink=0.8, label="T (K)")
    fig.savefig(ex.out / "extrapolation_fields.png", dpi=90)
    plt.close(fig)
    files.append(ex.out / "extrapolation_fields.png")
    if "T_hot_extra" in cols:
        fig, ax = plt.subplots(figsize=(6, 4))
        t = cols["time_s"]
        mk = "o--" if len(t) <= 60 else "--"
        ax.plot(t, cols["T_hot_extra"], mk, color="tab:red", label="hot, extrapolated")
        ax.plot(t, cols["T_cold_extra"], mk, color="tab:blue", label="cold, extrapolated")
        if "T_hot_dem" in cols:
            ax.plot(t, cols["T_hot_dem"], "-", color="tab:red", label="hot, full DEM")
            ax.plot(t, cols["T_cold_dem"], "-", color="tab:blue", label="cold, full DEM")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("mean temperature (K)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        ax.set_title(f"{name}: mean temperature of the initially hot and cold halves",
                     fontsize=9)
        fig.tight_layout()
        fig.savefig(ex.out / "extrapolation_means.png", dpi=90)
        plt.close(fig)
        files.append(ex.out / "extrapolation_means.png")
    if full:
        seeds = ex.seeds
        m_dem, c_dem = cell_means(seeds, ex.dem_x[last], ex.dem_T[last])
        m_ext, c_ext = cell_means(seeds, res["x"][last], res["T"][last])
        ok = (c_dem > 0) & (c_ext > 0)
        fig, ax = plt.subplots(figsize=(5.5, 4.5))
        ax.scatter(log.x1[:, u], log.x1[:, v], s=3, color="0.85")
        sc = ax.scatter(seeds[ok, u], seeds[ok, v], c=np.abs(m_dem - m_ext)[ok], s=40,
                        cmap="viridis", edgecolors="k", linewidths=0.3)
        fig.colorbar(sc, ax=ax, label="|mean T_DEM - mean T_extra| (K)")
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(f"eq. 9 per Voronoi cell at t{last + 1} ({ok.sum()} cells, "
                     f"seeds shown)", fontsize=9)
        fig.savefig(ex.out / "extrapolation_cells.png", dpi=90)
        plt.close(fig)
        files.append(ex.out / "extrapolation_cells.png")
    return files

def hours_picture(ex, name="case"):
    """``extrapolation_hours.png``: the bed's (m c_p-weighted) mean temperature --
    left in the live DEM + FE window (the coupling records, from the moment the
    halves are set, with the extrapolated t_n in it), right against hours of physical
    time on a log axis, the live run beside the extrapolated hours, with the shell's
    mean and the initially hot and cold halves; returns the file."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cols, log = ex.cols, ex.log
    recs = ex.structure.thermal.records
    t_live = np.array([r.t for r in recs])
    bed_live = np.array([r.T_particles_mean for r in recs])
    wall_live = np.array([r.T_wall_mean for r in recs])
    t_set = ex.spec.halves.t if ex.spec.halves is not None else 0.0
    after = t_live > t_set + 1e-9
    t = cols["time_s"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4),
                                 gridspec_kw=dict(width_ratios=[1, 1.6]))
    a1.plot(t_live[after], bed_live[after], "-", color="tab:orange",
            label="bed, DEM + FE")
    win = t <= t_live[-1] + 1e-9
    a1.plot(t[win], cols["T_mean_extra"][win], "o", mfc="none", color="tab:orange",
            label="bed, extrapolated")
    a1.axvspan(log.t0, log.t1, color="tab:green", alpha=0.15, label="logged period")
    a1.set_xlabel("time (s)")
    a1.set_ylabel("bed mean temperature (K)")
    a1.set_title(f"live run window (shell mean {wall_live[-1]:.2f} K)", fontsize=9)
    a1.grid(alpha=0.3)
    a1.legend(fontsize=7)
    h = t / 3600.0
    a2.axvspan(t_live[after][0] / 3600.0, t_live[-1] / 3600.0, color="tab:green",
               alpha=0.15, label="live DEM + FE window")
    a2.plot(t_live[after] / 3600.0, bed_live[after], "-", lw=3, color="tab:orange",
            alpha=0.6, label="bed, DEM + FE")
    a2.plot(h, cols["T_mean_extra"], "--", color="tab:orange", label="bed, extrapolated")
    a2.plot(h, cols["T_wall_mean_extra"], "-", color="0.3", label="shell, extrapolated")
    if "T_hot_extra" in cols:
        a2.plot(h, cols["T_hot_extra"], ":", color="tab:red", lw=1,
                label="initially hot half")
        a2.plot(h, cols["T_cold_extra"], ":", color="tab:blue", lw=1,
                label="initially cold half")
    a2.set_xscale("log")
    a2.set_xlabel("physical time (h)")
    a2.set_ylabel("mean temperature (K)")
    a2.set_title(f"{name}: {len(t) - 1} periods of {log.period:.4g} s extrapolated "
                 f"({h[-1]:.3g} h)", fontsize=9)
    a2.grid(alpha=0.3, which="both")
    a2.legend(fontsize=7)
    fig.tight_layout()
    path = ex.out / "extrapolation_hours.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path
