"""Walls that respond: periodic motion, servo control and free rigid walls.

A *driver* sets a plane's or a mesh wall's velocity (and, for a mesh wall, its angular
velocity) before every DEM step, from the simulation time and the wall's force of the
last step.  Drivers are added with ``sim.drivers.add(driver)`` (:class:`WallDrivers`); while a
simulation has one, the step loop (:mod:`gsi.dem.step_loop`) runs chunks up to the next driver update
(``update_every`` steps: 1 by default, always 1 for a free wall) and calls
:meth:`WallDrivers.drive` before each (a call into the compiled engine per chunk, whose
arguments numba types each time: about 5e-5 to 4e-4 s, measured in
``benchmarks/driven_walls.py``); without a driver, the loop is unchanged.

All three act along one *axis* (a unit vector ``direction``) or about one hinge axis
(``axis`` through ``centre``, mesh walls only):

:class:`Oscillation`
    Prescribed periodic motion s(t) = A [sin(2 pi f t + phi) - sin(phi)] (m along
    ``direction``, or rad about ``axis``): the wall starts where it was built.  The
    velocity of the step [t, t + dt] is the secant (s(t + dt) - s(t))/dt, so the wall
    position is exact at every step (the rotation exact too: the mesh kernel turns by
    omega dt).  Peak acceleration A (2 pi f)^2: the dimensionless Gamma = A w^2/g.
:class:`Servo`
    Holds a target normal force N_t(t) (N) or stress sigma_t(t) A (Pa over the area A):
    N = -F . d is the particles' push on the wall against ``direction`` d (d points from
    the wall into the particles).  Proportional control of the velocity,
    v = clip(G (N_t - N), -v_max, v_max) d, with gain G (m/(s N)) and ``max_speed``
    v_max (m/s).  **Stability rule**: a wall step dx = v dt changes the contact force
    by K dx, K the summed normal stiffness of the wall's contacts, so one step maps the
    error e -> (1 - G K dt) e: monotone for G K dt <= 1, unstable above 2.  gsi takes
    G = 0.5/(K dt) by default and refuses a user gain with G K dt > 1, with K estimated
    from above (:func:`wall_stiffness`: every particle of the smallest radius in the
    area A in a hexagonal layer, N_t shared equally; Hertz k_n = (6 E*^2 R f)^(1/3)
    at force f, or the linear law's k_n).  The bed behind the contacts is softer than
    the contacts alone, so the true G K dt is smaller: slower, never less stable.  With
    a schedule, the target is piecewise linear in time between the given points and
    constant beyond them.
:class:`FreeWall`
    A rigid wall with mass M (kg) on one translational degree of freedom along d, or a
    moment of inertia I (kg m^2) about a hinge ``axis`` through ``centre``, moved by the
    particles' force (or torque about the hinge axis), gravity (acting at
    ``centre_of_mass``, by default on the axis), and an optional spring k (N/m or
    N m/rad) and damper c (N s/m or N m s/rad) to ground about the built position.
    Integrated as the particles are (velocity Verlet in its leapfrog form): after the
    step n the force F_n of that step's force pass gives v_{n+1/2} = v_{n-1/2} + dt F_n/M
    (the first step takes half of it), and the next step moves the wall by v_{n+1/2} dt.
    The wall's contact force is the sum of minus the forces on the particles, evaluated
    at the same instant: the impulses are equal and opposite, so particles plus wall
    conserve momentum to round-off (without gravity and other walls).  The damper uses
    v_{n-1/2} (explicit, as the contacts' damping uses the last velocities).

Notes
-----
* Walls stand still while the simulation holds no particles (the step loop counts
  the clock only); an oscillation keeps its clock, so its phase is the simulation time's.
* A driver's own state (next update, velocity, a free wall's half-step velocity, a
  servo's gain and target) is in the simulation's checkpoints (:meth:`_Axial.state`):
  a restart continues bit-identically.
"""
import math

from collections import namedtuple

import numpy as np

from gsi.dem.materials import P_E, P_KN
from gsi.dem.walls import PlaneWall, vec3
from gsi.errors import GsiInputError

#: default fraction G K dt of the servo's stability limit (monotone below 1)
SERVO_ALPHA = 0.5
#: contacts per area of one hexagonal layer of spheres of radius r: 1/(2 sqrt(3) r^2)
HEX_LAYER = 1.0 / (2.0 * math.sqrt(3.0))


