"""Velocity-Verlet integration and the scan for rebuilds (law-independent kernels).

One DEM step (docs/design.md, "DEM physics"): v += dt/2 F/m, x += dt v, omega += dt/2 T/I;
F = m g, T = 0, Q = 0 for the new forces; contacts; v += dt/2 F/m, omega += dt/2 T/I,
T += dt Q/(m c_p).  The per-particle pieces here are called by the engine
(:mod:`gsi.dem.engine`) inside its force pass.  ``P`` is the
:data:`gsi.dem.state.Particles` bundle.
"""
import numpy as np

from gsi.jit import njit, pjit, prange, uint
from gsi.dem.state import Particles, as_tuple


@njit
def clear_one(i, gx, gy, gz, P):
    """F = m g, T = 0, Q = 0 for particle i (before contacts add up)."""
    m = P.mass[i]
    P.force[i, 0] = m * gx
    P.force[i, 1] = m * gy
    P.force[i, 2] = m * gz
    for d in range(3):
        P.torque[i, d] = 0.0
    P.q[i] = 0.0


@njit
def kick_with(i, a, b, P):
    """Half kick of particle i with a = dt/(2 m), b = dt/(2 I): v += a F, omega += b T."""
    for d in range(3):
        P.v[i, d] += a * P.force[i, d]
        P.omega[i, d] += b * P.torque[i, d]


@njit
def kick_one(i, half_dt, P):
    """Half kick of particle i (unless fixed): v += dt/2 F/m, omega += dt/2 T/I."""
    if not P.fixed[i]:
        kick_with(i, half_dt / P.mass[i], half_dt / P.inertia[i], P)


@njit
def drift_one(i, half_dt, dt, gx, gy, gz, P):
    """First half kick and drift of particle i: v += dt/2 F/m, omega += dt/2 T/I,
    x += dt v; then clear it for the new forces (:func:`clear_one`)."""
    kick_one(i, half_dt, P)
    if not P.fixed[i]:
        for d in range(3):
            P.x[i, d] += dt * P.v[i, d]
    clear_one(i, gx, gy, gz, P)


@njit
def scan_one(i, P, lo, hi):
    """(squared displacement since build, squared speed, outside the domain) of i."""
    d2 = 0.0
    s2 = 0.0
    out = False
    for d in range(3):
        xi = P.x[i, d]
        dd = xi - P.x0[i, d]
        d2 += dd * dd
        s2 += P.v[i, d] * P.v[i, d]
        if not (lo[d] <= xi <= hi[d]):
            out = True
    return d2, s2, out


@njit
def _drift_t(i, half_dt, dt, gx, gy, gz, Pt):
    """:func:`drift_one` with the bundle as a plain tuple (inside a prange)."""
    drift_one(np.int64(i), half_dt, dt, gx, gy, gz, Particles(*Pt))   # int64, as callers


@njit
def _clear_t(i, gx, gy, gz, Pt):
    """:func:`clear_one` with the bundle as a plain tuple (inside a prange)."""
    clear_one(np.int64(i), gx, gy, gz, Particles(*Pt))


@pjit
def initial_integrate(P, half_dt, dt, gx, gy, gz):
    """First half kick and drift of every particle, then clear (:func:`drift_one`)."""
    Pt = as_tuple(P)      # a bundle crosses a prange as a plain tuple (see gsi.dem.state)
    for i in prange(P.x.shape[0]):
        _drift_t(i, half_dt, dt, gx, gy, gz, Pt)


@pjit
def clear_forces(P, gx, gy, gz):
    """f = m g, torque = 0, heat rate = 0, contact count = 0 (before contacts add up)."""
    Pt = as_tuple(P)
    for i in prange(P.x.shape[0]):
        _clear_t(i, gx, gy, gz, Pt)


