"""The DEM step engine: one compiled module for every contact model.

The contact model is chosen at run time (:mod:`gsi.dem.contact.model`: a small integer
array names the normal, tangential, rolling and heat sub-models and the contact-log
switch), so the engine compiles once, is cached by numba like any module, and lives in
the repository.  :func:`get_engine` returns an :class:`Engine` bound to one model.

Every contact -- sphere pair, plane, mesh triangle -- goes through the same path:
its geometry is written into a lane of a buffer (:mod:`gsi.dem.contact.lanes`) by
:mod:`gsi.dem.pair_lanes` (pairs) or :mod:`gsi.dem.wall_lanes` (planes and triangles),
then :func:`gsi.dem.contact.model.evaluate` runs the sub-models over the lanes, then the
results are added to the bodies.  There is one law evaluation per contact and no second path.

Arguments: the state bundles of :mod:`gsi.dem.state` -- ``P`` particles, ``pairs``
neighbour lists, ``pl`` planes, ``M`` mesh walls, ``wc`` wall contacts -- the pair table
``table`` (ntypes, ntypes, N_PAIR) (see :mod:`gsi.dem.materials`) and ``model``.

One DEM step (velocity Verlet, docs/design.md "DEM physics"):

1. v += dt/2 F/m, x += dt v, omega += dt/2 T/I, then F = m g, T = 0, Q = 0 for the
   new forces; walls move.
2. scan: largest displacement since the last neighbour build (rebuild when it
   exceeds skin/2; taken from a bound, exactly only near skin/2:
   :func:`gsi.dem.integrate.displacement_bound`), particles outside the domain, NaN or
   runaway velocities.
3. the force pass (parallel, two colours of slabs; see :func:`advance`): every contact
   once, added to both bodies.
4. v += dt/2 F/m, omega += dt/2 T/I; T += dt Q/(m c_p).
5. serial sums of wall forces, torques and the coupling accumulators.

Steps 4 and the next step's 1-2 run inside the force pass, slab by slab as the
forces complete, so a step has two parallel regions; only the first step of a call to
:func:`advance` drifts on its own.  With the contact log on, a sampled step ends before
the next one drifts (same arithmetic, not fused) and the log samples its contacts.
"""
import math

import numpy as np

from gsi.jit import njit, pjit, prange, uint
from gsi.dem.contact.lanes import CH, NB, A2, RI, RJ, DTEMP, Q, MX
from gsi.dem.contact.model import (evaluate_heat, model_ids, M_HEAT, M_LOG, M_ROLLING,
                                   M_FRICTION, M_NORMAL, NORMAL, ROLLING, HEAT)
from gsi.dem.contact_geometry import spheres_touch, wall_radius2, plane_distance
from gsi.dem.fast_call import FastCall
from gsi.dem.contact_log import C_NEXT, C_STEP, has_room, sample, empty_log_state
from gsi.dem.integrate import (clear_forces, initial_integrate, scan, integrate_rows,
                               friction_correction, reduce_scans, verdict,
                               displacement_bound)
from gsi.dem.pair_lanes import (gather_pairs, finish_pairs, friction_pairs, prefetch_ahead,
                                PREFETCH_AHEAD)
from gsi.dem.spring_heat import book_ended_springs
from gsi.dem.wall_lanes import (gather_planes, gather_triangles, finish_walls, friction_walls,
                                plane_count)
from gsi.dem.state import (Particles, Pairs, Planes, Mesh, WallContacts, as_tuple,
                           MAX_WALL_SLOTS)
from gsi.dem.wall_kernels import move_walls, plane_sums, mesh_scatter
from gsi.errors import GsiInputError


#: ``nsteps`` of :func:`advance` that computes the forces only (no step)
FORCES_ONLY = -1


# ---- the force pass ----------------------------------------------------------------------

