"""Wall motions of a case: ``motion = {kind = ...}`` of a ``[[walls]]`` entry
(:class:`Motion`, its schedule steps :class:`MotionEvent`); see :mod:`gsi.case.walls`
for the keys' use. The runner finds the next event with :func:`next_event` and applies
the motion state there (:meth:`Motion.state_at`)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from gsi.case.driven_motion import DRIVEN_KEYS, DRIVEN_KINDS, SchedulePoint, validate_driven
from gsi.case.regions import key_prefix
from gsi.config.schema import nonnegative, one_of, param, positive
from gsi.errors import GsiInputError

__all__ = ["Motion", "MotionEvent", "MOTION_KINDS", "RPM", "next_event"]

Vec3 = tuple[float, ...]
MOTION_KINDS = ("fixed", "translation", "rotation", "schedule") + DRIVEN_KINDS
#: rad/s per revolution per minute
RPM = 2.0 * math.pi / 60.0


def _time_tol(t: float) -> float:
    """Times closer than this are the same instant (s): sim.time = steps x dt is exact to
    round-off, far below it."""
    return 1e-9 * max(abs(t), 1e-3)


def _omega(rpm, omega) -> float | None:
    if rpm is not None:
        return rpm * RPM
    return omega


def _unit(v, key) -> np.ndarray:
    from gsi.dem.shapes import unit
    return unit(v, key=key)


@dataclass(kw_only=True)
class MotionEvent:
    """One step of a schedule: from ``t`` on, the wall moves with ``velocity`` and turns at
    ``rpm`` or ``omega`` about ``axis`` through ``centre`` (both default to the motion's,
    then the wall's)."""

    t: float = param(unit="s", check=nonnegative(), doc="time the event takes effect")
    velocity: Vec3 = param((0.0, 0.0, 0.0), unit="m/s", length=3, doc="translation velocity")
    rpm: Optional[float] = param(None, unit="1/min", doc="rotation speed about axis")
    omega: Optional[float] = param(None, unit="rad/s", doc="rotation speed about axis (not with rpm)")
    axis: Optional[Vec3] = param(None, unit="-", length=3, doc="rotation axis direction")
    centre: Optional[Vec3] = param(None, unit="m", length=3, doc="a point of the rotation axis")

    @property
    def turns(self) -> bool:
        w = _omega(self.rpm, self.omega)
        return w is not None and w != 0.0


@dataclass(kw_only=True)
class Motion:
    """How a wall moves (see the module docstring); velocities m/s, rotation rad/s or rpm."""

    kind: str = param("fixed", check=one_of(*MOTION_KINDS),
                      doc="fixed, translation, rotation, schedule; oscillation, servo or free "
                      "(gsi.case.driven_motion)")
    velocity: Optional[Vec3] = param(None, unit="m/s", length=3, doc="translation velocity")
    axis: Optional[Vec3] = param(None, unit="-", length=3,
                                 doc="rotation axis direction (default: the shape's axis)")
    centre: Optional[Vec3] = param(None, unit="m", length=3,
                                   doc="a point of the rotation axis (default: the shape's centre)")
    rpm: Optional[float] = param(None, unit="1/min", doc="rotation speed (revolutions per minute)")
    omega: Optional[float] = param(None, unit="rad/s", doc="rotation speed (not with rpm)")
    events: Optional[list[MotionEvent]] = param(
        None, doc="schedule: list of {t, velocity, rpm|omega, axis, centre}")
    # the driven kinds (gsi.case.driven_motion)
    amplitude: Optional[float] = param(None, unit="m or rad", check=positive(),
                                       doc="oscillation: amplitude (rad with axis)")
    frequency: Optional[float] = param(None, unit="Hz", check=positive(),
                                       doc="oscillation: frequency")
    phase: float = param(0.0, unit="rad", doc="oscillation: phase")
    update_every: int = param(1, check=positive(),
                              doc="oscillation, servo: DEM steps between velocity updates "
                              "(1: every step, exact)")
    direction: Optional[Vec3] = param(None, unit="-", length=3,
                                      doc="oscillation, servo, free: direction of the motion "
                                      "(servo: into the particles; default: a plane's normal)")
    stress: Optional[float] = param(None, unit="Pa", sane=False, doc="servo: target normal stress")
    force: Optional[float] = param(None, unit="N", doc="servo: target normal force")
    stress_schedule: Optional[list[SchedulePoint]] = param(
        None, doc="servo: target stress, list of {t, value} (Pa), piecewise linear")
    force_schedule: Optional[list[SchedulePoint]] = param(
        None, doc="servo: target force, list of {t, value} (N), piecewise linear")
    max_speed: Optional[float] = param(None, unit="m/s", check=positive(),
                                       doc="servo: largest wall speed")
    area: Optional[float] = param(None, unit="m^2", check=positive(),
                                  doc="servo: area the stress acts on (needed for a plane)")
    gain: Optional[float] = param(None, unit="m/(s N)", check=positive(),
                                  doc="servo: gain (default 0.5/(K dt), the stability rule)")
    mass: Optional[float] = param(None, unit="kg", check=positive(), doc="free: wall mass")
    inertia: Optional[float] = param(None, unit="kg m^2", check=positive(),
                                     doc="free: moment of inertia about the hinge axis")
    centre_of_mass: Optional[Vec3] = param(None, unit="m", length=3,
                                           doc="free hinged wall: where its weight acts")
    spring: float = param(0.0, unit="N/m or N m/rad", check=nonnegative(),
                          doc="free: spring to the built position")
    damper: float = param(0.0, unit="N s/m or N m s/rad", check=nonnegative(),
                          doc="free: damper to ground")

    # ---- construction helpers
    @classmethod
    def fixed(cls) -> "Motion":
        return cls()

    @classmethod
    def translation(cls, velocity) -> "Motion":
        m = cls(kind="translation", velocity=tuple(map(float, velocity)))
        m.validate("motion", has_axis=True)
        return m

    @classmethod
    def rotation(cls, *, axis=None, centre=None, rpm=None, omega=None) -> "Motion":
        m = cls(kind="rotation", axis=None if axis is None else tuple(map(float, axis)),
                centre=None if centre is None else tuple(map(float, centre)), rpm=rpm, omega=omega)
        m.validate("motion", has_axis=True)
        return m

    @classmethod
    def schedule(cls, events) -> "Motion":
        """``events``: MotionEvent objects or dicts of their keys."""
        evs = [e if isinstance(e, MotionEvent) else MotionEvent(**e) for e in events]
        m = cls(kind="schedule", events=evs)
        m.validate("motion", has_axis=True)
        return m

    # ---- validation
    def validate(self, path: str = "motion", *, has_axis: bool = True,
                 planes: bool | None = None, box: bool = False) -> None:
        """Keys match the kind.  ``has_axis=False``: the wall supplies no default axis and
        centre, so a rotation must give both (:meth:`Wall.validate` passes it);
        ``planes``/``box``: the wall is a plane or a box of planes (the driven kinds;
        None: the wall is not known yet, its checks wait for :meth:`Wall.validate`)."""
        p = key_prefix(path)
        uses = {"fixed": (), "translation": ("velocity",),
                "rotation": ("axis", "centre", "rpm", "omega"),
                "schedule": ("events", "axis", "centre"), **DRIVEN_KEYS}[self.kind]
        for key in _OPTIONAL_KEYS:
            if key not in uses and getattr(self, key) != _DEFAULTS[key]:
                fit = [k for k, u in (("translation", ("velocity",)),
                                      ("rotation", ("rpm", "omega", "axis", "centre")),
                                      ("schedule", ("events",)), *DRIVEN_KEYS.items())
                       if key in u]
                raise GsiInputError(f"{p}{key}: not a key of a '{self.kind}' motion; set "
                                    f"{p}kind = '{fit[0]}' or remove it" if fit else
                                    f"{p}{key}: not a key of a '{self.kind}' motion")
        if self.kind in DRIVEN_KINDS:
            validate_driven(self, p, planes=planes, box=box)
            for key in ("axis", "direction"):
                if getattr(self, key) is not None:
                    _unit(getattr(self, key), f"{p}{key}")
            return
        if self.kind == "translation" and self.velocity is None:
            raise GsiInputError(f"{p}velocity: missing; a translation needs a velocity (m/s)")
        if self.axis is not None:
            _unit(self.axis, f"{p}axis")
        if self.kind == "rotation":
            self._check_rotation(p, self.rpm, self.omega, self.axis, self.centre, has_axis)
        if self.kind == "schedule":
            if not self.events:
                raise GsiInputError(f"{p}events: missing; a schedule needs a list of "
                                    "{t, velocity, rpm|omega, axis, centre} events")
            prev = -math.inf
            for i, e in enumerate(self.events):
                q = f"{p}events[{i}]."
                if not e.t > prev + _time_tol(e.t):
                    raise GsiInputError(f"{q}t = {e.t}: event times must increase (previous "
                                        f"{prev} s)")
                prev = e.t
                if e.rpm is not None or e.omega is not None:
                    self._check_rotation(q, e.rpm, e.omega, e.axis or self.axis,
                                         e.centre or self.centre, has_axis)
                elif e.axis is not None or e.centre is not None:
                    raise GsiInputError(f"{q}{'axis' if e.axis is not None else 'centre'}: only "
                                        "with rpm or omega (a rotating event)")
                if e.axis is not None:
                    _unit(e.axis, f"{q}axis")

    @staticmethod
    def _check_rotation(p, rpm, omega, axis, centre, has_axis) -> None:
        if (rpm is None) == (omega is None):
            raise GsiInputError(f"{p}rpm: give exactly one of rpm (1/min) or omega (rad/s)")
        if not has_axis:
            for key, value in (("axis", axis), ("centre", centre)):
                if value is None:
                    raise GsiInputError(f"{p}{key}: missing; a rotation of this wall needs "
                                        "axis and centre")

    @property
    def driven(self) -> bool:
        """Whether the DEM drives the wall step by step (:mod:`gsi.case.driven_motion`)."""
        return self.kind in DRIVEN_KINDS

    @property
    def rotates(self) -> bool:
        """Whether the wall ever turns."""
        if self.driven:
            return self.axis is not None
        if self.kind == "rotation":
            return _omega(self.rpm, self.omega) != 0.0
        if self.kind == "schedule":
            return any(e.turns for e in self.events or ())
        return False

    @property
    def moves(self) -> bool:
        return self.kind != "fixed"

    # ---- state
    def event_times(self) -> list[float]:
        """Times (s) at which the motion changes (a schedule's event times; else none)."""
        return [e.t for e in self.events] if self.kind == "schedule" else []

    def next_event(self, t: float) -> float:
        """The first event time after ``t`` (s), or inf.  Step to it, then call
        :meth:`Wall.apply_motion` at the new time."""
        for te in self.event_times():
            if te > t + _time_tol(te):
                return te
        return math.inf

    def state_at(self, t: float, *, axis=None, centre=None):
        """The motion at time ``t`` (s): (velocity (3,) m/s, omega (3,) rad/s, centre).

        ``centre`` (3,) m is the rotation centre, or None when the state does not turn
        (the wall keeps its current reference point).  ``axis``, ``centre``: the wall's
        defaults when the motion gives none.  An event takes effect at its ``t`` (within
        1e-9 relative)."""
        zero = np.zeros(3)
        if self.kind == "fixed" or self.driven:      # a driver sets it before every step
            return zero, zero.copy(), None
        if self.kind == "translation":
            return np.asarray(self.velocity, float), zero, None
        if self.kind == "rotation":
            return zero, self._omega_vec(self.rpm, self.omega, self.axis or axis), \
                np.asarray(self.centre or centre, float)
        current = None
        for e in self.events:
            if e.t <= t + _time_tol(e.t):
                current = e
        if current is None:
            return zero, zero.copy(), None
        v = np.asarray(current.velocity, float)
        if not current.turns:
            return v, zero, None
        return v, self._omega_vec(current.rpm, current.omega, current.axis or self.axis or axis), \
            np.asarray(current.centre or self.centre or centre, float)

    @staticmethod
    def _omega_vec(rpm, omega, axis) -> np.ndarray:
        return _omega(rpm, omega) * _unit(axis, "motion.axis")

    # ---- checks
    def check(self, path: str = "motion", *, duration: float | None = None,
              has_axis: bool = True, planes: bool | None = None, box: bool = False) -> None:
        """Keys match the kind; no schedule event at or after the end ``duration`` (s) of
        the run (an error: such an event never happens, usually a unit slip)."""
        self.validate(path, has_axis=has_axis, planes=planes, box=box)
        if duration is None:
            return
        for i, t in enumerate(self.event_times()):
            if t >= duration - _time_tol(duration):
                raise GsiInputError(f"{key_prefix(path)}events[{i}].t = {t}: at or after the end of "
                                    f"the run (run.duration = {duration} s); it would never "
                                    "happen: move it earlier or remove it (s)")


_OPTIONAL_KEYS = ("velocity", "axis", "centre", "rpm", "omega", "events", "amplitude",
                  "frequency", "phase", "direction", "stress", "force", "stress_schedule",
                  "force_schedule", "max_speed", "area", "gain", "mass", "inertia",
                  "centre_of_mass", "spring", "damper", "update_every")
_DEFAULTS = {key: (0.0 if key in ("phase", "spring", "damper") else None)
             for key in _OPTIONAL_KEYS} | {"update_every": 1}


def next_event(walls, t: float) -> float:
    """The earliest motion event of ``walls`` (Wall objects) after ``t`` (s), or inf."""
    return min([w.motion.next_event(t) for w in walls], default=math.inf)
