"""The rotating drum of Haydar, Martin & Bonnefoy (2023), "Long time extrapolation of DEM
with heat conduction in a moving granular medium", Chem. Eng. Sci. 277, 118815.

The paper gives the particles and the speed (its Tables 3-4) but not the drum:

- particles r = 5 mm (the table's "0.005 mm" is a slip: dt = 1e-4 s is 0.23 Rayleigh
  times only for 5 mm), E = 1e7 Pa, nu = 0.3, rho = 2500 kg/m^3, e = 0.2, mu_pp = 0.3,
  mu_pw = 0.5, mu_r = 0.002 (both), k = 100 W/(m K), c_p = 840 J/(kg K), Hertz contacts
  with rolling resistance, the "area" conductance H = 2 k sqrt(pi a^2);
- 5 s per turn; at t_init the left half (x < 0) at 30 K, the right half at 10 K; the wall
  is adiabatic.

The drum chosen here for 80,000 particles (:data:`REFERENCE`): inner radius R = 0.30 m,
length L = 2 R = 0.60 m, axis horizontal (along y), so the settled bed fills about 40 %
of it; at 5 s per turn its Froude number is Fr = omega^2 R/g = 0.0483, the cascading
regime, as the paper says of 5 s per turn (its Fig. 11: 15 s per turn rolling, 0.1 s
centrifuging; with R = 0.30 m those are Fr = 0.0054 and 121).

Smaller drums (:func:`drum_geometry`) keep the shape (L = 2 R), the fill and Fr: for N
particles of the same size, R scales by lambda = (N/80,000)^(1/3) and the period by
sqrt(lambda) (omega^2 R fixed).  The CI drum, 5,000 particles, is R = 0.1191 m turning
once in 3.1498 s.  ``drum_geometry(N, reference_period=ROLLING_PERIOD)`` is the family
of the seed's rolling regime (its Figs. 11a, 12: the 80,000-particle drum at 15 s per
turn, Fr = 0.0054), scaled the same way (the 640-particle drum: 6.708 s per turn).

Regimes (:func:`regime`) after Mellmann (2001), Powder Technol. 118, 251-270, whose
ranges overlap; here split at Fr = 1e-4 (slumping/rolling), 1e-2 (rolling/cascading),
0.1 (cascading/cataracting) and 1 (centrifuging).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gsi.errors import GsiInputError

__all__ = ["DrumGeometry", "REFERENCE", "drum_geometry", "froude", "regime", "drum_case",
           "PARTICLE_RADIUS", "DT", "DT_SPLIT", "EVERY", "T_HOT", "T_COLD", "ROLLING_PERIOD",
           "prepare", "restore", "extrapolation_member"]

#: particle radius (m), seed 003 Table 3
PARTICLE_RADIUS = 0.005
#: DEM step (s), 0.23 Rayleigh times of the particles
DT = 1.0e-4
#: seed 003's contact-log sampling: every n = 10 steps, rows of at most Delta t_c^max =
#: 10 DEM steps = 0.001 s (its reference case, section 3.1, and "n = 10 and m = 10", the
#: scenario it keeps after its Fig. 10 sweep and uses for its Table 8).  gsi's case
#: schema keeps 0.01 s (100 steps) as the general default (docs/design.md, "Long-time
#: heat extrapolation": on the quick drum the two agree in eq. 10 to 0.1 % of the heat
#: moved, and 0.01 s writes a smaller log)
EVERY = 10
DT_SPLIT = 1.0e-3
#: initial temperatures (K) of the left (x < 0) and right halves, seed 003 Table 4
T_HOT = 30.0
T_COLD = 10.0
#: gravity (m/s^2)
G = 9.81


def froude(radius: float, period: float) -> float:
    """Fr = omega^2 R/g of a drum of inner ``radius`` R (m) turning once per ``period`` (s)."""
    return (2.0 * math.pi / period) ** 2 * radius / G


def regime(fr: float) -> str:
    """The bed's regime at Froude number ``fr`` (see the module docstring)."""
    if fr < 1e-4:
        return "slumping"
    if fr < 1e-2:
        return "rolling"
    if fr < 0.1:
        return "cascading"
    if fr < 1.0:
        return "cataracting"
    return "centrifuging"


