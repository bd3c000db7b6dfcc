"""The checks of a case that look at several of its tables together (called by
:meth:`gsi.case.case.Case.check`): the Verlet skin, the stiffness against the impact
speed, the overlaps of placed particles, the streams' rates and the radiation's
stability."""
from __future__ import annotations

import math
import warnings

import numpy as np

from gsi.case.sources import MAX_OVERLAP
from gsi.errors import GsiInputError

#: largest Verlet skin, in largest particle radii
MAX_SKIN = 4.0
#: largest head-on overlap of two particles meeting at the estimated impact speed, as a
#: fraction of the radius (a softer material lets particles pass through each other)
MAX_IMPACT_OVERLAP = 0.5

#: gravity above this (m/s^2, about 200 g: a geotechnical centrifuge) is a unit slip
MAX_GRAVITY = 2000.0


def check_gravity(case) -> None:
    """|g| above MAX_GRAVITY: mm/s^2 typed for m/s^2 (9810 for 9.81)."""
    g = float(np.linalg.norm(case.dem.gravity))
    if g > MAX_GRAVITY:
        raise GsiInputError(
            f"dem.gravity = {list(case.dem.gravity)}: |g| = {g:.4g} m/s^2, over "
            f"{MAX_GRAVITY:g} (about 200 g); did you give mm/s^2? ({g:.4g} mm/s^2 = "
            f"{g / 1000:.4g} m/s^2)")


def check_speeds(case) -> None:
    """Gravity's magnitude, then the particles' stiffness against the speeds they meet
    each other (:func:`check_stiffness`) and the moving walls (:func:`check_wall_speeds`)."""
    check_gravity(case)
    check_stiffness(case)
    check_wall_speeds(case)


def check_skin(case) -> None:
    """A Verlet skin above MAX_SKIN largest radii (or the domain) is a unit slip: every
    particle would list every other as a neighbour."""
    skin = case.dem.skin
    if skin is None:
        return
    r_max = case.largest_radius()
    limit = min(MAX_SKIN * r_max, case.dem.domain_size)
    if skin > limit:
        raise GsiInputError(
            f"dem.skin = {skin:g}: larger than {MAX_SKIN:g} x the largest particle radius "
            f"({r_max:g} m) or the domain; use about 0.4 x the smallest radius = "
            f"{0.4 * case.smallest_radius():.3g} m, or remove it for the default (m)")


def check_stiffness(case) -> None:
    """Particles of each source meeting head-on at :meth:`impact_speed` must not
    overlap by more than MAX_IMPACT_OVERLAP of their radius: Hertz (Johnson, Contact
    Mechanics, eq. 11.24) delta = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) with m* = m/2,
    R* = r/2, E* = E / (2 (1 - nu^2)); linear law delta = v sqrt(m*/k_n). delta / r
    does not depend on r. A softer material (E = 1 Pa) lets every particle pass
    through its neighbours and out of the domain."""
    for i, p in enumerate(case.particles):
        v = case.impact_speed(i)
        if v <= 0:
            continue
        mat = case.materials[p.material]
        r = case.source_largest_radius(i)
        m_star = 0.5 * mat.rho * 4.0 / 3.0 * math.pi * r ** 3
        if case.dem.contact == "linear":
            delta = v * math.sqrt(m_star / case.dem.k_n)
            if delta > MAX_IMPACT_OVERLAP * r:
                need = case.dem.k_n * (delta / (0.1 * r)) ** 2
                raise GsiInputError(
                    f"dem.k_n = {case.dem.k_n:g}: too soft; particles[{i}] (radius {r:g} m) "
                    f"meeting at {v:.3g} m/s would overlap by {delta / r:.3g} x their radius; "
                    f"use k_n >= {need:.3g} N/m (overlap 0.1 r)")
            continue
        e_star = mat.E / (2.0 * (1.0 - mat.nu ** 2))
        delta = (15.0 * m_star * v ** 2 / (16.0 * e_star * math.sqrt(0.5 * r))) ** 0.4
        if delta > MAX_IMPACT_OVERLAP * r:
            need = mat.E * (delta / (0.1 * r)) ** 2.5
            v0 = float(np.linalg.norm(p.velocity))
            if v0 > 0.5 * v:        # the initial speed, not the fall, makes it: name it
                v_ok = v * (MAX_IMPACT_OVERLAP * r / delta) ** 1.25 - (v - v0)
                raise GsiInputError(
                    f"particles[{i}].velocity = {list(p.velocity)}: particles (radius {r:g} "
                    f"m) meeting at {v:.3g} m/s would overlap by {delta / r:.3g} x their "
                    f"radius and pass through each other (materials.{p.material}.E = "
                    f"{mat.E:g}); use a speed below about {max(v_ok, 0.0):.3g} m/s (m/s, not "
                    f"mm/s?) or E >= {need:.3g} Pa")
            raise GsiInputError(
                f"materials.{p.material}.E = {mat.E:g}: too soft; particles[{i}] (radius "
                f"{r:g} m) meeting at {v:.3g} m/s would overlap by {delta / r:.3g} x their "
                f"radius and pass through each other; use E >= {need:.3g} Pa (overlap "
                f"0.1 r; check the units: Pa)")


