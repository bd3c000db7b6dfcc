"""A heated kiln: the rotating drum of seed 003 (Haydar, Martin & Bonnefoy 2023, Chem.
Eng. Sci. 277, 118815) whose shell is an FE heat structure held hot on its outside.

The bed is the drum's (:mod:`gsi.studies.drum`): spheres of r = 5 mm with the materials of the
paper's Tables 3-4 (c_p = 840 J/(kg K), Hertz contacts with rolling resistance, the
"area" conductance) but a limestone-like conductivity :data:`K_GRAIN` = 2 W/(m K)
instead of 100 (``k_grain``), filled by lattice, settled with the kiln at rest,
the half y < 0 set to :data:`T_HOT` and the other to :data:`T_COLD`, then turned.

The kiln (:func:`kiln_case`):

- the shell is a steel tube (k = 53.3 W/(m K), c = 440 J/(kg K), rho = 7850 kg/m^3;
  :mod:`gsi.meshes.drum`, axis along x from 0 to L, inner radius R, 5 mm thick, P1) whose
  outer surface is held at :data:`T_SHELL` (a Dirichlet tag: the heating jacket), its
  ends insulated; it starts at :data:`T_SHELL` throughout;
- its inner surface is the DEM wall the bed touches (the wall material has the seed's
  contact parameters and the steel's conductivity), turning with the shell
  (``contact.motion``); the FE heat problem lives in the shell's own frame;
- the kiln's end plates (x = 0 and x = L) stand still and are adiabatic, as the seals of
  a rotary kiln;
- the heat between bed and shell: the live coupling (:mod:`gsi.coupling.thermal`) every
  ``n_sub`` DEM steps; the long-time replay (:class:`gsi.extrapolation.FEWallReplay`)
  after one logged period.

Sizes (:func:`kiln_geometry`): the drums of :func:`gsi.studies.drum.drum_geometry` (same fill and
Froude number for N particles) with the turn rounded to a whole number of
:data:`TURN_STEP` DEM steps, so that a quarter turn is a whole number of coupling
intervals of :data:`N_SUB` steps.  The rounding moves Fr off the seed's 0.048: 0.047 for
300 particles (R = 0.0466 m, 2 s per turn), 0.060 for 640 (R = 0.06 m, 2 s), 0.039 for
2,000 (R = 0.0877 m, 3 s) -- all cascading (:attr:`KilnGeometry.regime`).
"""
from __future__ import annotations

import dataclasses
import math

from gsi.studies.drum import DT, PARTICLE_RADIUS, G, DrumGeometry, drum_geometry
from gsi.errors import GsiInputError

__all__ = ["KilnGeometry", "kiln_geometry", "kiln_case", "T_HOT", "T_COLD", "T_SHELL",
           "N_SUB", "TURN_STEP", "SHELL_THICKNESS", "K_GRAIN"]

#: initial bed temperatures (K): the half y < 0 and the other half (the seed's 20 K apart)
T_HOT = 313.15
T_COLD = 293.15
#: conductivity of the kiln's grains (W/(m K)): a limestone-like charge (the seed's 100
#: would bring this small bed to the shell's temperature within minutes)
K_GRAIN = 2.0
#: outer shell temperature and the shell's initial temperature (K)
T_SHELL = 393.15
#: DEM steps per coupling (FE heat) interval: dt_FE = 0.25 s
N_SUB = 2500
#: a turn is a whole number of these steps (a quarter turn of whole intervals)
TURN_STEP = 4 * N_SUB
#: shell thickness (m)
SHELL_THICKNESS = 0.005


@dataclasses.dataclass(frozen=True)
class KilnGeometry(DrumGeometry):
    """A kiln of the family (module docstring): the fields and properties of
    :class:`gsi.studies.drum.DrumGeometry` (``particles``, inner ``radius`` and ``length`` in m,
    ``steps_per_turn`` of :data:`gsi.studies.drum.DT`, ``period``, ``rpm``, ``froude``,
    ``regime``), here with the axis along x."""


def kiln_geometry(particles: int) -> KilnGeometry:
    """The kiln holding ``particles`` spheres: the drum of
    :func:`gsi.studies.drum.drum_geometry` with its turn rounded to whole :data:`TURN_STEP` s."""
    d = drum_geometry(particles)
    steps = max(TURN_STEP, int(round(d.steps_per_turn / TURN_STEP)) * TURN_STEP)
    return KilnGeometry(particles=d.particles, radius=d.radius, length=d.length,
                        steps_per_turn=steps)


