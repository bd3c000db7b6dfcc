"""The case file: TOML tables -> typed, validated dataclasses.

A case is one TOML file; ``gsi check CASE.toml`` validates it and ``gsi run CASE.toml`` runs
it. Every key, its unit and default is listed by ``gsi check --keys``. Sections:

``[case]``        name and kind (which driver runs it: ``pour``, ...)
``[run]``         duration, time step, output interval, seed, threads
``[dem]``         contact law, rolling resistance, heat model, skin, gravity, domain box
``[materials.X]`` particle and wall materials by name
``[[particles]]`` particle sources: material, size distribution, region and fill
``[[walls]]``     planes, boxes and triangle-mesh walls
"""
from __future__ import annotations

import dataclasses
import pathlib
import tomllib
from dataclasses import dataclass
from typing import Optional

from gsi.config.schema import between, load, nonnegative, one_of, param, positive
from gsi.errors import GsiInputError

Vec3 = tuple[float, ...]

CASE_KINDS = ("pour",)
CONTACT_LAWS = ("hertz", "linear")
HEAT_MODELS = ("none", "area", "radius", "constant")


@dataclass(kw_only=True)
class CaseSection:
    name: str = param("case", doc="a name for the run (used in file names)")
    kind: str = param("pour", check=one_of(*CASE_KINDS), doc="which driver runs the case")
    description: str = param("", doc="free text")


@dataclass(kw_only=True)
class RunSection:
    duration: float = param(unit="s", check=positive(), doc="simulated time")
    quick_duration: Optional[float] = param(None, unit="s", check=positive(),
                                            doc="simulated time with --quick (default duration/5)")
    dt: Optional[float] = param(None, unit="s", check=positive(),
                                doc="DEM time step (default 0.2 x the Rayleigh time)")
    output_interval: float = param(unit="s", check=positive(), doc="time between snapshots")
    seed: int = param(12345, check=nonnegative(), doc="random seed (insertion, jitter)")
    threads: int = param(0, check=nonnegative(), doc="numba threads (0 = all cores)")

    def validate(self, path: str) -> None:
        if self.output_interval > self.duration:
            raise GsiInputError(f"{path}.output_interval = {self.output_interval}: must be <= "
                                f"run.duration = {self.duration} (s)")


@dataclass(kw_only=True)
class DemSection:
    contact: str = param("hertz", check=one_of(*CONTACT_LAWS), doc="contact law")
    k_n: Optional[float] = param(None, unit="N/m", check=positive(),
                                 doc="normal stiffness of the linear law")
    rolling: bool = param(False, doc="constant directional torque rolling resistance")
    heat: str = param("none", check=one_of(*HEAT_MODELS), doc="particle conduction model")
    h_c: Optional[float] = param(None, unit="W/K", check=positive(),
                                 doc="conductance of the 'constant' heat model")
    skin: Optional[float] = param(None, unit="m", check=positive(),
                                  doc="Verlet skin (default 0.4 x the smallest radius)")
    gravity: Vec3 = param((0.0, 0.0, -9.81), unit="m/s^2", length=3, doc="gravity vector")
    domain_lo: Vec3 = param(unit="m", length=3, doc="lower corner of the domain box")
    domain_hi: Vec3 = param(unit="m", length=3, doc="upper corner of the domain box")
    force_dt: bool = param(False, doc="run even if dt exceeds the Rayleigh time")

    def validate(self, path: str) -> None:
        for i, (lo, hi) in enumerate(zip(self.domain_lo, self.domain_hi)):
            if hi <= lo:
                raise GsiInputError(f"{path}.domain_hi = {list(self.domain_hi)}: must exceed "
                                    f"domain_lo = {list(self.domain_lo)} in every component (m)")
        if self.contact == "linear" and self.k_n is None:
            raise GsiInputError(f"{path}.k_n: missing; the linear law needs a normal stiffness (N/m)")
        if self.heat == "constant" and self.h_c is None:
            raise GsiInputError(f"{path}.h_c: missing; the constant heat model needs a conductance (W/K)")


