"""``[extrapolation]``: long-time heat extrapolation from one logged period (seed 003,
Haydar, Martin & Bonnefoy 2023; the method is :mod:`gsi.extrapolation`).

::

    [extrapolation]
    start = 3.95            # t0 (s): the contact log starts here
    period = 3.1498         # tau (s): t1 = start + period
    periods = 6             # periods extrapolated after t1
    every = 10              # sampling factor n (steps)
    dt_split = 0.01         # Delta t_c^max (s), a multiple of every x dt
    compare = true          # run the DEM on to t1 + periods tau as the reference
    cells = 200             # Voronoi cells of the error of eq. 9
    halves = { t = 0.8, axis = "x", at = 0.0, below = 30.0, above = 10.0 }

``halves`` (optional) sets the particle temperatures at time ``t``: ``below`` where the
``axis`` coordinate is below ``at`` (m), ``above`` elsewhere; the two sets are the hot
and cold groups of eq. 9 (the paper's left and right halves at t_init).

The runner (:mod:`gsi.run`) logs t0..t1, writes ``contact_log.npz``, pairs and
replays, and writes ``extrapolation.csv`` (per t_n: mean temperatures of the two groups
and of all particles (heat-capacity weighted), extrapolated and, with ``compare``, full
DEM; eqs. 9 and 10; the drift of sum m c_p T of the replay) and the pictures
``extrapolation_fields.png``, ``extrapolation_means.png``, ``extrapolation_cells.png``.  ``run.duration`` must reach t1 (with ``compare``,
t1 + compare_periods tau).  Not resumable from a checkpoint (the log is not
checkpointed).

A heated kiln wall: with one ``[[structures]]`` of ``contact.mode = "thermal"`` (its
contact wall may turn, ``contact.motion``) the replay exchanges the wall contacts' heat
with the FE heat problem, which steps once per coupling interval
(:class:`gsi.extrapolation.FEWallReplay`); t0 and tau must then be whole numbers of
its intervals (``contact.n_sub`` x ``run.dt``), the run is on one MPI rank, and
``compare_periods`` (< ``periods``) keeps the full DEM + FE reference to a short window
while the replay runs on for hours (``extrapolation_hours.png``: the bed and wall
temperature against hours, the live window beside the extrapolated hours).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from gsi.config.schema import nonnegative, one_of, param, positive
from gsi.errors import GsiInputError

__all__ = ["Extrapolation", "Halves"]


@dataclass(kw_only=True)
class Halves:
    """Temperatures set at time ``t`` on the two sides of a plane normal to an axis."""

    t: float = param(unit="s", check=nonnegative(), doc="time the temperatures are set")
    axis: str = param("x", check=one_of("x", "y", "z"), doc="coordinate that splits")
    at: float = param(0.0, unit="m", doc="the split coordinate")
    # the conduction is linear in T: any two levels serve (the seed's 30 and 10), so no
    # "did you give deg C?" range here
    below: float = param(unit="K", check=positive(), sane=False,
                         doc="temperature where coordinate < at")
    above: float = param(unit="K", check=positive(), sane=False, doc="temperature elsewhere")


@dataclass(kw_only=True)
class Extrapolation:
    """The ``[extrapolation]`` table (module docstring)."""

    start: float = param(unit="s", check=nonnegative(), doc="t0: the contact log starts")
    period: float = param(unit="s", check=positive(), doc="tau: t1 = start + period")
    periods: int = param(6, check=positive(), doc="periods extrapolated after t1")
    every: int = param(10, check=positive(), doc="sampling factor n (DEM steps)")
    dt_split: Optional[float] = param(0.01, unit="s", check=positive(),
                                      doc="Delta t_c^max: longer contacts make several rows")
    compare: bool = param(True, doc="run the DEM on over the periods as the reference")
    compare_periods: Optional[int] = param(None, check=positive(),
                                           doc="periods of that reference (default: periods)")
    cells: int = param(200, check=positive(), doc="Voronoi cells of the eq. 9 error")
    halves: Optional[Halves] = param(None, doc="temperatures set on two sides of a plane")

    def validate(self, path: str) -> None:
        if self.compare_periods is not None and self.compare_periods > self.periods:
            raise GsiInputError(f"{path}.compare_periods = {self.compare_periods}: more than "
                                f"periods = {self.periods}; compare at most the periods "
                                "extrapolated")
        if self.halves is not None and self.halves.t > self.start:
            raise GsiInputError(f"{path}.halves.t = {self.halves.t}: after extrapolation.start "
                                f"= {self.start} (s); set the temperatures before t0")

    @property
    def n_compare(self) -> int:
        """Periods of full DEM reference after t1 (0 without ``compare``)."""
        if not self.compare:
            return 0
        return self.periods if self.compare_periods is None else self.compare_periods

    def end(self) -> float:
        """Simulated time (s) the run must reach: t1, or t1 + compare_periods tau to
        compare."""
        return self.start + self.period * (1 + self.n_compare)

    def check(self, *, dt: float, duration: float, heat: str, structures=()) -> None:
        """What can be known before a run (one-line GsiInputError naming the key);
        ``structures``: the case's :class:`gsi.case.structure.Structure` tables."""
        if heat not in ("area", "radius", "constant"):
            raise GsiInputError(f"dem.heat = {heat!r}: the extrapolation replays the contacts "
                                f"of 'area', 'radius' or 'constant' conduction; set one")
        if len(structures) > 1:
            raise GsiInputError(f"extrapolation: {len(structures)} [[structures]]; the replay "
                                "exchanges heat with one FE wall (a kiln shell); keep one")
        if structures:
            st = structures[0]
            if st.contact.mode != "thermal":
                raise GsiInputError(f"structures[0].contact.mode = {st.contact.mode!r}: the "
                                    "extrapolation replays heat only; set mode = 'thermal'")
            step = st.contact.n_sub * dt
            for key, value in (("start", self.start), ("period", self.period)):
                k = round(value / step)
                if k < 1 or abs(k * step - value) > 1e-9 * value:
                    raise GsiInputError(f"extrapolation.{key} = {value}: must be a whole "
                                        f"number of coupling intervals (structures[0].contact"
                                        f".n_sub x run.dt = {step:g} s)")
        if self.period < 10 * self.every * dt:
            raise GsiInputError(f"extrapolation.period = {self.period}: shorter than 10 "
                                f"samples of every x dt = {self.every * dt:g} s")
        if self.dt_split is not None:
            per = self.every * dt
            k = round(self.dt_split / per)
            if k < 1 or abs(k * per - self.dt_split) > 1e-9 * self.dt_split:
                raise GsiInputError(f"extrapolation.dt_split = {self.dt_split}: must be a "
                                    f"multiple of every x run.dt = {per:g} s")
        if duration < self.end() - 1e-9 * self.end():
            what = ("t1 = start + period" if not self.compare else "t1 + periods x period"
                    if self.compare_periods is None else "t1 + compare_periods x period")
            raise GsiInputError(f"run.duration = {duration}: shorter than {what} = "
                                f"{self.end():.6g} s of [extrapolation]; lengthen the run")