@njit
def scan(P, lo, hi, vmax2):
    """Largest squared displacement since build (m^2), count outside domain, bad particle.

    Returns ``(max_disp2, n_out, bad)``; ``bad`` is the first particle whose velocity
    is NaN or above sqrt(vmax2), else -1.
    """
    dmax = 0.0
    nout = 0
    bad = -1
    for i in range(P.x.shape[0]):
        d2, s2, out = scan_one(i, P, lo, hi)
        if d2 > dmax:
            dmax = d2
        if out:
            nout += 1
        if bad < 0 and not (s2 <= vmax2):
            bad = i
    return dmax, nout, bad


@njit
def integrate_rows(m0, m1, slab_list, mode, heat_on, half_dt, dt, gx, gy, gz, P, lo, hi,
                   vmax2):
    """Particles ``slab_list[m0:m1]``, whose forces are complete: the second half kick
    v += dt/2 F/m, omega += dt/2 T/I and (``heat_on``) heat T += dt Q/(m c_p); with
    ``mode`` 2 also the next step's first half kick, drift and clear
    (:func:`drift_one`), returning the scan of those particles: (the largest squared
    speed |v|^2 of the drift, number outside the domain, lowest row whose speed is NaN
    or above sqrt(vmax2), else -1).  Not the displacement since the build, as
    :func:`scan` returns: the engine bounds that by the sum of the steps' largest
    drifts, dt max|v| (:func:`displacement_bound`), without reading ``x0``.

    With frictional heating, :func:`friction_correction` runs first, on the same rows.

    The arithmetic is that of :func:`kick_one` twice, :func:`drift_one` and
    :func:`scan_one`, bitwise, written out so that a particle's values stay in registers
    and a fixed particle or one outside the domain is a select, not a branch (the
    settled ``settle`` bed's force pass with integration 2.70 -> 2.60 ms, median of 9
    interleaved batches, ``MODE=2 benchmarks/engine_ab.py`` -- removed in 0b42e1f --, one
    thread, 2026-12-03).
    """
    dmax = 0.0
    nout = 0
    bad = -1
    x = P.x
    v = P.v
    w = P.omega
    f = P.force
    tq = P.torque
    for m in range(uint(m0), uint(m1)):
        i = uint(slab_list[m])        # unsigned: no wrap-around tests (gsi.jit.uint)
        free = P.fixed[i] == 0
        # the two half kicks (this step's second, the next step's first) use the same
        # forces and the same factors: divide once (bitwise as kick_one twice)
        a = half_dt / P.mass[i]
        b = half_dt / P.inertia[i]
        v0 = v[i, 0] + a * f[i, 0]
        v1 = v[i, 1] + a * f[i, 1]
        v2 = v[i, 2] + a * f[i, 2]
        w0 = w[i, 0] + b * tq[i, 0]
        w1 = w[i, 1] + b * tq[i, 1]
        w2 = w[i, 2] + b * tq[i, 2]
        if heat_on:
            P.T[i] += dt * P.q[i] * P.mcp_inv[i]
        if mode == 2:
            v0 = v0 + a * f[i, 0]
            v1 = v1 + a * f[i, 1]
            v2 = v2 + a * f[i, 2]
            w0 = w0 + b * tq[i, 0]
            w1 = w1 + b * tq[i, 1]
            w2 = w2 + b * tq[i, 2]
            X0 = x[i, 0] + dt * v0 if free else x[i, 0]
            X1 = x[i, 1] + dt * v1 if free else x[i, 1]
            X2 = x[i, 2] + dt * v2 if free else x[i, 2]
            x[i, 0] = X0
            x[i, 1] = X1
            x[i, 2] = X2
        # the new velocity in registers too: the scan below reads these, not v[i] (a
        # load right after the stores would wait for them)
        v0 = v0 if free else v[i, 0]
        v1 = v1 if free else v[i, 1]
        v2 = v2 if free else v[i, 2]
        v[i, 0] = v0
        v[i, 1] = v1
        v[i, 2] = v2
        w[i, 0] = w0 if free else w[i, 0]
        w[i, 1] = w1 if free else w[i, 1]
        w[i, 2] = w2 if free else w[i, 2]
        if mode == 2:
            clear_one(i, gx, gy, gz, P)
            # the scan of the new position and velocity (the speed of the drift)
            s2 = v0 * v0 + v1 * v1 + v2 * v2
            if s2 > dmax:
                dmax = s2
            inside = ((lo[0] <= X0) & (X0 <= hi[0]) & (lo[1] <= X1) & (X1 <= hi[1])
                      & (lo[2] <= X2) & (X2 <= hi[2]))
            nout += 1 - np.int64(inside)
            if not (s2 <= vmax2) and (bad < 0 or np.int64(i) < bad):
                bad = np.int64(i)
    return dmax, nout, bad