def placed_particles(case, i: int, p, lattice_radius: str):
    """Known positions of particle source ``i`` (``p``) before the run: a file's rows
    (x, radius) or a lattice fill's sites with its ``lattice_radius`` ("smallest" or
    "largest" of its size distribution). Returns (x, r, key, what) -- ``key`` names the
    source in messages, ``what`` one row ("row", "lattice site") -- or None for a random
    fill or a stream, whose positions are drawn at the start."""
    from gsi.case.sources import read_particle_file
    if p.fill == "file":
        data = read_particle_file(case.base_dir / p.file, key=f"particles[{i}].file",
                                  shown=p.file)
        return data["x"], data["radius"], f"particles[{i}].file = '{p.file}'", "row"
    if p.fill == "lattice":
        x = p.lattice_sites(f"particles[{i}]")
        r = np.full(len(x), getattr(p.size, lattice_radius))
        return x, r, f"particles[{i}].region", "lattice site"
    return None


def check_placed_overlaps(case) -> None:
    """Particles placed at known positions (files, lattice fills) must not overlap one
    another (within a file, or across sources) by more than MAX_OVERLAP of the smaller
    radius: they would fly apart. With ``dem.force_dt`` a warning instead. A lattice
    fill counts with its smallest radius here (its radii are drawn at the run's start,
    when :meth:`ParticleSource.add_to` checks again); overlaps with random fills
    (positions drawn at the start) are found there too."""
    from gsi.case.sources import first_overlap
    seen_x, seen_r, seen_from = [], [], []
    for i, p in enumerate(case.particles):
        placed = placed_particles(case, i, p, "smallest")
        if placed is None:
            continue
        x, r, key, what = placed
        hit = pair = None
        # fixed particles of a file cannot fly apart: their overlaps among themselves
        # are the case's (e.g. seed 001 case 4's two particles at a given overlap)
        if p.fill == "file" and not p.fixed:
            hit = first_overlap(x, r, MAX_OVERLAP)
            pair = None if hit is None else f"rows {hit[0]} and {hit[1]}"
        if hit is None and seen_x:
            hit = first_overlap(x, r, MAX_OVERLAP, other_x=np.concatenate(seen_x),
                                other_r=np.concatenate(seen_r))
            if hit is not None:
                pair = f"{what} {hit[0]} and {seen_from[hit[1]]}"
        if hit is not None:
            msg = (f"{key}: {pair} overlap by {hit[2]:.3g} x the smaller radius (more than "
                   f"{MAX_OVERLAP:g}); they would fly apart: separate them, shrink the "
                   "radii, or move the region")
            if not case.dem.force_dt:
                raise GsiInputError(msg + " (or dem.force_dt = true to run anyway)")
            warnings.warn(f"dem.force_dt = true: {msg}", stacklevel=3)
        seen_x.append(x)
        seen_r.append(r)
        seen_from += ([f"row {k} of particles[{i}].file" for k in range(len(x))]
                      if p.fill == "file" else
                      [f"lattice site {k} of particles[{i}]" for k in range(len(x))])


