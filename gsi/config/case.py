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
from typing import Any, Optional

from gsi.config.schema import between, load, nonnegative, one_of, param, positive
from gsi.errors import GsiInputError

Vec3 = tuple[float, ...]

CASE_KINDS = ("pour", "hopper_membrane", "thermal_silo")
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


STRUCTURE_SCHEMES = ("static", "newmark", "generalized_alpha")


@dataclass(kw_only=True)
class StructureSection:
    """The FE structure: a shipped gmsh builder, its material, element, integrator, supports."""

    mesh: str = param(doc="builder of meshes.build: membrane, hopper, silo, drum, box")
    geometry: dict[str, Any] = param(default_factory=dict,
                                     doc="[structure.geometry] keyword parameters of the builder (m)")
    material: str = param("steel", doc="library material (steel, aluminium, rubber, ...) or base of overrides")
    E: Optional[float] = param(None, unit="Pa", check=positive(), doc="Young's modulus override")
    nu: Optional[float] = param(None, unit="-", check=between(-1.0, 0.5, open_lo=True, open_hi=True),
                                doc="Poisson's ratio override")
    rho: Optional[float] = param(None, unit="kg/m^3", check=positive(), doc="density override")
    alpha: Optional[float] = param(None, unit="1/K", check=nonnegative(), doc="thermal expansion override")
    k: Optional[float] = param(None, unit="W/(m K)", check=positive(), doc="conductivity override")
    c: Optional[float] = param(None, unit="J/(kg K)", check=positive(), doc="heat capacity override")
    degree: int = param(2, check=one_of(1, 2), doc="Lagrange degree (P2: no bending locking)")
    scheme: str = param("generalized_alpha", check=one_of(*STRUCTURE_SCHEMES),
                        doc="static (quasi-static coupling), newmark or generalized_alpha")
    rho_inf: float = param(0.3, unit="-", check=between(0.0, 1.0),
                           doc="generalized-alpha spectral radius at infinite frequency "
                               "(0.3 damps the step-to-step oscillation of staggered coupling)")
    rayleigh: Vec3 = param((0.0, 0.0), unit="1/s, s", length=2, check=nonnegative(),
                           doc="Rayleigh damping C = a0 M + a1 K: [a0, a1]")
    damping_ratio: Optional[float] = param(None, unit="-", check=between(0.0, 1.0),
                                           doc="sets a0 = 2 zeta omega_1 (mass-proportional) instead of rayleigh[0]")
    self_weight: bool = param(False, doc="load the structure with its own weight (dem.gravity)")
    supports: list[str] = param(default_factory=lambda: ["support"],
                                doc="surface tags clamped (u = 0)")

    def validate(self, path: str) -> None:
        import meshes
        if self.mesh not in meshes.BUILDERS:
            raise GsiInputError(f"{path}.mesh = '{self.mesh}': must be one of "
                                f"{', '.join(sorted(meshes.BUILDERS))}")
        if not self.supports:
            raise GsiInputError(f"{path}.supports = []: give at least one clamped surface tag")
        import inspect
        allowed = [k for k in inspect.signature(meshes.BUILDERS[self.mesh]).parameters
                   if k not in ("comm", "root")]
        for key, value in self.geometry.items():
            if key not in allowed:
                raise GsiInputError(f"{path}.geometry.{key} = {value!r}: not a parameter of the "
                                    f"'{self.mesh}' builder; allowed: {', '.join(allowed)}")
        if self.damping_ratio is not None and self.rayleigh[0] > 0:
            raise GsiInputError(f"{path}.damping_ratio = {self.damping_ratio}: give either "
                                f"damping_ratio or rayleigh[0] (a0), not both")

    def mesh_params(self) -> dict:
        """Keyword parameters of ``meshes.build(self.mesh, ...)``."""
        return dict(self.geometry)

    def material_spec(self):
        """Material for :func:`gsi.fem.materials.get_material`: a name or a dict of overrides."""
        over = {k: getattr(self, k) for k in ("E", "nu", "rho", "alpha", "k", "c")
                if getattr(self, k) is not None}
        return dict(base=self.material, **over) if over else self.material

    def apply_supports(self, elasticity) -> None:
        """Clamp every tag of ``supports`` on an Elasticity problem."""
        for tag in self.supports:
            elasticity.clamp(tag)