@dataclass(frozen=True)
class DrumGeometry:
    """A drum of the family (module docstring).

    Attributes
    ----------
    particles : int
    radius, length : float
        Inner radius and length (m); the axis is y, from y = 0 to y = length, through
        x = z = 0.
    steps_per_turn : int
        DEM steps of :data:`DT` per turn.
    """

    particles: int
    radius: float
    length: float
    steps_per_turn: int

    @property
    def period(self) -> float:
        """Time of one turn (s)."""
        return self.steps_per_turn * DT

    @property
    def rpm(self) -> float:
        return 60.0 / self.period

    @property
    def froude(self) -> float:
        return froude(self.radius, self.period)

    @property
    def regime(self) -> str:
        return regime(self.froude)


#: the 80,000-particle drum (module docstring)
REFERENCE = DrumGeometry(particles=80_000, radius=0.30, length=0.60, steps_per_turn=50_000)


#: seconds per turn of the 80,000-particle drum in the seed's rolling regime (its Figs.
#: 11a and 12; Fr = 0.0054 at R = 0.30 m)
ROLLING_PERIOD = 15.0


def drum_geometry(particles: int, reference_period: float | None = None) -> DrumGeometry:
    """The drum of the family holding ``particles`` spheres of r = 5 mm at the reference
    fill and Froude number (R, L by lambda = (N/80,000)^(1/3), rounded to 0.1 mm; the
    period by sqrt(lambda), rounded to whole DEM steps; Fr within 0.1 % of the
    reference).  ``reference_period`` (s): the 80,000-particle drum's time per turn that
    sets the Froude number (default the seed's reference, 5 s, cascading;
    :data:`ROLLING_PERIOD`, 15 s, is its rolling regime)."""
    if not (isinstance(particles, (int, np.integer)) and 50 <= particles <= 2_000_000):
        raise GsiInputError(f"particles = {particles}: must be an integer in [50, 2e6]")
    turn = REFERENCE.steps_per_turn
    if reference_period is not None:
        if not (isinstance(reference_period, (int, float)) and 0.05 <= reference_period <= 1e3):
            raise GsiInputError(f"reference_period = {reference_period!r}: must be the "
                                "80,000-particle drum's seconds per turn, in [0.05, 1000] "
                                "(5 cascading, 15 rolling)")
        turn = int(round(reference_period / DT))
    lam = (particles / REFERENCE.particles) ** (1.0 / 3.0)
    steps = int(round(turn * math.sqrt(lam)))
    return DrumGeometry(particles=int(particles), radius=round(REFERENCE.radius * lam, 4),
                        length=round(REFERENCE.length * lam, 4), steps_per_turn=steps)