def check_streams(case, dt: float) -> None:
    """A stream must not be asked for more particles per step (rate x dt) than its
    region holds (a random fill jams at RANDOM_FILL_LIMIT): the rest would be skipped
    silently."""
    from gsi.case.sources import RANDOM_FILL_LIMIT
    for i, p in enumerate(case.particles):
        if p.fill != "stream":
            continue
        per_step = p.rate * dt
        holds = RANDOM_FILL_LIMIT * p.region.volume / p.size.mean_volume()
        if per_step > holds:
            raise GsiInputError(
                f"particles[{i}].rate = {p.rate:g}: {per_step:.3g} particles per DEM step "
                f"(rate x dt, dt = {dt:.3g} s) but the region holds about {holds:.3g}; "
                f"lower the rate (at most {holds / dt:.3g} 1/s) or enlarge the region")


def check_radiation(case, dt: float) -> None:
    """The explicit radiation update must be stable at the start (the bound of
    :mod:`gsi.dem.radiation`, which the run checks again at every evaluation):
    radiation_every x dt x 4 eps sigma T_max^3 A/(m c_p) <= 1 with A/m = 3/(R rho)
    at each source's smallest radius, c_p divided by the heat-time scale, T_max the
    highest particle, wall, structure or enclosure temperature."""
    opts = case.radiation_options()
    if opts is None:
        return
    from gsi.dem.radiation import SIGMA
    s = case.run.heat_time_scale
    temps = [p.temperature for p in case.particles]
    temps += [w.temperature for w in case.walls if w.temperature is not None]
    for st in case.structures:
        th = st.thermal
        if th is not None:
            temps.append(th.T_initial if th.T_initial is not None else th.T_ref)
    if opts["T_enclosure"] is not None:
        temps.append(opts["T_enclosure"])
    T_max = max(temps)
    rate = max(3.0 * case.materials[p.material].emissivity
               / (case.source_smallest_radius(i) * case.materials[p.material].rho
                  * case.materials[p.material].cp / s)
               for i, p in enumerate(case.particles))
    ratio = opts["every"] * dt * 4.0 * SIGMA * T_max ** 3 * rate
    if ratio > 1.0:
        raise GsiInputError(
            f"dem.radiation_every = {opts['every']}: the explicit radiation update is "
            f"unstable (radiation_every x dt x 4 eps sigma T^3 A/(m c_p) = {ratio:.3g} > 1 "
            f"at T = {T_max:g} K); use dem.radiation_every <= "
            f"{max(1, int(opts['every'] / ratio))} or a smaller run.dt")


#: the unit of each motion key, for the wall-speed refusal
HINT = {"rpm": "rpm: revolutions per minute", "omega": "omega: rad/s",
        "velocity": "velocity: m/s",
        "amplitude": "amplitude: m, or rad about an axis; peak speed 2 pi frequency "
                     "amplitude, times the largest distance from the axis for a rotation",
        "max_speed": "max_speed: m/s, the servo's largest speed"}