def _unit(v, key):
    a = vec3(v, key)
    n = np.linalg.norm(a)
    if n == 0:
        raise GsiInputError(f"{key} = {list(v)}: must be a nonzero vector")
    return a / n


class WallDrivers:
    """The drivers of one simulation (empty: the step loop runs as without walls that
    respond)."""

    def __init__(self):
        self.items = []

    def __bool__(self):
        return bool(self.items)

    def add(self, driver):
        self.items.append(driver)
        return driver

    def drive(self, now, time, dt, bed):
        """Set the velocity of every driven wall due for an update (step ``now``, at
        ``time`` (s), has reached its next update) for its next ``every`` steps of ``dt``
        (s); ``bed`` (:class:`Bed`) is what a servo's gain rule reads of the particles.
        Returns the steps until the next update of any driver (the step loop's chunk)."""
        for d in self.items:
            if now >= d.next_step:
                d.drive(time, dt, bed)
                d.next_step = now + d.every
        return self.steps_due(now)

    def steps_due(self, now):
        """Steps from ``now`` to the next update of any driver (>= 1)."""
        return max(1, min(d.next_step for d in self.items) - now)


class _Axial:
    """One degree of freedom of a wall: translation along ``direction`` or rotation
    about ``axis`` through ``centre`` (mesh walls only)."""

    def __init__(self, walls, *, direction=None, axis=None, centre=None, what="wall driver"):
        self.walls = list(walls) if isinstance(walls, (list, tuple)) else [walls]
        if direction is not None and axis is not None:
            raise GsiInputError(f"{what}.axis: give one of direction (translation) or axis "
                                "(rotation), not both")
        self.rotates = axis is not None
        if self.rotates:
            if any(isinstance(w, PlaneWall) for w in self.walls):
                raise GsiInputError(f"{what}.axis: a plane cannot rotate; use a mesh wall "
                                    "(kind = 'plate')")
            if centre is None:
                raise GsiInputError(f"{what}.centre: missing; a rotation needs a point of "
                                    "its axis (m)")
            self.d = _unit(axis, f"{what}.axis")
            for w in self.walls:
                w.set_motion(centre=vec3(centre, f"{what}.centre"))
        else:
            if direction is None:
                if not isinstance(self.walls[0], PlaneWall):
                    raise GsiInputError(f"{what}.direction: missing; a mesh wall needs the "
                                        "direction (or axis) it moves along")
                direction = self.walls[0].normal
            self.d = _unit(direction, f"{what}.direction")
        self.ref = self._place()
        self.every = 1              # steps between updates (Oscillation, Servo: update_every)
        self.next_step = 0          # step count of the next update
        self.angle = 0.0            # rotation since the start (rad)
        self.rate = 0.0             # velocity (m/s) or angular velocity (rad/s) now set

    def _place(self):
        w = self.walls[0]
        return float((w.point if isinstance(w, PlaneWall) else w.centre) @ self.d)

    @property
    def position(self):
        """Displacement along ``direction`` since the start (m), or the angle turned about
        ``axis`` (rad)."""
        return self.angle if self.rotates else self._place() - self.ref

    @property
    def load(self):
        """The particles' force on the wall along ``direction`` (N) or their torque about
        the hinge axis (N m), at the last step (summed over the driven walls)."""
        if self.rotates:
            return float(sum(w.torque @ self.d for w in self.walls))
        return float(sum(w.force @ self.d for w in self.walls))

    def _set(self, rate, dt):
        self.rate = float(rate)
        for w in self.walls:
            if self.rotates:
                w.set_motion(omega=rate * self.d)
            elif isinstance(w, PlaneWall):
                w.set_motion(velocity=rate * self.d)
            else:
                w.set_motion(velocity=rate * self.d, omega=(0.0, 0.0, 0.0))
        if self.rotates:
            self.angle += rate * dt

    @property
    def velocity(self):
        """The velocity (m/s, rad/s) of the wall over the step now running."""
        return self.rate

    target = math.nan

    #: the driver's state beyond its walls' (checkpoints: gsi.dem.checkpoint_state)
    STATE_KEYS = ("next_step", "angle", "rate")

    def state(self):
        """The driver's state as one float array (NaN: unset)."""
        return np.array([math.nan if getattr(self, k) is None else float(getattr(self, k))
                         for k in self.STATE_KEYS])

    def set_state(self, a):
        """Restore :meth:`state` (the driver of a simulation built the same way)."""
        for k, v in zip(self.STATE_KEYS, a):
            cast = {"next_step": int, "started": bool}.get(k, float)
            setattr(self, k, None if math.isnan(v) else cast(v))