def drum_case(geometry: DrumGeometry, *, settle: float = 1.0, duration: float | None = None,
              heat: str = "area", seed: int = 3, facets: int | None = None,
              extrapolation: bool = False, spin_up: float = 1.0, period_turns: float = 1.0,
              periods: int = 6, every: int = EVERY, dt_split: float = DT_SPLIT,
              name: str | None = None, skin: float | None = None, dt: float = DT):
    """The drum as a :class:`gsi.case.Case`: materials of seed 003 Tables 3-4, a closed
    ``drum`` wall (adiabatic) at rest for ``settle`` seconds and then turning once per
    ``geometry.period``, and a lattice fill of ``geometry.particles`` spheres from the
    bottom of the drum (at 293.15 K).

    Parameters
    ----------
    geometry : DrumGeometry
    settle : float
        Time (s) the drum stands still while the fill settles.
    duration : float, optional
        ``run.duration`` (s); default ``settle`` + one turn, or with ``extrapolation``
        the end of its comparison.
    heat : str
        ``dem.heat`` ("area" as the paper, LIGGGHTS' model).
    seed : int
    facets : int, optional
        Vertices around the drum axis (default: triangles about 2 particle radii wide,
        at least 48).
    extrapolation : bool
        Add the ``[extrapolation]`` table of the paper's study: at ``settle`` the left
        half (x < 0) at :data:`T_HOT` and the right half at :data:`T_COLD`, ``spin_up``
        turns, then one period of ``period_turns`` turns logged (sampling ``every``,
        ``dt_split`` s) and extrapolated over ``periods`` periods, compared with the
        DEM run on.
    name : str, optional
        ``case.name`` (default ``drum_<N>``).
    skin : float, optional
        ``dem.skin`` (m; default gsi's, 0.4 particle radii). Only the neighbour lists
        depend on it (more candidates, fewer rebuilds); results agree to round-off.
    dt : float
        ``run.dt`` (s; default :data:`DT`). The turns stay whole numbers of
        ``geometry.steps_per_turn`` steps; a test changes it by 1e-12 relative to change
        only the round-off of every step (tests/validation/conftest.py).
    """
    from gsi.case import (Case, CaseInfo, Dem, Material, Output, ParticleSource, Region,
                          Run, Size, Wall)
    from gsi.case.materials import Pair
    from gsi.case.walls import Motion
    R, L, r = geometry.radius, geometry.length, PARTICLE_RADIUS
    if facets is None:
        facets = max(48, int(math.ceil(2 * math.pi * R / (2.5 * r))))
    grain = Material(E=1.0e7, nu=0.3, rho=2500.0, e=0.2, mu=0.3, mu_r=0.002, k=100.0, cp=840.0)
    wall = Material(E=1.0e7, nu=0.3, rho=2500.0, e=0.2, mu=0.5, mu_r=0.002, k=100.0, cp=840.0)
    margin = round(0.05 * R + 4 * r, 3)
    fill = ParticleSource(
        name="grains", material="grain", fill="lattice", count=geometry.particles,
        size=Size(kind="single", radius=r),
        region=Region(kind="cylinder", centre=(0.0, 0.5 * r, 0.0), axis=(0.0, 1.0, 0.0),
                      radius=round(R - 0.2 * r, 6), length=round(L - r, 6)))
    xp = None
    end = settle + geometry.period
    if extrapolation:
        from gsi.case.extrapolation import Extrapolation, Halves
        steps = int(round(period_turns * geometry.steps_per_turn))
        start = round(settle + round(spin_up * geometry.steps_per_turn) * DT, 10)
        xp = Extrapolation(start=start, period=round(steps * DT, 10), periods=periods,
                           every=every, dt_split=dt_split, compare=True, cells=200,
                           halves=Halves(t=settle, axis="x", at=0.0, below=T_HOT,
                                         above=T_COLD))
        end = xp.end()
    return Case(
        case=CaseInfo(name=name or f"drum_{geometry.particles}",
                      description=f"seed-003 drum, {geometry.particles} spheres of r = 5 mm, "
                                  f"R = {R:.4g} m, {geometry.period:.4g} s per turn "
                                  f"(Fr = {geometry.froude:.3g}, {geometry.regime})"),
        run=Run(duration=end if duration is None else duration, dt=dt, seed=seed,
                progress=False),
        dem=Dem(contact="hertz", rolling=True, heat=heat, gravity=(0.0, 0.0, -G), skin=skin,
                domain_lo=(round(-R - margin, 6), -margin, round(-R - margin, 6)),
                domain_hi=(round(R + margin, 6), round(L + margin, 6), round(R + margin, 6))),
        materials={"grain": grain, "drum_wall": wall},
        pairs=[Pair(materials=("grain", "drum_wall"), e=0.2, mu=0.5, mu_r=0.002)],
        particles=[fill],
        walls=[Wall(kind="drum", name="drum", material="drum_wall", centre=(0.0, 0.0, 0.0),
                    axis=(0.0, 1.0, 0.0), radius=R, length=L, facets=facets,
                    motion=Motion.schedule([dict(t=settle, rpm=round(geometry.rpm, 6))]))],
        output=Output(interval=geometry.period if xp is None else xp.period, pictures=False,
                      color_by="temperature", view="+y"),
        extrapolation=xp)