@njit
def lane_buffer():
    """A lane buffer (:mod:`gsi.dem.contact.lanes`) whose outputs of the sub-models that
    can be "none" (rolling ``MX..MZ``, heat ``Q``) are zero, as
    :func:`gsi.dem.contact.model.evaluate` requires; every other field of a lane is
    written before it is read, so the rest is left unset (zeroing all 51 fields of both
    buffers of every slab task cost a memset of 59 kB per task and step)."""
    B = np.empty(NB * CH)
    for l in range(uint(0), uint(3 * CH)):
        B[MX + l] = 0.0
    for l in range(uint(0), uint(CH)):
        B[Q + l] = 0.0
    return B


@njit
def slab_task(sl, colour, mode, dt, Pt, pairst, plt, Mt, wct, plh, tab, nt, model, pl_acc,
              gx, gy, gz, lo, hi, vmax2, scan_out):
    """One task of the force pass (:func:`advance`): the contacts of the particles of slab ``sl``
    (pairs, planes, triangles) in batches of up to :data:`CH` lanes, then, for the second
    colour, the integration of the slabs this task completes (see :func:`advance`).

    A plain (not parallel) function called from the ``prange`` loop; the bundles arrive
    as plain tuples (see :mod:`gsi.dem.state`) and are named here."""
    P = Particles(*Pt)
    pairs = Pairs(*pairst)
    pl = Planes(*plt)
    M = Mesh(*Mt)
    wc = WallContacts(*wct)
    # frictional heat also heats the particles (T += dt Q/(m c_p))
    fric_on = model[M_FRICTION] != 0
    heat_on = model[M_HEAT] != 0 or fric_on
    if fric_on and dt > 0.0:    # springs of ended contacts into heat
        book_ended_springs(sl, P, pairs, pl, wc, plh, tab, nt, dt, model[M_NORMAL], pl_acc)
    roll_on = model[M_ROLLING] != 0
    multi = nt > 1       # more than one material type: a table row per lane
    mesh_on = M.tri.shape[0] > 0
    # pair batch: lanes, lane -> pair row, partner, table row; batch rows and their lanes
    B = lane_buffer()
    lk = np.empty(CH, np.uint64)
    lj = np.empty(CH, np.uint64)
    lrow = np.empty(CH, np.int64)
    brow = np.empty(CH, np.uint64)
    blane = np.zeros(CH + 1, np.uint64)
    # wall batch: lanes, lane -> particle, kind, spring row, plane or slot, table row
    W = lane_buffer()
    wi = np.empty(CH, np.int64)
    wkind = np.empty(CH, np.int64)
    wk = np.empty(CH, np.int64)
    wp = np.empty(CH, np.int64)
    wrow = np.empty(CH, np.int64)
    n = uint(0)
    nrow = np.int64(0)     # not a literal 0 (gsi.jit: literals)
    nw = uint(0)
    m_end = uint(pairs.slab_start[sl + 1])
    for m in range(uint(pairs.slab_start[sl]), m_end):
        # a row index unsigned: numba tests a signed index for wrap-around at every
        # array it indexes (three instructions each, about ten arrays per particle)
        ui = uint(pairs.slab_list[m])
        row_i = P.type[ui] * nt
        prefetch_ahead(pairs.slab_list[min(m + uint(PREFETCH_AHEAD), m_end - uint(1))], P,
                       pairs)
        k0 = uint(pairs.start[ui])
        k_end = uint(pairs.start[ui + uint(1)])
        while k0 < k_end:              # a row longer than the room left spans batches
            if n == uint(CH) or nrow == CH:
                finish_pairs(nrow, brow, blane, n, B, lk, lj, lrow, P, pairs, tab, dt,
                             model, heat_on)
                if fric_on:
                    friction_pairs(nrow, brow, blane, n, B, lj, P, dt, model)
                n = uint(0)
                nrow = np.int64(0)
            k1 = min(k_end, k0 + (uint(CH) - n))
            n = gather_pairs(ui, k0, k1, row_i, P, pairs, B, lk, lj, lrow, n, roll_on,
                             heat_on, multi)
            brow[nrow] = ui
            nrow += 1
            blane[nrow] = n
            k0 = k1
        cand = wc.plane_cand[ui]
        tri = mesh_on and (pairs.tri_start[ui + uint(1)] > pairs.tri_start[ui]
                           or wc.count[ui] > 0)
        if cand != 0 or tri:
            i = np.int64(ui)
            if nw + uint(plane_count(cand) + MAX_WALL_SLOTS) > uint(CH):
                finish_walls(nw, W, wi, wkind, wk, wp, wrow, sl, P, pairs, pl, M, wc, plh,
                             tab, dt, model, heat_on, pl_acc)
                if fric_on:
                    friction_walls(nw, W, wi, wkind, wp, sl, P, wc, dt, model, pl_acc)
                nw = uint(0)
            if cand != 0:
                nw = gather_planes(i, P, pl, wc, plh, W, wi, wkind, wk, wp, wrow, nw, row_i)
            if tri:
                nw = gather_triangles(i, P, pairs, M, wc, W, wi, wkind, wk, wp, wrow, nw,
                                      row_i)
    finish_pairs(nrow, brow, blane, n, B, lk, lj, lrow, P, pairs, tab, dt, model, heat_on)
    finish_walls(nw, W, wi, wkind, wk, wp, wrow, sl, P, pairs, pl, M, wc, plh, tab, dt, model,
                 heat_on, pl_acc)
    if fric_on:      # outside finish_pairs/walls, which then compile as without the feature
        friction_pairs(nrow, brow, blane, n, B, lj, P, dt, model)
        friction_walls(nw, W, wi, wkind, wp, sl, P, wc, dt, model, pl_acc)
    if colour == 1 and mode > 0:
        nslab = pairs.slab_start.shape[0] - 1
        m0 = pairs.slab_start[0] if sl == 1 else pairs.slab_start[sl]
        m1 = pairs.slab_start[min(sl + 2, nslab)]
        if model[M_FRICTION] != 0:
            friction_correction(m0, m1, pairs.slab_list, 0.5 * dt, P)
        dm, no, bd = integrate_rows(m0, m1, pairs.slab_list, mode, heat_on, 0.5 * dt, dt,
                                    gx, gy, gz, P, lo, hi, vmax2)
        scan_out[sl, 0] = dm
        scan_out[sl, 1] = no
        scan_out[sl, 2] = bd