def kiln_case(geometry: KilnGeometry, *, settle: float = 0.5, spin_up: float = 0.25,
              period_turns: float = 0.25, periods: int = 100, compare_periods: int = 3,
              hours: float | None = None, every: int = 10, dt_split: float = 0.01,
              h: float = 0.012, T_shell: float = T_SHELL,
              k_grain: float = K_GRAIN, seed: int = 3, name: str | None = None):
    """The kiln as a :class:`gsi.case.Case` (module docstring) with its
    ``[extrapolation]``: the halves set at ``settle`` (s; the kiln starts turning then),
    ``spin_up`` turns, one logged period of ``period_turns`` turns (sampling ``every``,
    rows of at most ``dt_split`` s), extrapolated over ``periods`` periods (or as many as
    make ``hours`` of physical time after t1), the full DEM + FE run on for
    ``compare_periods`` of them.

    Parameters
    ----------
    geometry : KilnGeometry
    h : float
        FE element size (m); the shell's heat is P1 (the case model's heat problem).
    T_shell : float
        Outer shell temperature and the shell's initial temperature (K).
    k_grain : float
        Conductivity of the grains (W/(m K)); 100 is the seed's.
    """
    from gsi.case import (Case, CaseInfo, Dem, Material, Motion, Output, ParticleSource,
                          Region, Run, Size, Structure, Wall)
    from gsi.case.extrapolation import Extrapolation, Halves
    from gsi.case.materials import Pair
    from gsi.case.structure import Contact, FixedTemperature, StructureThermal
    R, L, r = geometry.radius, geometry.length, PARTICLE_RADIUS
    K = int(round(period_turns * geometry.steps_per_turn))
    k_settle = int(round(settle / DT))
    k0 = k_settle + int(round(spin_up * geometry.steps_per_turn))
    for key, k in (("settle", k_settle), ("spin_up", k0 - k_settle), ("period_turns", K)):
        if k % N_SUB or k <= 0:
            raise GsiInputError(f"kiln {key}: {k} DEM steps, must be a positive multiple "
                                f"of the coupling interval N_SUB = {N_SUB} steps")
    if hours is not None:
        periods = max(1, int(math.ceil(hours * 3600.0 / (K * DT))))
    grain = Material(E=1.0e7, nu=0.3, rho=2500.0, e=0.2, mu=0.3, mu_r=0.002, k=k_grain,
                     cp=840.0)
    steel = dict(k=53.3, cp=440.0)
    wall = Material(E=1.0e7, nu=0.3, rho=7850.0, e=0.2, mu=0.5, mu_r=0.002, **steel)
    margin = round(0.05 * R + 4 * r, 3)
    t0 = round(k0 * DT, 10)
    xp = Extrapolation(start=t0, period=round(K * DT, 10), periods=periods, every=every,
                       dt_split=dt_split, compare=True, compare_periods=compare_periods,
                       cells=200, halves=Halves(t=round(k_settle * DT, 10), axis="y", at=0.0,
                                                below=T_HOT, above=T_COLD))
    motion = Motion.schedule([dict(t=round(k_settle * DT, 10), rpm=round(geometry.rpm, 6),
                                   axis=(1.0, 0.0, 0.0), centre=(0.0, 0.0, 0.0))])
    shell = Structure(
        name="shell", mesh="drum",
        geometry=dict(radius=R, length=L, thickness=SHELL_THICKNESS, h=h),
        material="steel", degree=1, scheme="static",
        contact=Contact(tags=["contact"], mode="thermal", wall_material="kiln_wall",
                        n_sub=N_SUB, motion=motion),
        thermal=StructureThermal(T_ref=T_COLD, T_initial=T_shell, theta=1.0,
                                 fixed=[FixedTemperature(tag="outer", T=T_shell)]))
    ends = [Wall(kind="plane", name=f"end_{i}", material="kiln_wall", point=(x, 0.0, 0.0),
                 normal=(n, 0.0, 0.0)) for i, (x, n) in enumerate(((0.0, 1.0), (L, -1.0)))]
    fill = ParticleSource(
        name="grains", material="grain", fill="lattice", count=geometry.particles,
        size=Size(kind="single", radius=r),
        region=Region(kind="cylinder", centre=(0.5 * r, 0.0, 0.0), axis=(1.0, 0.0, 0.0),
                      radius=round(R - 0.2 * r, 6), length=round(L - r, 6)),
        temperature=T_COLD)
    hours_done = periods * K * DT / 3600.0
    return Case(
        case=CaseInfo(name=name or f"kiln_{geometry.particles}",
                      description=f"heated kiln: {geometry.particles} spheres of r = 5 mm in a "
                                  f"steel shell R = {R:.4g} m at {T_shell:g} K outside, "
                                  f"{geometry.period:.4g} s per turn (Fr = "
                                  f"{geometry.froude:.3g}, {geometry.regime}); "
                                  f"{hours_done:.3g} h extrapolated"),
        run=Run(duration=xp.end(), dt=DT, seed=seed, progress=False),
        dem=Dem(contact="hertz", rolling=True, heat="area", gravity=(0.0, 0.0, -G),
                domain_lo=(-margin, round(-R - margin, 6), round(-R - margin, 6)),
                domain_hi=(round(L + margin, 6), round(R + margin, 6), round(R + margin, 6))),
        materials={"grain": grain, "kiln_wall": wall},
        pairs=[Pair(materials=("grain", "kiln_wall"), e=0.2, mu=0.5, mu_r=0.002)],
        particles=[fill], walls=ends, structures=[shell],
        output=Output(interval=xp.period, pictures=False, color_by="temperature",
                      view="+x"),
        extrapolation=xp)