def prepare(geometry: DrumGeometry, *, settle: float = 0.8, spin_up: float = 1.0,
            seed: int = 3, state: str | None = None, chunk: int = 5000, say=None,
            timing: dict | None = None, skin: float | None = None, dt: float = DT):
    """Fill, settle and spin up a drum of the family (the paper's set-up before t0).

    The lattice fill settles with the drum at rest for ``settle`` s; then the left half
    (x < 0) is set to :data:`T_HOT` and the right half to :data:`T_COLD` (t_init), the
    drum starts turning, and it turns ``spin_up`` turns.

    With ``state`` (a ``.npz`` path) the set-up can be spread over several runs: every
    ``chunk`` steps the whole DEM state (:meth:`gsi.dem.Simulation.state`), the hot
    flags and the steps done are written to ``state`` (crash-safe: a temporary file
    renamed over it), and a run that finds the file resumes from it, bit-identically to
    an uninterrupted set-up (the simulation is rebuilt the same way); a file written for
    another drum, settle, seed or skin is refused; one written for fewer spin-up turns is
    extended (it is this set-up's prefix). ``say(msg)`` gets a line per chunk.
    ``timing`` (a dict), if given, receives ``spin_seconds`` and ``spin_steps``: the wall
    seconds and steps of the turning drum, summed over all the runs that made this
    set-up (kept in the state file), so the spin-up's own rate can be reported.
    ``skin`` and ``dt`` are :func:`drum_case`'s.

    Returns
    -------
    sim : gsi.dem.Simulation
        At t0 (end of the spin-up).
    hot : (N,) bool
        By particle id (``sim.ids`` are 0..N-1): the particle was hot at t_init.
    case : gsi.case.Case
    """
    import pathlib
    import time
    from gsi.case.build_dem import build_simulation
    say = say or (lambda m: None)
    case = drum_case(geometry, settle=settle, seed=seed, skin=skin, dt=dt)
    dt = case.check()
    sim, handles, _ = build_simulation(case, dt=dt)
    n_settle = int(round(settle / dt))
    n_total = n_settle + int(round(spin_up * geometry.steps_per_turn))
    key = np.array([geometry.particles, geometry.steps_per_turn, n_settle, n_total, seed,
                    round(sim.skin * 1e9)], np.int64)
    done, hot, spin = 0, None, np.zeros(2)       # spin: seconds, steps of the turning drum
    path = pathlib.Path(state) if state is not None else None
    if path is not None and path.exists():
        from gsi.checkpoint import read_npz
        d = read_npz(path)
        old = np.asarray(d["drum.key"])
        done = int(d["drum.done"])
        # a set-up of fewer spin-up turns is this one's prefix (the set-up is deterministic
        # and a step does not depend on the total): it is extended
        prefix = (old.shape == key.shape and np.array_equal(np.delete(old, 3), np.delete(key, 3))
                  and done <= n_total)
        if not prefix:
            raise GsiInputError(
                f"state = {str(path)!r} was written for another drum set-up (particles, "
                f"steps per turn, settle and total steps, seed, skin in nm = "
                f"{d['drum.key'].tolist()}, "
                f"this one {key.tolist()}); remove it or give another path")
        sim.set_state({k: v for k, v in d.items() if not k.startswith("drum.")})
        spin = np.array(d["drum.spin"], float)
        if done >= n_settle:
            hot = np.array(d["drum.hot"], bool)
        say(f"resumed the set-up at step {done} of {n_total} from {path}")
    while True:
        if done == n_settle and hot is None:
            hot = np.zeros(sim.next_id, bool)
            hot[sim.ids] = sim.x[:, 0] < 0.0
            sim.T[:] = np.where(hot[sim.ids], T_HOT, T_COLD)
        if done >= n_settle:
            case.walls[0].apply_motion(handles["drum"], sim.time)
        if done >= n_total:
            break
        end = n_settle if done < n_settle else n_total
        k = min(end - done, chunk if path is not None else end - done)
        t = time.perf_counter()
        sim.step(k)
        if done >= n_settle:
            spin += (time.perf_counter() - t, k)
        done += k
        if path is not None:
            from gsi.checkpoint import write_npz
            d = sim.state()
            d.update({"drum.key": key, "drum.done": np.array(done), "drum.spin": spin,
                      "drum.hot": hot if hot is not None else np.zeros(0, bool)})
            write_npz(path, d)
            say(f"set-up step {done} of {n_total} (t = {sim.time:.4g} s) saved to {path}")
    if timing is not None:
        timing.update(spin_seconds=float(spin[0]), spin_steps=int(spin[1]))
    return sim, hot, case


