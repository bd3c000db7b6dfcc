"""Wall motions that the DEM drives step by step (:mod:`gsi.dem.wall_drivers`): the
``oscillation``, ``servo`` and ``free`` kinds of a ``[[walls]]`` ``motion`` table.

``oscillation``  ``amplitude`` (m, or rad with ``axis``), ``frequency`` (Hz), ``phase``
                 (rad, default 0), and ``direction`` (default: a plane's normal) or
                 ``axis`` + ``centre`` (a mesh wall's rotation):
                 s(t) = amplitude [sin(2 pi frequency t + phase) - sin(phase)];
                 ``update_every`` k (default 1): the velocity is the secant over k steps,
                 the wall exactly on s(t) every k steps and on the chord between.
``servo``        exactly one of ``stress`` (Pa, over ``area``), ``force`` (N),
                 ``stress_schedule`` or ``force_schedule`` (a list of ``{t, value}``,
                 piecewise linear, constant beyond its ends); ``max_speed`` (m/s);
                 ``direction`` from the wall into the particles (default: a plane's
                 normal); ``area`` (m^2; a plane needs it, a mesh wall defaults to its area
                 projected on the direction); ``gain`` (m/(s N), default 0.5/(K dt) from the
                 stability rule of :class:`gsi.dem.wall_drivers.Servo`); ``update_every``
                 k (default 1): steps between updates (the rule then holds G K k dt <= 1).
``free``         ``mass`` (kg) along ``direction``, or ``inertia`` (kg m^2) about ``axis``
                 through ``centre`` (a hinge; ``mass`` then weighs at ``centre_of_mass``);
                 ``spring`` (N/m or N m/rad) and ``damper`` (N s/m or N m s/rad) to the built
                 position, default 0.

A box of planes oscillates as a whole; servo and free walls are one wall (a plane or a
mesh wall, not a box of planes). Each is one driver of the simulation (one-step chunks,
see :mod:`gsi.dem.wall_drivers`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gsi.config.schema import nonnegative, param
from gsi.errors import GsiInputError

__all__ = ["DRIVEN_KINDS", "DRIVEN_KEYS", "SchedulePoint", "validate_driven", "make_driver",
           "check_servo_gains"]

DRIVEN_KINDS = ("oscillation", "servo", "free")
#: the keys each driven kind takes
DRIVEN_KEYS = {
    "oscillation": ("amplitude", "frequency", "phase", "direction", "axis", "centre",
                    "update_every"),
    "servo": ("stress", "force", "stress_schedule", "force_schedule", "max_speed", "direction",
              "area", "gain", "update_every"),
    "free": ("mass", "inertia", "direction", "axis", "centre", "centre_of_mass", "spring",
             "damper"),
}
_TARGETS = ("stress", "force", "stress_schedule", "force_schedule")


@dataclass(kw_only=True)
class SchedulePoint:
    """One point of a servo's target schedule: the target ``value`` (Pa or N) at ``t``."""

    t: float = param(unit="s", check=nonnegative(), doc="time of the point")
    value: float = param(unit="Pa or N", doc="target stress (Pa) or force (N) at t")


def validate_driven(m, p: str, *, planes, box: bool) -> None:
    """The keys of a driven motion ``m`` (prefix ``p``); ``planes``: the wall is a plane or
    a box of planes (None: not known yet, the wall's checks are left out); ``box``:
    several planes."""
    k = m.kind
    if k == "oscillation":
        for key in ("amplitude", "frequency"):
            if getattr(m, key) is None:
                raise GsiInputError(f"{p}{key}: missing; an oscillation needs amplitude (m, or "
                                    "rad about an axis) and frequency (Hz)")
    known = planes is not None
    if k in ("servo", "free") and box:
        raise GsiInputError(f"{p}kind = '{k}': a box of planes moves as six walls; use a "
                            "single plane (kind = 'plane') or as_planes = false")
    if m.axis is not None and m.direction is not None:
        raise GsiInputError(f"{p}axis: give direction (translation) or axis (rotation), not "
                            "both")
    if m.axis is not None:
        if known and planes:
            raise GsiInputError(f"{p}axis: a plane cannot rotate; use kind = 'plate' (a mesh) "
                                "or give direction")
        if m.centre is None:
            raise GsiInputError(f"{p}centre: missing; a rotation about axis needs a point of "
                                "the axis (m)")
    if known and m.direction is None and m.axis is None and not planes:
        raise GsiInputError(f"{p}direction: missing; a mesh wall needs the direction it moves "
                            "along (or an axis to turn about)")
    if k == "servo":
        given = [key for key in _TARGETS if getattr(m, key) is not None]
        if len(given) != 1:
            raise GsiInputError(f"{p}stress: give exactly one of stress (Pa), force (N), "
                                f"stress_schedule or force_schedule (got {', '.join(given) or 'none'})")
        if m.max_speed is None:
            raise GsiInputError(f"{p}max_speed: missing; a servo wall needs its largest speed "
                                "(m/s)")
        if m.area is None and known and planes:
            raise GsiInputError(f"{p}area: missing; a plane is infinite: give the area (m^2) "
                                "the particles press on")
        sched = getattr(m, given[0]) if given[0].endswith("schedule") else None
        if sched is not None:
            if not sched:
                raise GsiInputError(f"{p}{given[0]}: empty; give a list of {{t, value}}")
            ts = [s.t for s in sched]
            if any(b <= a for a, b in zip(ts, ts[1:])):
                raise GsiInputError(f"{p}{given[0]}: times must increase ({ts})")
    if k == "free":
        key = "inertia" if m.axis is not None else "mass"
        if getattr(m, key) is None:
            raise GsiInputError(f"{p}{key}: missing; a free wall needs "
                                f"{'inertia (kg m^2) about its axis' if key == 'inertia' else 'mass (kg)'}")
        if m.axis is None and m.inertia is not None:
            raise GsiInputError(f"{p}inertia: only for a hinged wall (with axis); a "
                                "translating free wall takes mass (kg)")
        if m.centre_of_mass is not None and m.axis is None:
            raise GsiInputError(f"{p}centre_of_mass: only for a hinged wall (with axis)")