class Oscillation(_Axial):
    """Periodic motion s(t) = A [sin(2 pi f t + phi) - sin(phi)] (module docstring).

    Parameters
    ----------
    walls : PlaneWall, MeshWall or a list of them
    amplitude : float
        A (m along ``direction``; rad about ``axis``), > 0.
    frequency : float
        f (Hz), > 0.
    direction, axis, centre : (3,) float
        Translation direction (default: the first wall's normal), or the rotation axis
        and a point on it (m).
    phase : float, default 0
        phi (rad).
    update_every : int, default 1
        k: steps between velocity updates.  The secant velocity (s(t + k dt) - s(t))/(k dt)
        puts the wall exactly on s at every k-th step and on the chord between (off by at
        most A (w k dt)^2/8); k = 1 is exact at every step.  A larger k saves the one-step
        chunks' cost (:mod:`gsi.dem.wall_drivers`) where the path between may be a chord.
    """

    def __init__(self, walls, *, amplitude, frequency, direction=None, axis=None,
                 centre=None, phase=0.0, update_every=1):
        super().__init__(walls, direction=direction, axis=axis, centre=centre,
                         what="oscillation")
        self.every = _steps(update_every, "oscillation.update_every")
        if not amplitude > 0 or not frequency > 0:
            raise GsiInputError(f"oscillation: amplitude = {amplitude} and frequency = "
                                f"{frequency} must be > 0")
        self.A, self.w, self.phi = float(amplitude), 2.0 * math.pi * float(frequency), float(phase)

    def s(self, t):
        """The prescribed displacement (m) or angle (rad) at time ``t`` (s)."""
        return self.A * (math.sin(self.w * t + self.phi) - math.sin(self.phi))

    def gamma(self, g):
        """Gamma = A w^2/|g| (-), the peak acceleration in units of gravity."""
        return self.A * self.w ** 2 / float(np.linalg.norm(g))

    def drive(self, t, dt, bed):
        h = self.every * dt
        self._set((self.s(t + h) - self.s(t)) / h, h)


def stiffness_estimate(*, E_eff, r, force, area, k_linear=None):
    """An upper estimate K (N/m) of the summed normal stiffness of the contacts of a wall
    carrying ``force`` (N) over ``area`` (m^2): N_c = area/(2 sqrt(3) r^2) contacts (a
    hexagonal layer of spheres of the smallest radius ``r``), each carrying f = force/N_c,
    Hertz k_n = (6 E*^2 r f)^(1/3) (``E_eff`` = E* of the stiffest particle-wall pair,
    Pa), or the linear law's ``k_linear`` (N/m)."""
    n_c = max(1.0, HEX_LAYER * area / r ** 2)
    if k_linear is not None:
        return n_c * float(k_linear)
    return n_c * (6.0 * E_eff ** 2 * r * abs(force) / n_c) ** (1.0 / 3.0)


Bed = namedtuple("Bed", ["store", "materials", "linear"])
"""What a servo's stability rule reads of the particles: the particle store
(:class:`gsi.dem.storage.ParticleStore`), the :class:`gsi.dem.material_set.MaterialSet`
(names and pair table) and whether the contact law is linear."""


def bed_of(sim) -> Bed:
    """The :class:`Bed` of a simulation (the step loop passes it to the drivers)."""
    return Bed(sim.store, sim.material_set, sim.contact == "linear")


def wall_stiffness(bed, wall, force, area):
    """:func:`stiffness_estimate` for ``wall`` and the particles of ``bed`` (:class:`Bed`)
    now (0 without particles)."""
    if bed.store.n == 0:
        return 0.0
    P, table = bed.store.particles(), bed.materials.table
    wt = bed.materials.index(wall.material)
    types = np.unique(P.type)
    k_lin = float(table[types, wt, P_KN].max()) if bed.linear else None
    return stiffness_estimate(E_eff=float(table[types, wt, P_E].max()),
                              r=float(P.radius.min()), force=force, area=area,
                              k_linear=k_lin)