@dataclass(kw_only=True)
class MaterialSection:
    E: float = param(unit="Pa", check=positive(), doc="Young's modulus")
    nu: float = param(unit="-", check=between(-1.0, 0.5, open_lo=True, open_hi=True),
                      doc="Poisson's ratio")
    rho: float = param(unit="kg/m^3", check=positive(), doc="density")
    e: float = param(0.5, unit="-", check=between(0.0, 1.0, open_lo=True), doc="restitution")
    mu: float = param(0.5, unit="-", check=nonnegative(), doc="sliding friction")
    mu_r: float = param(0.0, unit="-", check=nonnegative(), doc="rolling friction")
    k: float = param(1.0, unit="W/(m K)", check=positive(), doc="thermal conductivity")
    cp: float = param(1000.0, unit="J/(kg K)", check=positive(), doc="heat capacity")


@dataclass(kw_only=True)
class SizeSection:
    kind: str = param("single", check=one_of("single", "uniform", "normal", "discrete"),
                      doc="size distribution of the radius")
    radius: Optional[float] = param(None, unit="m", check=positive(), doc="radius (single)")
    min: Optional[float] = param(None, unit="m", check=positive(), doc="smallest radius")
    max: Optional[float] = param(None, unit="m", check=positive(), doc="largest radius")
    mean: Optional[float] = param(None, unit="m", check=positive(), doc="mean radius (normal)")
    std: Optional[float] = param(None, unit="m", check=positive(), doc="std deviation (normal)")
    values: Optional[tuple[float, ...]] = param(None, unit="m", check=positive(),
                                               doc="radii (discrete)")
    weights: Optional[tuple[float, ...]] = param(None, unit="-", check=positive(),
                                                doc="number fractions (discrete)")

    def validate(self, path: str) -> None:
        need = {"single": ("radius",), "uniform": ("min", "max"), "normal": ("mean", "std"),
                "discrete": ("values", "weights")}[self.kind]
        for key in need:
            if getattr(self, key) is None:
                raise GsiInputError(f"{path}.{key}: missing; size kind '{self.kind}' needs "
                                    f"{' and '.join(need)}")
        if self.kind == "uniform" and self.max < self.min:
            raise GsiInputError(f"{path}.max = {self.max}: must be >= {path}.min = {self.min} (m)")
        if self.kind == "discrete" and len(self.values) != len(self.weights):
            raise GsiInputError(f"{path}.weights: must have as many entries as values "
                                f"({len(self.values)})")

    @property
    def smallest(self) -> float:
        if self.kind == "single":
            return self.radius
        if self.kind == "uniform":
            return self.min
        if self.kind == "normal":
            return self.min if self.min is not None else max(self.mean - 3 * self.std, 0.1 * self.mean)
        return min(self.values)

    @property
    def largest(self) -> float:
        if self.kind == "single":
            return self.radius
        if self.kind == "uniform":
            return self.max
        if self.kind == "normal":
            return self.max if self.max is not None else self.mean + 3 * self.std
        return max(self.values)


@dataclass(kw_only=True)
class RegionSection:
    kind: str = param("box", check=one_of("box", "cylinder"), doc="insertion region shape")
    lo: Optional[Vec3] = param(None, unit="m", length=3, doc="box lower corner")
    hi: Optional[Vec3] = param(None, unit="m", length=3, doc="box upper corner")
    centre: Optional[Vec3] = param(None, unit="m", length=3, doc="cylinder axis point (bottom)")
    radius: Optional[float] = param(None, unit="m", check=positive(), doc="cylinder radius")
    height: Optional[float] = param(None, unit="m", check=positive(), doc="cylinder height (along z)")

    def validate(self, path: str) -> None:
        need = ("lo", "hi") if self.kind == "box" else ("centre", "radius", "height")
        for key in need:
            if getattr(self, key) is None:
                raise GsiInputError(f"{path}.{key}: missing; a {self.kind} region needs "
                                    f"{', '.join(need)}")
        if self.kind == "box" and any(h <= l for l, h in zip(self.lo, self.hi)):
            raise GsiInputError(f"{path}.hi = {list(self.hi)}: must exceed lo = {list(self.lo)} "
                                f"in every component (m)")


@dataclass(kw_only=True)
class ParticleSource:
    material: str = param(doc="name of a [materials.X] table")
    size: SizeSection = param(doc="the [particles.size] table")
    region: RegionSection = param(doc="the [particles.region] table")
    fill: str = param("random", check=one_of("random", "lattice", "stream"),
                      doc="random or lattice fill at start, or a stream at a rate")
    count: Optional[int] = param(None, check=positive(), doc="number of particles")
    rate: Optional[float] = param(None, unit="1/s", check=positive(),
                                  doc="insertion rate of a stream")
    velocity: Vec3 = param((0.0, 0.0, 0.0), unit="m/s", length=3, doc="initial velocity")
    temperature: float = param(293.15, unit="K", check=positive(), doc="initial temperature")

    def validate(self, path: str) -> None:
        if self.fill == "stream" and self.rate is None:
            raise GsiInputError(f"{path}.rate: missing; a stream needs a rate (1/s)")
        if self.fill != "lattice" and self.count is None:
            raise GsiInputError(f"{path}.count: missing; give the number of particles")