def _schedule(points):
    t = np.array([s.t for s in points], float)
    v = np.array([s.value for s in points], float)
    return (lambda time: float(np.interp(time, t, v))), float(np.abs(v).max())


def make_driver(m, handles, sim, key="motion"):
    """The driver (:mod:`gsi.dem.wall_drivers`) of a driven motion ``m`` (key path
    ``key``) of the walls ``handles``, added to ``sim``."""
    from gsi.dem.wall_drivers import FreeWall, Oscillation, Servo
    if m.kind == "oscillation":
        d = Oscillation(handles, amplitude=m.amplitude, frequency=m.frequency, phase=m.phase,
                        direction=m.direction, axis=m.axis, centre=m.centre,
                        update_every=m.update_every)
    elif m.kind == "servo":
        stress = m.stress is not None or m.stress_schedule is not None
        if m.stress_schedule is not None or m.force_schedule is not None:
            target, peak = _schedule(m.stress_schedule or m.force_schedule)
        else:
            target = m.stress if m.stress is not None else m.force
            peak = abs(target)
        d = Servo(handles[0], target=target, peak=peak, max_speed=m.max_speed,
                  direction=m.direction, area=m.area, gain=m.gain, stress=stress,
                  update_every=m.update_every, key=key)
    else:
        d = FreeWall(handles[0], gravity=sim.g, mass=m.mass if m.axis is None else None,
                     inertia=m.inertia, direction=m.direction, axis=m.axis, centre=m.centre,
                     mass_for_gravity=m.mass, centre_of_mass=m.centre_of_mass,
                     spring=m.spring, damper=m.damper)
    return sim.drivers.add(d)


def check_servo_gains(case, dt: float) -> None:
    """Refuse a servo ``gain`` above the stability limit 1/(K k dt) before the run (the
    stiffness estimate of :class:`gsi.dem.wall_drivers.Servo` from the case's smallest
    planned radius and its materials; the run checks it again with its particles)."""
    from gsi.dem.wall_drivers import projected_area, stiffness_estimate
    mats = case.dem_materials()
    r = case.smallest_radius()
    for i, w in enumerate(case.walls):
        m = w.motion
        if m.kind != "servo" or m.gain is None:
            continue
        if m.area is not None:
            area = m.area
        else:
            V, T = w.surface(base_dir=case.base_dir)
            area = projected_area(V, T, np.asarray(m.direction, float)
                                  / np.linalg.norm(m.direction))
        sched = m.stress_schedule or m.force_schedule
        peak = max(abs(s.value) for s in sched) if sched else abs(
            m.stress if m.stress is not None else m.force)
        force = peak * area if (m.stress is not None or m.stress_schedule) else peak
        wm = mats[w.material]
        E_eff = max(1.0 / ((1 - p.nu ** 2) / p.E + (1 - wm.nu ** 2) / wm.E)
                    for p in (mats[s.material] for s in case.particles))
        K = stiffness_estimate(E_eff=E_eff, r=r, force=force, area=area,
                               k_linear=case.dem.k_n if case.dem.contact == "linear" else None)
        limit = 1.0 / (K * m.update_every * dt)
        if m.gain > limit:
            raise GsiInputError(f"walls[{i}].motion.gain = {m.gain:g}: above the stability "
                                f"limit 1/(K k dt) = {limit:.3g} m/(s N) (K = {K:.3g} N/m, the "
                                f"wall contacts' stiffness); lower it or leave it out "
                                f"(default 0.5 of the limit)")