def _reach(V, axis, centre) -> float:
    """The largest distance (m) of the vertices ``V`` from the axis through ``centre``."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    rel = V - np.asarray(centre, float)
    return float(np.linalg.norm(rel - np.outer(rel @ a, a), axis=1).max())


def _fastest_state(w, base_dir):
    """(surface speed bound (m/s), key of the motion value that sets it) of a moving wall:
    |v| + |omega| x the largest distance of its vertices from the rotation axis, at the
    start and at every schedule event; an oscillation's peak speed 2 pi f A (a rotation:
    2 pi f theta r_max), a servo's ``max_speed`` (None for a wall that does not move, and
    for a free wall, whose speed the particles decide)."""
    mo = w.motion
    if mo is None or not mo.moves:
        return None
    axis = getattr(w, "axis", None) or (0.0, 0.0, 1.0)
    centre = getattr(w, "centre", None) or (0.0, 0.0, 0.0)
    try:
        V = w.surface(base_dir=base_dir)[0] if w.kind not in ("plane", "box") else None
    except (GsiInputError, AttributeError, ValueError):
        V = None
    if mo.kind == "oscillation":      # peak speed 2 pi f A (a rotation: times the reach)
        peak = 2.0 * math.pi * mo.frequency * mo.amplitude
        if mo.axis is not None:
            if V is None:
                return None
            peak *= _reach(V, mo.axis, mo.centre)
        return peak, "motion.amplitude"
    if mo.kind == "servo":
        return float(mo.max_speed), "motion.max_speed"
    events = list(enumerate(getattr(mo, "events", None) or []))
    best = (0.0, None)
    for k, e in [(None, None)] + events:
        t = 0.0 if e is None else e.t
        v, omega, c = mo.state_at(t, axis=axis, centre=centre)
        speed = float(np.linalg.norm(v))
        if np.any(omega) and V is not None and c is not None:
            speed += float(np.linalg.norm(omega)) * _reach(V, omega, c)
        src = mo if e is None else e
        name = ("rpm" if getattr(src, "rpm", None) is not None else
                "omega" if getattr(src, "omega", None) is not None else "velocity")
        key = f"motion.{name}" if e is None else f"motion.events[{k}].{name}"
        if speed > best[0]:
            best = (speed, key)
    return best if best[1] is not None else None


def check_wall_speeds(case) -> None:
    """A moving wall meeting particles at its surface speed (plus their own impact speed)
    must not overlap them by more than MAX_IMPACT_OVERLAP of their radius (Hertz,
    particle against wall: R* = r, m* = m, 1/E* = (1 - nu_p^2)/E_p + (1 - nu_w^2)/E_w;
    :func:`check_stiffness` did the same without the wall): a drum at 1e6 rpm (an rpm
    typed for a rad/s, or a unit slip) throws the particles through its wall."""
    if case.dem.contact != "hertz":
        return
    for j, w in enumerate(case.walls):
        got = _fastest_state(w, case.base_dir)
        if got is None:
            continue
        v_wall, key = got
        wm = case.materials[w.material]
        for i, p in enumerate(case.particles):
            mat = case.materials[p.material]
            r = case.source_largest_radius(i)
            m = mat.rho * 4.0 / 3.0 * math.pi * r ** 3
            e_star = 1.0 / ((1.0 - mat.nu ** 2) / mat.E + (1.0 - wm.nu ** 2) / wm.E)
            v = v_wall + case.impact_speed(i)
            delta = (15.0 * m * v ** 2 / (16.0 * e_star * math.sqrt(r))) ** 0.4
            if delta > MAX_IMPACT_OVERLAP * r:
                v_ok = math.sqrt((MAX_IMPACT_OVERLAP * r) ** 2.5 * 16.0 * e_star
                                 * math.sqrt(r) / (15.0 * m)) - case.impact_speed(i)
                raise GsiInputError(
                    f"walls[{j}].{key}: the wall's surface moves at up to {v_wall:.3g} m/s; "
                    f"particles[{i}] (radius {r:g} m) hit at {v:.3g} m/s would overlap it by "
                    f"{delta / r:.3g} x their radius and pass through it; keep the surface "
                    f"speed below about {max(v_ok, 0.0):.3g} m/s ({HINT[key.rsplit('.', 1)[1]]})")