class Servo(_Axial):
    """A wall that moves along ``direction`` to hold a target force or stress (module
    docstring).

    Parameters
    ----------
    wall : PlaneWall or MeshWall
    target : float or callable
        The target: a constant or a function of time t (s), in N (``area`` None) or Pa.
    max_speed : float
        v_max (m/s), > 0.
    direction : (3,), optional
        d, from the wall into the particles (default: the plane's normal; needed for a
        mesh wall).
    area : float, optional
        A (m^2): the area of the stiffness estimate, and of the stress.  Default: the
        mesh wall's area projected on d (a plane needs ``area``).
    stress : bool, optional
        Whether ``target`` is a stress (Pa) over ``area`` (default: when ``area`` is
        given) or a force (N).
    gain : float, optional
        G (m/(s N)); default 0.5/(K dt) (:func:`wall_stiffness`), refused above 1/(K dt).
    peak : float, optional
        The largest target (same unit) for the stiffness estimate (default: ``target``
        when constant; needed with a callable).
    update_every : int, default 1
        k: steps between velocity updates; the stability rule becomes G K k dt <= 1.
    key : str, default "servo"
        The servo's name in the error that refuses ``gain`` (a case passes its key path).
    """

    def __init__(self, wall, *, target, max_speed, direction=None, area=None, gain=None,
                 peak=None, stress=None, update_every=1, key="servo"):
        super().__init__(wall, direction=direction, what="servo")
        self.key = key              # the name of the servo in messages (a case's walls[i].motion)
        self.every = _steps(update_every, "servo.update_every")
        self.stress = area is not None if stress is None else bool(stress)
        if not callable(target):
            value = float(target)
            target = (lambda t: value)
            peak = value if peak is None else peak
        if peak is None:
            raise GsiInputError("servo.peak: missing; give the largest target of the "
                                "schedule (for the gain's stiffness estimate)")
        if not max_speed > 0:
            raise GsiInputError(f"servo.max_speed = {max_speed}: must be > 0 (m/s)")
        if area is None:
            if isinstance(self.walls[0], PlaneWall):
                raise GsiInputError("servo.area: missing; a plane is infinite: give the area "
                                    "(m^2) its particles press on")
            area = projected_area(self.walls[0].vertices, self.walls[0].triangles, self.d)
        elif not area > 0:
            raise GsiInputError(f"servo.area = {area}: must be > 0 (m^2)")
        self.area = float(area)
        self.target_of = target
        self.peak_force = abs(float(peak)) * (self.area if self.stress else 1.0)
        self.v_max = float(max_speed)
        self.user_gain = None if gain is None else float(gain)
        self.gain = None           # set at the first step with particles (needs them)

    STATE_KEYS = _Axial.STATE_KEYS + ("gain", "_target")

    def target_force(self, t):
        """N_t(t) (N)."""
        return float(self.target_of(t)) * (self.area if self.stress else 1.0)

    @property
    def target(self):
        """The target force of the step now running (N)."""
        return self._target

    _target = math.nan

    @property
    def normal_force(self):
        """N = -F . d: the particles' push on the wall (N) at the last step."""
        return -self.load

    def set_gain(self, dt, bed):
        """The gain G (m/(s N)) from the stability rule (class docstring) at steps of
        ``dt`` (s) for the particles of ``bed`` (:class:`Bed`); None without particles."""
        K = wall_stiffness(bed, self.walls[0], self.peak_force, self.area)
        if K == 0.0:
            return None
        limit = 1.0 / (K * self.every * dt)
        if self.user_gain is not None and self.user_gain > limit:
            raise GsiInputError(f"{self.key}.gain = {self.user_gain:g}: above the stability limit "
                                f"1/(K k dt) = {limit:.3g} m/(s N) (K = {K:.3g} N/m, the wall "
                                f"contacts' stiffness); lower it or leave it out "
                                f"(default {SERVO_ALPHA} of the limit)")
        self.stiffness = K
        return self.user_gain if self.user_gain is not None else SERVO_ALPHA * limit

    def drive(self, t, dt, bed):
        if self.gain is None:
            self.gain = self.set_gain(dt, bed)
            if self.gain is None:
                self._set(0.0, dt)
                return
        self._target = self.target_force(t)
        v = self.gain * (self._target - self.normal_force)
        self._set(min(self.v_max, max(-self.v_max, v)), self.every * dt)