@dataclass(kw_only=True)
class WallSection:
    kind: str = param(check=one_of("plane", "box", "mesh"), doc="plane, box (5 or 6 planes) or mesh")
    material: str = param(doc="name of a [materials.X] table")
    point: Optional[Vec3] = param(None, unit="m", length=3, doc="a point of the plane")
    normal: Optional[Vec3] = param(None, unit="-", length=3, doc="plane normal into the domain")
    lo: Optional[Vec3] = param(None, unit="m", length=3, doc="box lower corner")
    hi: Optional[Vec3] = param(None, unit="m", length=3, doc="box upper corner")
    lid: bool = param(False, doc="box: also a top plane")
    file: Optional[str] = param(None, doc="mesh file (STL or any meshio format), relative to the case")
    scale: float = param(1.0, unit="-", check=positive(), doc="mesh: coordinate scale factor")
    velocity: Vec3 = param((0.0, 0.0, 0.0), unit="m/s", length=3, doc="translation velocity")
    omega: Vec3 = param((0.0, 0.0, 0.0), unit="rad/s", length=3, doc="rotation velocity")
    centre: Vec3 = param((0.0, 0.0, 0.0), unit="m", length=3, doc="centre of rotation")
    temperature: Optional[float] = param(None, unit="K", check=positive(),
                                         doc="wall temperature (none = adiabatic)")

    def validate(self, path: str) -> None:
        need = {"plane": ("point", "normal"), "box": ("lo", "hi"), "mesh": ("file",)}[self.kind]
        for key in need:
            if getattr(self, key) is None:
                raise GsiInputError(f"{path}.{key}: missing; a {self.kind} wall needs "
                                    f"{', '.join(need)}")
        if self.kind == "plane" and sum(c * c for c in self.normal) == 0.0:
            raise GsiInputError(f"{path}.normal = {list(self.normal)}: must be a nonzero vector")


@dataclass(kw_only=True)
class Case:
    run: RunSection = param(doc="the [run] table")
    dem: DemSection = param(doc="the [dem] table")
    materials: dict[str, MaterialSection] = param(doc="[materials.NAME] tables")
    case: CaseSection = param(default_factory=CaseSection, doc="the [case] table")
    particles: list[ParticleSource] = param(default_factory=list, doc="[[particles]] tables")
    walls: list[WallSection] = param(default_factory=list, doc="[[walls]] tables")
    #: directory of the case file: relative paths (mesh files) resolve against it
    base_dir: pathlib.Path = dataclasses.field(default=pathlib.Path("."), init=False,
                                               repr=False, compare=False)

    def validate(self, path: str) -> None:
        if not self.materials:
            raise GsiInputError("materials: missing; give at least one [materials.NAME] table")
        names = sorted(self.materials)
        for section, items in (("particles", self.particles), ("walls", self.walls)):
            for i, item in enumerate(items):
                if item.material not in self.materials:
                    raise GsiInputError(f"{section}[{i}].material = '{item.material}': not a "
                                        f"[materials.X] table; defined: {', '.join(names)}")

    def check_files(self) -> None:
        for i, w in enumerate(self.walls):
            if w.kind == "mesh" and not (self.base_dir / w.file).is_file():
                raise GsiInputError(f"walls[{i}].file = '{w.file}': no such file "
                                    f"(looked in {self.base_dir.resolve()})")


def load_case(path: str | pathlib.Path) -> Case:
    """Read and validate a case file; raise GsiInputError with a one-line message."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise GsiInputError(f"{path}: no such case file")
    try:
        with path.open("rb") as fh:
            table = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise GsiInputError(f"{path}: not valid TOML: {exc}") from None
    return case_from_table(table, base_dir=path.parent)


def case_from_table(table: dict, *, base_dir: pathlib.Path | str = ".") -> Case:
    """Validate an already parsed TOML table (demos build their case this way)."""
    case = load(Case, table)
    case.base_dir = pathlib.Path(base_dir)
    case.check_files()
    return case