# ---- the step loop ---------------------------------------------------------------------

@pjit
def advance(nsteps, skip_first_drift, dt, g, half_skin2, vmax2, lo, hi, P, pairs, pl, M, wc,
            table, lg, model):
    """Run up to ``nsteps`` steps; stop early when the caller must act.

    Each step is the force pass, which also ends this step and, unless it is the last
    one, starts the next (kick, drift, clear, scan), then the serial wall sums and the
    wall motion.  ``lg`` is the contact log's :data:`gsi.dem.contact_log.LogState` (read
    only when the model's log switch is on: the step ``lg.ctrl[C_STEP] + s + 1 ==
    lg.ctrl[C_NEXT]`` is sampled).  ``nsteps`` = :data:`FORCES_ONLY`: the force pass
    alone, at the current state (:meth:`Engine.compute_forces`).

    **The force pass** adds all contact forces, torques and heat rates to P.force,
    P.torque, P.q (cleared before), and (``mode`` 1 or 2) integrates each particle as
    soon as its forces are complete.  Pairs (half list; a pair is stored at the particle
    of the lower slab): the law is evaluated once per pair and added to both particles
    (Newton's third law).  The slabs (at least one cutoff wide) are processed in two
    colours, even then odd, in parallel within a colour (:func:`slab_task`): a particle
    of slab s writes only to slabs s and s + 1, so no two threads write the same
    particle.  Integration in the same pass (``mode`` 0: none, the forces only; 1: the
    second half kick; 2: that kick, then the next step's kick, drift and clear, see
    :func:`gsi.dem.integrate.integrate_rows`): slab s receives forces only from slabs
    s - 1 and s, so once the task of odd slab s (second colour) has run, slabs s and
    s + 1 are complete, and only this task reads them in that colour; it integrates
    them at once (the task of slab 1 also slab 0).  This leaves two parallel regions
    per step.  ``scan_out[s]`` gets the scan of the particles the task of slab s
    integrated (mode 2).

    The force pass is written once, inside the step loop (not a function of its own):
    every compiled function is optimized again in each function that calls it, and
    the force pass holds the whole contact model (see :mod:`gsi.jit`).

    Returns ``(steps_done, code, info)``: code 0 all done; 1 a rebuild is needed
    (the step ``steps_done`` has drifted; resume it with ``skip_first_drift``);
    2 ``info`` particles left the domain (same resume); 3 particle ``info`` blew up
    (NaN or speed above sqrt(vmax2)) at step ``steps_done``; 4 (log on) the log has
    no room for the sample of step ``steps_done``, which is complete and not drifted:
    grow the log, sample, resume without ``skip_first_drift``.
    """
    half_dt = 0.5 * dt
    gx = g[0]
    gy = g[1]
    gz = g[2]
    log_on = model[M_LOG] != 0
    heat_on = model[M_HEAT] != 0 or model[M_FRICTION] != 0
    forces_only = nsteps == FORCES_ONLY
    npl = pl.point.shape[0]
    nv = M.x.shape[0]
    nslab = pairs.slab_start.shape[0] - 1
    pl_acc = np.zeros((nslab, npl, 8))
    scan_out = np.zeros((nslab, 3))
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    plh = wc.plane_hist.reshape((P.x.shape[0] * npl, 3))
    # the bundles cross the prange as plain tuples (see gsi.dem.state)
    Pt = as_tuple(P)
    pairst = as_tuple(pairs)
    plt = as_tuple(pl)
    Mt = as_tuple(M)
    wct = as_tuple(wc)
    # a bound (m) on every particle's displacement since the lists were built: 0 when
    # they were built at this drift (a resumed step), else the exact scan's
    bound = 0.0
    if skip_first_drift or forces_only:
        clear_forces(P, gx, gy, gz)
    else:
        initial_integrate(P, half_dt, dt, gx, gy, gz)
        wd2 = move_walls(dt, pl, M)
        d2, nout, bad = scan(P, lo, hi, vmax2)
        bound = math.sqrt(d2)
        code, info = verdict(d2, wd2, nout, bad, half_skin2)
        if code != 0:
            return 0, code, info
    for s in range(1 if forces_only else nsteps):
        # mode 0 as a run-time value: a literal would compile the pass twice (gsi.jit)
        mode = nsteps + 1 if forces_only else (1 if s == nsteps - 1 else 2)
        sampled = False
        if log_on and not forces_only:
            if lg.ctrl[C_STEP] + s + 1 == lg.ctrl[C_NEXT]:
                sampled = True
                mode = 1
        scan_out[:, 0] = 0.0
        scan_out[:, 1] = 0.0
        scan_out[:, 2] = -1.0
        # the force pass
        for colour in range(2):
            for si in prange((nslab - colour + 1) // 2):
                slab_task(2 * si + colour, colour, mode, dt, Pt, pairst, plt, Mt, wct, plh,
                          tab, nt, model, pl_acc, gx, gy, gz, lo, hi, vmax2, scan_out)
        if nslab == 1 and mode > 0:        # no second colour: the one slab is complete now
            if model[M_FRICTION] != 0:
                friction_correction(pairs.slab_start[0], P.x.shape[0], pairs.slab_list,
                                    half_dt, P)
            dm, no, bd = integrate_rows(pairs.slab_start[0], P.x.shape[0], pairs.slab_list,
                                        mode, heat_on, half_dt, dt, gx, gy, gz, P, lo, hi,
                                        vmax2)
            scan_out[0, 0] = dm
            scan_out[0, 1] = no
            scan_out[0, 2] = bd
        if forces_only:
            return 0, 0, 0
        if npl > 0:
            plane_sums(dt, pl_acc, pl)
        if nv > 0:
            mesh_scatter(dt, wc, M)
        if sampled:
            if not has_room(P, pairs, wc, lg):
                return s + 1, 4, 0
            sample(P, pairs, pl, M, wc, lg)
            if s < nsteps - 1:
                # the next step's drift, as at the start of a call
                initial_integrate(P, half_dt, dt, gx, gy, gz)
                wd2 = move_walls(dt, pl, M)
                d2, nout, bad = scan(P, lo, hi, vmax2)
                bound = math.sqrt(d2)
                code, info = verdict(d2, wd2, nout, bad, half_skin2)
                if code != 0:
                    return s + 1, code, info
            continue
        if mode == 2:
            # the next step has drifted: its walls move, then the scan decides (the
            # displacement from the bound, exact only near skin/2: displacement_bound)
            wd2 = move_walls(dt, pl, M)
            s2max, nout, bad = reduce_scans(scan_out)
            d2 = 0.0
            if bad < 0:
                d2, bound = displacement_bound(bound, dt, s2max, P, lo, hi, vmax2,
                                               half_skin2)
            code, info = verdict(d2, wd2, nout, bad, half_skin2)
            if code != 0:
                return s + 1, code, info
    return nsteps, 0, 0


@njit
def heat_conductance_sum(P, pairs, pl, M, wc, table, model):
    """Per particle sum_j H_ij (W/K) over touching pairs and walls with a temperature
    (triangle contacts as found at the last step): the heat sub-model of the contact
    model over lanes of the same geometry as the force pass (``DTEMP`` = 1 K)."""
    x = P.x
    n = x.shape[0]
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    Hs = np.zeros(n)
    B = np.zeros(NB * CH)
    lj = np.empty(CH, np.int64)
    for i in range(n):
        ri = P.radius[i]
        row_i = P.type[i] * nt
        for k0 in range(pairs.start[i], pairs.start[i + 1], CH):
            k1 = min(k0 + CH, pairs.start[i + 1])
            m = uint(0)
            for k in range(k0, k1):
                j = pairs.j[k]
                rj = P.radius[j]
                dx = x[j, 0] - x[i, 0]
                dy = x[j, 1] - x[i, 1]
                dz = x[j, 2] - x[i, 2]
                L2 = dx * dx + dy * dy + dz * dz
                if not spheres_touch(L2, ri + rj):
                    continue
                inv_L = 1.0 / math.sqrt(L2)
                s = (ri * ri - rj * rj + L2) * 0.5 * inv_L
                B[A2 + m] = ri * ri - s * s
                B[RI + m] = ri
                B[RJ + m] = rj
                B[DTEMP + m] = 1.0
                lj[m] = j
                m += uint(1)
            # runs of one table row (lane indices typed as in the force pass: the heat
            # sub-model is compiled once for both)
            l0 = uint(0)
            while l0 < m:
                row = row_i + P.type[lj[l0]]
                l1 = l0 + uint(1)
                while l1 < m and row_i + P.type[lj[l1]] == row:
                    l1 += uint(1)
                evaluate_heat(l0, l1, B, tab, row, model)
                l0 = l1
            for l in range(m):
                Hs[i] += B[Q + l]
                Hs[lj[l]] += B[Q + l]
        for p in range(pl.point.shape[0]):
            if not pl.has_T[p]:
                continue
            dist = plane_distance(x[i, 0], x[i, 1], x[i, 2], pl.point[p, 0], pl.point[p, 1],
                                  pl.point[p, 2], pl.normal[p, 0], pl.normal[p, 1],
                                  pl.normal[p, 2])
            delta = ri - dist
            if delta > 0.0:
                Hs[i] += _wall_conductance(B, ri, delta, tab, row_i + pl.type[p], model)
        for s in range(wc.count[i]):
            wl = M.tri_wall[wc.tri[i, s]]
            if not M.wall_has_T[wl]:
                continue
            d2 = 0.0
            for d in range(3):
                d2 += (wc.point[i, s, d] - x[i, d]) ** 2
            delta = ri - math.sqrt(d2)
            if delta > 0.0:
                Hs[i] += _wall_conductance(B, ri, delta, tab, row_i + M.wall_type[wl], model)
    return Hs


@njit
def _wall_conductance(B, ri, delta, tab, row, model):
    """H (W/K) of one sphere-wall contact by the model's heat sub-model (lane 0 of B)."""
    B[A2] = wall_radius2(ri, delta)
    B[RI] = ri
    B[RJ] = math.inf
    B[DTEMP] = 1.0
    evaluate_heat(uint(0), uint(1), B, tab, row, model)
    return B[Q]


# ---- the engine object ----------------------------------------------------------------------

_NO_LOG = empty_log_state()


#: :func:`advance` and :func:`heat_conductance_sum` without numba's re-typing of the
#: bundles at each call (:mod:`gsi.dem.fast_call`)
fast_advance = FastCall(advance)
fast_heat_sum = FastCall(heat_conductance_sum)


class Engine:
    """The compiled engine bound to one contact model (:func:`get_engine`).

    Its methods take the same arguments as the kernels :func:`advance`
    and :func:`heat_conductance_sum`, without ``model``.
    """

    def __init__(self, model):
        self.model = model
        self.heat_on = bool(model[M_HEAT] != 0)
        self.friction_on = bool(model[M_FRICTION] != 0)

    def advance(self, nsteps, skip_first_drift, dt, g, half_skin2, vmax2, lo, hi, P, pairs,
                pl, M, wc, table, lg):
        """Run up to ``nsteps`` steps (see :func:`advance`)."""
        return fast_advance(nsteps, skip_first_drift, dt, g, half_skin2, vmax2, lo, hi, P,
                            pairs, pl, M, wc, table, lg, self.model)

    def compute_forces(self, g, P, pairs, pl, M, wc, table):
        """Forces, torques and the contact springs' rotation at the current state, no
        motion, no heat update (dt = 0): the start of a run and after external changes
        (:func:`advance` with ``nsteps`` = :data:`FORCES_ONLY`)."""
        fast_advance(FORCES_ONLY, False, 0.0, g, 0.0, 0.0, g, g, P, pairs, pl, M, wc, table,
                     _NO_LOG, self.model)

    def heat_conductance_sum(self, P, pairs, pl, M, wc, table):
        """Per-particle conductance sums (see :func:`heat_conductance_sum`)."""
        return fast_heat_sum(P, pairs, pl, M, wc, table, self.model)


def is_cached():
    """Whether numba's cache holds the compiled engine (else its first step compiles it,
    about a minute on 2 cores; see :mod:`gsi.jit` for where the cache lives)."""
    import glob
    import os
    import numba
    return bool(glob.glob(os.path.join(numba.config.CACHE_DIR, "**", "engine.advance-*.nbi"),
                          recursive=True))


def get_engine(contact="hertz", rolling=False, heat=None, log=False, friction=False):
    """The engine for a contact law, rolling law and heat model (by registry name), with
    or without the contact log: the one compiled engine bound to these sub-models.

    Parameters
    ----------
    contact : str
        Normal sub-model, a key of :data:`gsi.dem.contact.model.NORMAL` ("hertz", "linear").
    rolling : bool or str
        Rolling sub-model: False/"none", True/"cdt" (:data:`gsi.dem.contact.model.ROLLING`).
    heat : str or None
        Heat sub-model, a key of :data:`gsi.dem.contact.model.HEAT` (None, "area",
        "radius", "constant", "pipe").
    log : bool
        Sample contacts into the contact log (:mod:`gsi.dem.contact_log`).
    friction : bool
        Frictional heating (:mod:`gsi.dem.contact.dissipation`): the power each contact
        dissipates heats its two bodies, half each.
    """
    if contact not in NORMAL:
        raise GsiInputError(f"contact = {contact!r}: must be one of {sorted(NORMAL)}")
    if rolling not in (False, True, None) and rolling not in ROLLING:
        raise GsiInputError(f"rolling = {rolling!r}: must be false, true or 'cdt'")
    if heat is not None and heat not in HEAT:
        raise GsiInputError(
            f"heat = {heat!r}: must be one of None, 'area', 'radius', 'constant', 'pipe'")
    return Engine(model_ids(contact, "history", rolling, heat, log, friction))