def _steps(k, key):
    if int(k) != k or k < 1:
        raise GsiInputError(f"{key} = {k}: must be an integer >= 1 (DEM steps)")
    return int(k)


def projected_area(vertices, triangles, d):
    """Area (m^2) of triangles (``vertices`` (nv, 3) m, ``triangles`` (nt, 3)) projected
    on the plane normal to ``d``."""
    x = np.asarray(vertices, float)[np.asarray(triangles)]
    n = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    return 0.5 * float(np.abs(n @ d).sum())


class FreeWall(_Axial):
    """A rigid wall moved by the particles (module docstring).

    Parameters
    ----------
    wall : PlaneWall or MeshWall
    mass : float, optional
        M (kg) of a translating wall, > 0.
    inertia : float, optional
        I (kg m^2) about the hinge axis of a rotating wall, > 0.
    direction : (3,), optional
        The translation's direction (default: the plane's normal).
    axis, centre : (3,), optional
        Hinge axis and a point on it (m).
    gravity : (3,)
        g (m/s^2), the simulation's.
    mass_for_gravity : float, optional
        M (kg) of a hinged wall (its weight's torque about the hinge); default 0.
    centre_of_mass : (3,), optional
        Where gravity acts on a hinged wall (m); default: on the axis (no torque).
    spring : float, default 0
        k (N/m or N m/rad) to the built position.
    damper : float, default 0
        c (N s/m or N m s/rad).
    velocity : float, default 0
        Initial velocity (m/s or rad/s).
    """

    def __init__(self, wall, *, gravity, mass=None, inertia=None, direction=None, axis=None,
                 centre=None, mass_for_gravity=None, centre_of_mass=None, spring=0.0,
                 damper=0.0, velocity=0.0):
        super().__init__(wall, direction=direction, axis=axis, centre=centre,
                         what="free wall")
        key, value = ("inertia", inertia) if self.rotates else ("mass", mass)
        if value is None or not value > 0:
            raise GsiInputError(f"free wall.{key} = {value}: must be > 0 "
                                f"({'kg m^2' if self.rotates else 'kg'})")
        if spring < 0 or damper < 0:
            raise GsiInputError(f"free wall.spring = {spring}, damper = {damper}: must be >= 0")
        self.inertia = float(value)
        self.g = vec3(gravity, "gravity")
        self.k, self.c = float(spring), float(damper)
        self.rate = float(velocity)
        self.v_half = self.rate         # v_{n-1/2}
        self.started = False
        if self.rotates:
            m = 0.0 if mass_for_gravity is None else float(mass_for_gravity)
            cm = np.asarray(centre if centre_of_mass is None else centre_of_mass, float)
            self.r_cm = cm - vec3(centre, "free wall.centre")
            self.weight = m * self.g
        else:
            self.weight = float(value) * self.g

    STATE_KEYS = _Axial.STATE_KEYS + ("v_half", "started")

    def _gravity(self):
        """Gravity's force along d (N) or torque about the axis (N m) now."""
        if not self.rotates:
            return float(self.weight @ self.d)
        th, k, r = self.angle, self.d, self.r_cm
        r = r * math.cos(th) + np.cross(k, r) * math.sin(th) + k * (k @ r) * (1 - math.cos(th))
        return float(np.cross(r, self.weight) @ k)

    def acceleration(self):
        """Acceleration (m/s^2 or rad/s^2) from the last step's loads."""
        F = self.load + self._gravity() - self.k * self.position - self.c * self.v_half
        return F / self.inertia

    def momentum(self, dt):
        """M v (kg m/s) or I omega (kg m^2/s) at the end of the last step: v_n = v_{n-1/2} +
        dt/2 a_n (the particles' velocities are at the same instant)."""
        v = self.v_half + (0.5 * dt * self.acceleration() if self.started else 0.0)
        return self.inertia * v

    def drive(self, t, dt, bed):
        a = self.acceleration()
        if self.started:
            v = self.v_half + dt * a
        else:
            v = self.v_half + 0.5 * dt * a
            self.started = True
        self.v_half = v
        self._set(v, dt)