@njit
def friction_correction(m0, m1, slab_list, half_dt, P):
    """Frictional heating, before :func:`integrate_rows` of the same rows: the contacts
    booked their heat with the velocity the force laws use, v_(n-1/2); the energy the
    step's forces take is paired with the full-step velocity v_n = v_(n-1/2) + dt/2 F/m
    (velocity Verlet), so each particle adds -F_d . (dt/2 F/m) dt - T_d . (dt/2 T/I) dt
    to its heat, F_d dt and T_d dt its dissipative impulses ``P.fd``, ``P.td`` (then
    cleared): the frictional heat is then second-order accurate (docs/design.md,
    "Frictional heating").  A function of its own, called only with frictional heating:
    :func:`integrate_rows` compiles as it did before the feature (measured: with this
    loop inside it, behind a run-time switch, the fused step of a dense bed was slower
    with the switch off)."""
    f = P.force
    tq = P.torque
    for m in range(m0, m1):
        i = slab_list[m]
        a = half_dt / P.mass[i]
        b = half_dt / P.inertia[i]
        corr = 0.0
        for d in range(3):
            corr -= P.fd[i, d] * (a * f[i, d]) + P.td[i, d] * (b * tq[i, d])
            P.fd[i, d] = 0.0
            P.td[i, d] = 0.0
        if P.fixed[i] == 0:
            P.T[i] += corr * P.mcp_inv[i]
            P.heat_friction[i] += corr


@njit
def displacement_bound(bound, dt, s2max, P, lo, hi, vmax2, half_skin2):
    """The squared displacement since the build to judge a rebuild by, and the new bound.

    ``bound`` (m) bounds every particle's displacement since the build before this
    step's drift; the drift moves each particle by dt |v| <= dt sqrt(``s2max``), so
    ``bound + dt sqrt(s2max)`` bounds it after.  While that stays below 0.99 skin/2 no
    rebuild is due and it is returned as it is; above, the exact largest displacement
    is taken (:func:`scan`, which reads ``x0``) and becomes the new bound.  A rebuild
    then comes at the same step as with the exact scan at every step (the bound is
    never below the exact displacement; the 1 % covers its round-off), and the fused
    integration does not read ``x0`` (nor compute the displacement) at every step."""
    bound = bound + dt * np.sqrt(s2max)
    if bound * bound < 0.9801 * half_skin2:
        return bound * bound, bound
    d2 = scan(P, lo, hi, vmax2)[0]
    return d2, np.sqrt(d2)


@njit
def reduce_scans(scan_out):
    """(largest squared speed, number outside, lowest bad row or -1) over the slabs' scans
    (:func:`integrate_rows`)."""
    d2 = 0.0
    nout = 0
    bad = -1
    for k in range(scan_out.shape[0]):
        d2 = max(d2, scan_out[k, 0])
        nout += int(scan_out[k, 1])
        b = int(scan_out[k, 2])
        if b >= 0 and (bad < 0 or b < bad):
            bad = b
    return d2, nout, bad


@njit
def verdict(d2, wd2, nout, bad, half_skin2):
    """(code, info) of the engine's ``advance`` from a scan after a drift: 3 and the
    row of a blown-up particle, 2 and the number of particles outside the domain, 1 a
    rebuild is due (a particle or wall vertex moved more than skin/2), 0 go on."""
    if bad >= 0:
        return 3, bad
    if nout > 0:
        return 2, nout
    if d2 > half_skin2 or wd2 > half_skin2:
        return 1, 0
    return 0, 0
