"""Contact-log control of a DEM simulation (the logging kernels: :mod:`gsi.dem.contact_log`):
:class:`ContactLogControl` starts a log at t0, grows it while the engine fills it, and at
t1 turns it into a :class:`gsi.dem.contact_log.ContactLog`."""
import numpy as np

from gsi.errors import GsiInputError, GsiRunError
from gsi.dem import contact_log as clog
from gsi.dem.materials import P_HC, P_KH


class ContactLogControl:
    """The contact log of one simulation: ``state`` is the
    :data:`gsi.dem.contact_log.LogState` the logging engine writes (an empty one while no
    log runs)."""

    def __init__(self):
        self.state = clog.empty_log_state()     # read only by a logging engine
        self._t0 = None                         # (t0, particle data) while logging

    @property
    def running(self) -> bool:
        return self._t0 is not None

    def start(self, P, *, time, step_count, dt, heat, n_planes, every=1, dt_split=None,
              capacity=None) -> None:
        """Record every contact from now (t0) until :meth:`stop` (t1); see
        :mod:`gsi.dem.contact_log`.

        Parameters
        ----------
        P : gsi.dem.state.Particles
            The particles now (their ids, positions, temperatures, heat capacities and
            types at t0 are kept).
        time, step_count, dt : float, int, float
            The simulation's clock (s, steps) and time step (s).
        heat : str or None
            The contact heat model (the log knows the contact sizes of "area",
            "radius" and "constant").
        n_planes : int
            Plane walls of the simulation.
        every : int
            Sampling factor n: the contacts are sampled every ``every`` steps (the first
            sample ``every`` steps from now).
        dt_split : float, optional
            Delta t_c^max (s): a contact longer than this is logged as several rows
            (Algorithm 2 of the seed); a multiple of every dt. Default: never split.
        capacity : int, optional
            Rows to reserve at first (default 32 per particle); the log grows as
            needed.

        The simulation switches to the logging variant of its engine (compiled once per
        law combination, then cached); trajectories are the same bit for bit.  The log
        is not part of :meth:`state` (a checkpoint taken while logging does not hold it).
        """
        if self.running:
            raise GsiInputError("start_contact_log: a contact log is already running; call "
                                "stop_contact_log() first")
        if not (isinstance(every, (int, np.integer)) and every >= 1):
            raise GsiInputError(f"contact_log.every = {every}: must be an integer >= 1 "
                                "(steps)")
        n = len(P.id)
        if n == 0:
            raise GsiInputError("start_contact_log: no particles to log")
        if int(P.id.max()) >= 2 ** 31:
            raise GsiInputError("start_contact_log: particle ids above 2^31 cannot be logged")
        if n_planes > clog.TRI_BASE:
            raise GsiInputError(f"start_contact_log: at most {clog.TRI_BASE} planes")
        split = 0
        if dt_split is not None:
            per = every * dt
            split = int(round(dt_split / per))
            if not (dt_split > 0 and split >= 1
                    and abs(split * per - dt_split) <= 1e-9 * dt_split):
                raise GsiInputError(
                    f"contact_log.dt_split = {dt_split}: must be a positive multiple of "
                    f"every x dt = {per:g} s (e.g. {max(split, 1) * per:g} s)")
        n_cap = 8 * n + 64
        self.state = clog.empty_log_state(n_cap, int(capacity) if capacity else 4 * n_cap)
        c = self.state.ctrl
        c[clog.C_EVERY] = every
        c[clog.C_SPLIT] = split
        c[clog.C_NEXT] = step_count + every
        c[clog.C_START] = step_count
        if heat not in clog.SIZE_MODELS:
            raise GsiInputError(f"contact_log: heat = {heat!r} is not logged (the replay "
                                f"knows the contact sizes of 'area', 'radius' and 'constant')")
        c[clog.C_MODEL] = clog.SIZE_MODELS[heat]
        order = np.argsort(P.id, kind="stable")
        self._t0 = dict(t0=time, ids=P.id[order].copy(), x0=P.x[order].copy(),
                        T0=P.T[order].copy(), heat_capacity=(1.0 / P.mcp_inv)[order],
                        type_=P.type[order].astype(np.int32))

    def stop(self, P, walls, *, time, dt, heat, table):
        """End the log (now is t1): ``P`` the particles (:data:`gsi.dem.state.Particles`),
        ``walls`` the simulation's :class:`gsi.dem.wall_registry.Walls`, ``time`` (s) and
        ``dt`` (s) its clock and step, ``heat`` its contact heat model and ``table`` its
        pair table. Returns the :class:`gsi.dem.contact_log.ContactLog`."""
        if not self.running:
            raise GsiInputError("stop_contact_log: no contact log is running; call "
                                "start_contact_log() first")
        lg = self.state
        need = int(lg.ctrl[clog.C_NROWS] + lg.ctrl[clog.C_NOPEN])
        if need > lg.row_key.shape[0]:
            lg = clog.grown(lg, 0, need)
        clog.close_open(lg)
        a = self._t0
        self._t0 = None
        self.state = clog.empty_log_state()
        order = np.argsort(P.id, kind="stable")
        ids = P.id[order]
        if len(ids) != len(a["ids"]) or not (ids == a["ids"]).all():
            raise GsiRunError("stop_contact_log: particles were inserted or lost since "
                              "start_contact_log; the log needs the same particles at t0 and t1")
        pl, M = walls.plane_state, walls.mesh_state
        col = P_HC if heat == "constant" else P_KH
        return clog.ContactLog.from_rows(
            lg, ids=ids, x0=a["x0"], x1=P.x[order].copy(), T0=a["T0"],
            T1=P.T[order].copy(), heat_capacity=a["heat_capacity"], type_=a["type_"],
            coef=table[:, :, col].copy(),
            wall_type=np.concatenate([pl.type, M.wall_type]).astype(np.int32),
            wall_T=np.concatenate([pl.T, walls.mean_temperatures()]),
            wall_has_T=np.concatenate([pl.has_T, M.wall_has_T]).astype(bool),
            tri_wall=M.tri_wall.astype(np.int64), tri_first=walls.first_triangles(),
            n_planes=walls.n_planes, dt=dt, t0=a["t0"], t1=time,
            model=heat or "area")

    def grow(self, P, pairs, wc) -> None:
        """Room for the next sample: open contacts and rows at least doubled."""
        lg = self.state
        nc = int(clog.count_contacts(P, pairs, wc))
        self.state = clog.grown(lg, max(2 * lg.cur_key.shape[0], 2 * nc),
                                max(2 * lg.row_key.shape[0],
                                    int(lg.ctrl[clog.C_NROWS] + lg.ctrl[clog.C_NOPEN]) + 4 * nc))