@dataclass(kw_only=True)
class CouplingSection:
    """DEM <-> FE coupling through the structure's contact surface."""

    wall_material: str = param(doc="[materials.X] table of the wall in DEM contacts")
    tag: str = param("contact", doc="surface tag of the structure that the particles touch")
    n_sub: Optional[int] = param(None, check=positive(),
                                 doc="DEM steps per FE step (default: from steps_per_period)")
    steps_per_period: float = param(20.0, unit="-", check=positive(),
                                    doc="FE steps per lowest structural period (sets n_sub)")
    relaxation: float = param(0.05, unit="-", check=between(0.0, 1.0, open_lo=True),
                              doc="under-relaxation of the quasi-static (static scheme) update; "
                                  "needs about k_structure/k_contact (0.01-0.1)")


@dataclass(kw_only=True)
class HopperSection:
    """Conical hopper (rigid DEM wall) with a slide gate under its outlet (hopper_membrane)."""

    top_radius: float = param(unit="m", check=positive(), doc="inner radius at the top rim")
    outlet_radius: float = param(unit="m", check=positive(), doc="inner radius of the outlet")
    height: float = param(unit="m", check=positive(), doc="vertical height of the cone")
    outlet_z: float = param(unit="m", doc="height of the outlet")
    centre: Vec3 = param((0.0, 0.0, 0.0), unit="m", length=3, doc="axis point (x, y used)")
    facets: int = param(48, check=positive(), doc="triangles around the cone")
    material: str = param(doc="[materials.X] table of the hopper and gate")
    open_time: float = param(unit="s", check=nonnegative(), doc="the gate starts to open")
    gate_speed: float = param(2.0, unit="m/s", check=positive(), doc="sideways speed of the opening gate")
    quick_open_time: Optional[float] = param(None, unit="s", check=nonnegative(),
                                             doc="open_time with --quick (default open_time)")
    quick_fraction: float = param(0.25, unit="-", check=between(0.0, 1.0, open_lo=True),
                                  doc="with --quick, each particle source's count times this")

    def validate(self, path: str) -> None:
        if self.outlet_radius >= self.top_radius:
            raise GsiInputError(f"{path}.outlet_radius = {self.outlet_radius}: must be < "
                                f"top_radius = {self.top_radius} (m)")
        if self.facets < 8:
            raise GsiInputError(f"{path}.facets = {self.facets}: must be >= 8")


@dataclass(kw_only=True)
class ThermalSection:
    """Heat in the structure and its exchange with hot particles (thermal_silo).

    The particle-wall conductance is the [dem] heat model with the wall material's k
    (which must equal the structure's k). ``time_scale`` s divides the heat capacities of
    the particles and of the structure (documented time scaling: every thermal time
    constant shrinks by s; temperatures at simulated time t are those at s t)."""

    T_ref: float = param(293.15, unit="K", check=positive(),
                         doc="stress-free temperature and zero of the stored energies")
    T_wall_initial: Optional[float] = param(None, unit="K", check=positive(),
                                            doc="initial structure temperature (default T_ref)")
    T_ambient: float = param(293.15, unit="K", check=positive(), doc="ambient air temperature")
    h: float = param(10.0, unit="W/(m^2 K)", check=nonnegative(),
                     doc="convection coefficient on the cooled surfaces")
    cooled: list[str] = param(default_factory=lambda: ["outer"],
                              doc="structure surface tags cooled by convection")
    theta: float = param(1.0, unit="-", check=between(0.5, 1.0),
                         doc="heat time scheme: 1 backward Euler, 0.5 Crank-Nicolson")
    time_scale: float = param(1.0, unit="-", check=positive(),
                              doc="heat-capacity scaling s (particle cp and structure c / s)")


@dataclass(kw_only=True)
class Case:
    run: RunSection = param(doc="the [run] table")
    dem: DemSection = param(doc="the [dem] table")
    materials: dict[str, MaterialSection] = param(doc="[materials.NAME] tables")
    case: CaseSection = param(default_factory=CaseSection, doc="the [case] table")
    particles: list[ParticleSource] = param(default_factory=list, doc="[[particles]] tables")
    walls: list[WallSection] = param(default_factory=list, doc="[[walls]] tables")
    structure: Optional[StructureSection] = param(None, doc="the [structure] table (coupled cases)")
    coupling: Optional[CouplingSection] = param(None, doc="the [coupling] table (coupled cases)")
    hopper: Optional[HopperSection] = param(None, doc="the [hopper] table (hopper_membrane)")
    thermal: Optional[ThermalSection] = param(None, doc="the [thermal] table (thermal_silo)")
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
        for key, section, attr in (("coupling.wall_material", self.coupling, "wall_material"),
                                   ("hopper.material", self.hopper, "material")):
            value = getattr(section, attr) if section is not None else None
            if value is not None and value not in self.materials:
                raise GsiInputError(f"{key} = '{value}': not a [materials.X] table; "
                                    f"defined: {', '.join(names)}")

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
