"""The case-wide settings: ``[case]``, ``[run]``, ``[dem]`` and ``[output]``."""
from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Optional

from gsi.case.names import MAX_NAME
from gsi.config.schema import Check, nonnegative, one_of, param, positive
from gsi.errors import GsiInputError

__all__ = ["CaseInfo", "Run", "Dem", "Output", "CONTACT_LAWS", "HEAT_MODELS"]

CONTACT_LAWS = ("hertz", "linear")
HEAT_MODELS = ("none", "area", "radius", "constant", "pipe")
#: a case name is used in file names: letters, digits, '_', '-', '.' (no path separators);
#: the one rule of every output name (gsi.case.names)
_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$")


@dataclass(kw_only=True)
class CaseInfo:
    """``[case]``: a name (used in default output paths) and free text."""

    name: str = param("case", doc="a name for the run: letters, digits, '_', '-', '.'")
    description: str = param("", doc="free text")

    def validate(self, path: str) -> None:
        if not _NAME.match(self.name) or len(self.name) > MAX_NAME:
            raise GsiInputError(f"{path}.name = {self.name!r}: use letters, digits, '_', '-' "
                                f"or '.' only (it becomes a directory name)")


@dataclass(kw_only=True)
class Run:
    """``[run]``: how long, with which step, on how many threads."""

    duration: float = param(unit="s", check=positive(), doc="simulated time")
    dt: Optional[float] = param(None, unit="s", check=positive(),
                                doc="DEM time step (default 0.2 x the smallest Rayleigh time)")
    seed: int = param(12345, check=nonnegative(), doc="random seed (fills, insertion)")
    threads: int = param(0, check=nonnegative(), doc="numba threads of the DEM (0 = all cores)")
    heat_time_scale: float = param(
        1.0, unit="-", check=positive(),
        doc="heat-capacity scaling s: particle c_p and structure c are divided by s, so every "
            "thermal time constant shrinks by s (temperatures at t are those at s t)")
    progress: bool = param(True, doc="print a progress line (simulated time, rate, ETA)")
    checkpoint_interval: float = param(
        0.0, unit="s", check=nonnegative(),
        doc="simulated time between checkpoints in <out>/checkpoints (0 = none; one is "
            "always written on SIGINT/SIGTERM; gsi run --checkpoint-every overrides)")
    checkpoint_minutes: float = param(
        0.0, unit="min", check=nonnegative(),
        doc="wall-clock minutes between checkpoints (0 = none)")


@dataclass(kw_only=True)
class Dem:
    """``[dem]``: contact law, rolling resistance, heat model, radiation, neighbour skin,
    gravity, domain."""

    contact: str = param("hertz", check=one_of(*CONTACT_LAWS), doc="contact law")
    k_n: Optional[float] = param(None, unit="N/m", check=positive(),
                                 doc="normal stiffness of the linear law")
    rolling: bool = param(False, doc="constant directional torque rolling resistance (mu_r)")
    heat: str = param("none", check=one_of(*HEAT_MODELS), doc="particle conduction model")
    h_c: Optional[float] = param(None, unit="W/K", check=positive(),
                                 doc="conductance of the 'constant' heat model")
    pipe_length: Optional[float] = param(None, unit="m", check=positive(),
                                         doc="pipe length w of the 'pipe' heat model (Feng's "
                                             "pipe network, a 2D model: the slab thickness)")
    pipe_resistance: float = param(0.0, unit="K m/W", check=nonnegative(),
                                   doc="contact resistance per length R_c* of the 'pipe' model")
    radiation: bool = param(False, doc="particle-particle and particle-wall radiation (seed 000 "
                                       "eqs. 22-23; emissivity per [materials.X])")
    radiation_cutoff: Optional[float] = param(
        None, unit="-", check=Check(lambda v: v >= 1.0, "must be >= 1"),
        doc="radiation neighbours closer than this x (R_i + R_j) between centres, walls "
            "closer than this x R_i (default 1.5)")
    radiation_every: Optional[int] = param(
        None, check=positive(),
        doc="DEM steps per radiation evaluation, applied over that interval (default 1)")
    radiation_T_enclosure: Optional[float] = param(
        None, unit="K", check=nonnegative(),
        doc="black enclosure seen by particles with no radiation neighbour (default: none)")
    frictional_heating: bool = param(
        False, doc="energy dissipated in contacts (normal damping, sliding, rolling "
                   "resistance) heats the two bodies, half each; a thermal wall's half "
                   "reaches the FE heat solve")
    skin: Optional[float] = param(None, unit="m", check=positive(),
                                  doc="Verlet skin, fixed (default: adaptive, 0.4 to 1 x the smallest radius, "
                                      "aiming at 10 steps between list builds)")
    gravity: tuple[float, ...] = param((0.0, 0.0, -9.81), unit="m/s^2", length=3,
                                       doc="gravity vector")
    domain_lo: tuple[float, ...] = param(unit="m", length=3, doc="lower corner of the domain box")
    domain_hi: tuple[float, ...] = param(unit="m", length=3, doc="upper corner of the domain box")
    force_dt: bool = param(False, doc="run (with a warning) even if dt is above 0.5 t_R "
                                      "(linear: t_c/10) or placed particles overlap")

    def validate(self, path: str) -> None:
        if any(hi <= lo for lo, hi in zip(self.domain_lo, self.domain_hi)):
            raise GsiInputError(f"{path}.domain_hi = {list(self.domain_hi)}: must exceed "
                                f"domain_lo = {list(self.domain_lo)} in every component (m)")
        if self.contact == "linear" and self.k_n is None:
            raise GsiInputError(f"{path}.k_n: missing; the linear law needs a normal stiffness (N/m)")
        if self.heat == "constant" and self.h_c is None:
            raise GsiInputError(f"{path}.h_c: missing; the constant heat model needs a "
                                f"conductance (W/K)")
        if not self.radiation:
            for key in ("radiation_cutoff", "radiation_every", "radiation_T_enclosure"):
                if getattr(self, key) is not None:
                    raise GsiInputError(f"{path}.{key}: set, but {path}.radiation = false; set "
                                        f"{path}.radiation = true or remove it")
        if self.heat == "pipe" and self.pipe_length is None:
            raise GsiInputError(f"{path}.pipe_length: missing; the pipe heat model needs the "
                                f"pipe length w (m), e.g. the slab thickness of a quasi-2D run")

    @property
    def domain_size(self) -> float:
        """Largest edge of the domain box (m)."""
        return max(h - l for l, h in zip(self.domain_lo, self.domain_hi))


@dataclass(kw_only=True)
class Output:
    """``[output]``: when to write, what, and whether to draw pictures."""

    interval: float = param(unit="s", check=positive(),
                            doc="time between outputs (particles, structures, monitors, progress)")
    fields: tuple[str, ...] = param(("particles", "walls", "structures"),
                                    doc="what to write: any of particles, walls, structures")
    pictures: bool = param(True, doc="PNG snapshots (and an animated GIF) at the outputs")
    picture_every: int = param(1, check=positive(), doc="a picture every this many outputs")
    color_by: str = param("speed", check=one_of("speed", "temperature", "radius"),
                          doc="particle colour in pictures")
    view: str = param("iso", check=one_of("iso", "+x", "-x", "+y", "-y", "+z", "-z"),
                      doc="camera of the pictures: isometric, or looking along an axis")

    def validate(self, path: str) -> None:
        for f in self.fields:
            if f not in ("particles", "walls", "structures"):
                raise GsiInputError(f"{path}.fields = {list(self.fields)}: '{f}' is not one of "
                                    f"particles, walls, structures")