def restore(geometry: DrumGeometry, state: dict, *, settle: float = 0.8, seed: int = 3,
            skin: float | None = None, dt: float = DT):
    """The drum simulation :func:`prepare` builds (same ``geometry``, ``settle``, ``seed``,
    ``skin``, ``dt``) set to ``state`` (:meth:`gsi.dem.Simulation.state` of such a drum,
    e.g. after :func:`prepare`): the next step continues bitwise where that simulation
    stood, turning wall included. This is how an ensemble's members start from one
    shared set-up in other processes (:func:`gsi.studies.ensemble.run_ensemble`).

    Returns
    -------
    sim : gsi.dem.Simulation
    case : gsi.case.Case
    """
    from gsi.case.build_dem import build_simulation
    case = drum_case(geometry, settle=settle, seed=seed, skin=skin, dt=dt)
    sim, _, _ = build_simulation(case, dt=case.check())
    sim.set_state(state)
    return sim, case


def extrapolation_member(k: int, geometry: DrumGeometry, start: dict, hot: np.ndarray,
                         dt: float, periods: int, twin_periods: int, *, settle: float = 0.5,
                         sampling: tuple = (EVERY, 0.01), twin_members: int | None = None
                         ) -> dict:
    """Member ``k`` of a drum-extrapolation ensemble (the quick-drum and rolling tests
    run it in :func:`gsi.studies.ensemble.run_ensemble`'s workers).

    From ``start`` (a :meth:`~gsi.dem.Simulation.state` after :func:`prepare` with
    ``spin_up=0``, so at the end of the settling, halves hot/cold by ``hot``) every
    position is moved by member ``k``'s perturbation (up to k x 0.5 nm,
    :func:`gsi.studies.ensemble.perturb`), the drum turns a quarter turn to t0, half a
    turn t0..t1 is logged with ``sampling`` = (n, Delta t_c^max s) and replayed for
    ``periods`` half turns against the DEM run on, with a twin DEM from t1 (every
    position moved by up to 1 nm) for ``twin_periods`` of them
    (:func:`gsi.extrapolation.compare_with_dem`). With ``twin_members`` only the members
    ``k < twin_members`` run the twin (a quarter of a member's steps at two of four
    periods): the reference DEM does not depend on it (it runs first), so eq. 10 and the
    hot/cold gap of a member are the same with or without it, bit for bit.

    Returns the plain arrays the tests use (picklable): ``run`` (``log``, ``T``, ``x``,
    ``eps_abs``, ``eps_rel``, ``energy_error`` (eq. 10 per period), ``energy_drift``),
    ``dem`` (``T``, ``x``, ``energy_drift``, ``twin``: ``T``, ``eps_abs``, or None),
    ``seeds``
    (eq. 9's cells), ``hot`` (by log order), the hot-minus-cold gaps ``gap_dem``,
    ``gap_ext``, ``gap_twin`` at t1.., and ``seconds`` (wall) of the member.
    """
    import time
    from gsi.extrapolation import compare_with_dem
    from gsi.studies.ensemble import perturb
    t = time.perf_counter()
    sim, _ = restore(geometry, start, settle=settle, dt=dt)
    perturb(sim.x, k)
    quarter = geometry.steps_per_turn // 4
    sim.step(quarter)                                           # spin-up to t0
    with_twin = twin_members is None or k < twin_members
    r = compare_with_dem(sim, period_steps=2 * quarter, periods=periods,
                         samplings=(tuple(sampling),), hot=hot,
                         twin=1e-9 if with_twin else None,
                         twin_periods=twin_periods if with_twin else None)
    run, dem = r["runs"][0], r["dem"]
    run = {key: run[key] for key in ("log", "T", "x", "eps_abs", "eps_rel", "energy_error",
                                     "energy_drift")}
    twin = {key: dem["twin"][key] for key in ("T", "eps_abs")} if with_twin else None
    dem = dict({key: dem[key] for key in ("T", "x", "energy_drift")}, twin=twin)
    h = hot[run["log"].ids]

    def gap(T):
        return T[:, h].mean(1) - T[:, ~h].mean(1)

    return dict(run=run, dem=dem, seeds=r["seeds"], hot=h, gap_dem=gap(dem["T"]),
                gap_ext=gap(run["T"]), gap_twin=gap(twin["T"]) if with_twin else None,
                seconds=time.perf_counter() - t)
