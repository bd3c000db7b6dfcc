"""The ``[extrapolation]`` table of a case, run by :class:`gsi.run.runner.Runner`:
:class:`CaseExtrapolation` (halves, contact log t0..t1, pairing and replay, the reference
DEM's t_n, ``extrapolation.csv``)."""
from __future__ import annotations

import time

import numpy as np

from gsi.extrapolation.fe_replay import FEWallReplay
from gsi.extrapolation.metrics import finite_max, period_errors, voronoi_seeds
from gsi.extrapolation.replay import Replay


class CaseExtrapolation:
    """The ``[extrapolation]`` table of a case, run by :class:`gsi.run.Runner`.

    Parameters
    ----------
    spec : gsi.case.extrapolation.Extrapolation
    dt : float
        DEM step (s).
    out : pathlib.Path
        Output directory (``contact_log.npz``, ``extrapolation.csv``, pictures).
    structure : gsi.coupling.coupled_structure.CoupledStructure, optional
        An FE heat wall (a thermal-only structure, e.g. a kiln shell): the replay is :class:`FEWallReplay`, the
        structure's heat returns to its state at t1 after it (the live run goes on).
    """

    def __init__(self, spec, *, dt, out, structure=None):
        self.spec = spec
        self.out = out
        self.structure = structure
        self.n_cmp = spec.n_compare
        self.K = int(round(spec.period / dt))
        self.k_halves = None if spec.halves is None else int(round(spec.halves.t / dt))
        self.k0 = int(round(spec.start / dt))
        self.k1 = self.k0 + self.K
        self.steps = ([] if self.k_halves is None else [self.k_halves]) + [self.k0, self.k1]
        self.steps += [self.k1 + p * self.K for p in range(1, self.n_cmp + 1)]
        self.hot = None
        self.log = None
        self.res = None
        self.dem_T, self.dem_x = [], []
        self.t0_state = None
        self.times = {}

    def at_step(self, k, sim, say=print):
        """Act at DEM step ``k`` (call after every chunk; only event steps do anything)."""
        s = self.spec
        if k == self.k_halves:
            h = s.halves
            d = "xyz".index(h.axis)
            below = sim.x[:, d] < h.at
            sim.T[:] = np.where(below, h.below, h.above)
            self.hot = np.zeros(int(sim.ids.max()) + 1, bool)
            self.hot[sim.ids] = below if h.below >= h.above else ~below
        if k == self.k0:
            order = np.argsort(sim.ids, kind="stable")
            self.t0_state = (sim.x[order].copy(), sim.T[order].copy())
            sim.start_contact_log(every=s.every, dt_split=s.dt_split)
            self.times["log_start"] = time.perf_counter()
        if k == self.k1:
            self.log = sim.stop_contact_log()
            t = time.perf_counter()
            self.times["collision_file_s"] = t - self.times.pop("log_start")
            self.times["file_bytes"] = self.log.save(self.out / "contact_log.npz")
            if self.structure is None:
                rep = Replay(self.log)
                self.res = rep.run(s.periods, positions=True)
            else:
                rep, self.res = self._replay_fe_wall(sim, say)
            self.times.update(pairing_s=rep.pairing_seconds, replay_setup_s=rep.setup_seconds,
                              extrap_s_per_period=self.res["seconds"] / s.periods,
                              rows=rep.n_rows)
            say(f"extrapolation: {self.log.n_collisions} collisions logged "
                f"({self.log.bytes_per_collision():.1f} bytes each), {s.periods} periods "
                f"extrapolated in {self.res['seconds']:.3g} s")
            self.times["dem_start"] = time.perf_counter()
        if s.compare and k >= self.k1 and (k - self.k1) % self.K == 0 and \
                len(self.dem_T) <= self.n_cmp and self.log is not None:
            rows = sim.index(self.log.ids)
            self.dem_T.append(sim.T[rows].copy())
            self.dem_x.append(sim.x[rows].copy())
            if self.structure is not None:
                self.dem_wall.append(self.structure.heat.stored_heat())
            if len(self.dem_T) == self.n_cmp + 1:
                self.times["dem_s_per_period"] = \
                    (time.perf_counter() - self.times.pop("dem_start")) / self.n_cmp

    def _replay_fe_wall(self, sim, say):
        """The replay with the FE wall (:class:`FEWallReplay`) from t1; the structure's
        heat is put back to its state at t1 afterwards.  Returns (replay, result) with
        ``T``, ``x`` of the periods 0..n_cmp (and the last) in the form of
        :meth:`Replay.run`."""
        st, s = self.structure, self.spec
        w = st.wall.index
        M = sim.mesh_state
        saved = st.heat.state()
        rep = FEWallReplay(self.log, st, fe_wall=sim.wall_slot(st.wall), omega=M.wall_omega[w].copy(),
                           centre=M.wall_centre[w].copy())
        hot = None if self.hot is None else self.hot[self.log.ids]
        keep = sorted(set(range(self.n_cmp + 1)) | {s.periods})
        res = rep.run(s.periods, store=keep, hot=hot, say=say)
        st.heat.set_state(saved)
        res["stored_periods"] = keep
        res["T"] = np.array([res["stored"][p][0] for p in keep])
        res["x"] = np.array([res["stored"][p][1] for p in keep])
        self.dem_wall = []
        say(f"FE-wall replay: {s.periods} periods ({s.periods * self.log.period / 3600:.3g} h) "
            f"in {res['seconds']:.3g} s ({res['fe_seconds']:.3g} s FE), energy balance "
            f"{res['balance']:.2g} relative")
        return rep, res

    def finish(self, name="case"):
        """Write ``extrapolation.csv`` and the pictures; return the summary numbers."""
        s, log, res = self.spec, self.log, self.res
        if log is None:
            return {}
        n, c = s.periods, self.n_cmp
        fe_wall = self.structure is not None
        hot = None if self.hot is None else self.hot[log.ids]
        full = c > 0 and len(self.dem_T) == c + 1
        err = {}
        if full:
            seeds = voronoi_seeds(log.x1, min(s.cells, log.n_particles), seed=0)
            window = {"T": res["T"][:c + 1], "x": res["x"][:c + 1]}
            err = period_errors(log, window, np.array(self.dem_T), np.array(self.dem_x),
                                seeds, hot)
            self.seeds = seeds
        C = log.heat_capacity

        def pad(v):
            out = np.full(n + 1, np.nan)
            out[:len(v)] = v
            return out

        cols = {"time_s": res["time"]}
        if hot is not None:
            if fe_wall:
                cols["T_hot_extra"], cols["T_cold_extra"] = res["T_hot"], res["T_cold"]
            else:
                cols["T_hot_extra"] = res["T"][:, hot].mean(1)
                cols["T_cold_extra"] = res["T"][:, ~hot].mean(1)
            if full:
                D = np.array(self.dem_T)
                cols["T_hot_dem"] = pad(D[:, hot].mean(1))
                cols["T_cold_dem"] = pad(D[:, ~hot].mean(1))
        cols["T_mean_extra"] = res["T_mean"] if fe_wall else res["T"] @ C / C.sum()
        if full:
            cols["T_mean_dem"] = pad(np.array(self.dem_T) @ C / C.sum())
            for key in ("eps_abs", "eps_level", "eps_rel", "energy_error"):
                cols[key] = pad(np.concatenate([[np.nan], err[key]]))
            cols["energy_drift"] = pad(err["energy_drift"])
        if fe_wall:
            st = self.structure
            m = st.heat.material
            cols["T_wall_mean_extra"] = res["T_wall_mean"]
            if full:
                cols["T_wall_mean_dem"] = pad(np.array(self.dem_wall)
                                              / (m.rho * m.c * st.heat.volume()))
            cols["E_particles_extra"] = res["E_particles"]
            cols["E_structure_extra"] = res["E_structure"]
            cols["Q_boundary_extra"] = res["Q_boundary"]
            cols["Q_wall_extra"] = res["Q_wall"]
        with open(self.out / "extrapolation.csv", "w") as f:
            f.write(",".join(cols) + "\n")
            for r in range(n + 1):
                f.write(",".join(f"{cols[k][r]:.17g}" for k in cols) + "\n")
        summary = {"extrap_collisions": log.n_collisions,
                   "extrap_bytes_per_collision": round(log.bytes_per_collision(), 2),
                   "extrap_s_per_period": self.times["extrap_s_per_period"],
                   "pairing_s": self.times["pairing_s"],
                   "replay_setup_s": self.times["replay_setup_s"],
                   "collision_file_s": self.times["collision_file_s"]}
        if full:
            summary.update(dem_s_per_period=self.times["dem_s_per_period"],
                           speedup_per_period=self.times["dem_s_per_period"]
                           / self.times["extrap_s_per_period"],
                           eps_abs_max=float(err["eps_abs"].max()),
                           eps_over_level_max=finite_max(err["eps_abs"]
                                                          / err["eps_level"]),
                           eps_rel_max=float(np.nanmax(err["eps_rel"])),
                           energy_err_max=float(np.abs(err["energy_error"]).max()),
                           energy_drift_max=float(err["energy_drift"].max()))
        if fe_wall:
            hours = n * log.period / 3600.0
            summary.update(
                extrap_hours=hours, bed_T_t1=float(res["T_mean"][0]),
                bed_T_end=float(res["T_mean"][-1]),
                wall_T_end=float(res["T_wall_mean"][-1]),
                wall_heat_flow_W=float(res["Q_wall"][1:].sum() / (n * log.period)),
                boundary_heat_flow_W=float(res["Q_boundary"][-1] / (n * log.period)),
                energy_balance_rel=res["balance"])
            if full:
                dT = np.array(self.dem_wall) / (m.rho * m.c * st.heat.volume()) \
                    - res["T_wall_mean"][:c + 1]
                summary["wall_T_err_max"] = float(np.abs(dT).max())
        self.cols = cols
        self.err = err
        self.files = [self.out / "extrapolation.csv", self.out / "contact_log.npz"]
        return summary

    def pictures(self, name="case", view="iso"):
        """The pictures of the run (:func:`gsi.extrapolation.figures.pictures`); returns
        the files."""
        from gsi.extrapolation import figures
        if self.log is None:
            return []
        files = figures.pictures(self, name, view)
        if self.structure is not None:
            files.append(figures.hours_picture(self, name))
        return files

    def summary_lines(self, summary: dict) -> list[str]:
        """Lines of the closing summary beyond the key list (an FE wall: the bed, the
        shell and the heat through it over the extrapolated hours)."""
        if "extrap_hours" not in summary:
            return []
        e = summary
        return [f"  FE wall: mean bed temperature {e['bed_T_t1']:.2f} K at t1 -> "
                f"{e['bed_T_end']:.2f} K after {e['extrap_hours']:.3g} h extrapolated "
                f"(shell mean {e['wall_T_end']:.2f} K); wall -> bed "
                f"{e['wall_heat_flow_W']:.4g} W "
                f"and heat in through the shell's boundary {e['boundary_heat_flow_W']:.4g} W "
                f"on average; energy balance (bed + shell - boundary heat) "
                f"{e['energy_balance_rel']:.2g} relative"]
