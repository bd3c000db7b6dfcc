r"""An FE structure of a case: one ``[[structures]]`` table, one :class:`Structure` object.

A structure is a solid body of tetrahedra from a shipped gmsh builder (``mesh`` +
``geometry``) or from the user's own gmsh file (``file``: a ``.geo`` script whose
``DefineConstant`` values ``geometry`` may override, or a ``.msh``) with physical groups.
``tags`` maps gsi-side names onto the mesh's group names, so that every tag below may be
either name::

    [[structures]]
    name = "belt"
    file = "../meshes/belt.geo"          # relative to the case file
    geometry = { length = 1.0, h = 0.05 }
    tags = { support = "belt_ends", contact = "belt_top" }
    material = "rubber"
    degree = 2
    supports = ["support"]
    contact = { tags = ["contact"], mode = "mechanical" }
    solver = "auto"                      # direct | iterative | auto (by dof count)
    petsc = { ksp_rtol = 1e-12 }         # PETSc options of the elasticity solver

Physics (docs/design.md, "Structure (FE) physics", "Coupling"): linear elasticity, static or
dynamic (Newmark, generalized-alpha), Rayleigh damping C = a0 M + a1 K, clamped supports,
uniform tractions and self-weight; heat conduction with convection, fixed temperature and
flux by tag, theta-scheme; thermal strain alpha (T - T_ref). The contact surface
(``contact.tags``) is one DEM mesh wall; its coupling is mechanical (forces and motion),
thermal (heat; the wall stays at its reference position) or both.

:meth:`Structure.build` is the one structure set-up of gsi:

1. mesh (builder or file), tags mapped;
2. a static problem with the supports -> the lowest period T_1 by Rayleigh's quotient
   (:func:`gsi.coupling.staggered.lowest_period`, trial shape: the static deflection under
   a uniform body force along gravity);
3. n_sub = ``contact.n_sub`` or :func:`gsi.coupling.staggered.choose_n_sub`
   (T_1 / (steps_per_period dt_DEM)); dt_FE = n_sub dt_DEM;
4. damping a0 = 2 zeta (2 pi / T_1) from ``damping_ratio`` zeta (else ``rayleigh[0]``);
5. the dynamic elasticity (or the static one for ``scheme = "static"``) with supports,
   tractions, self-weight and T_ref;
6. the heat problem (capacity c / ``heat_scale``: the heat-capacity time scaling of
   :mod:`gsi.coupling.thermal`) with its boundary conditions;
7. the one contact interface (:class:`gsi.coupling.interface.SurfaceInterface`).

It returns a :class:`gsi.coupling.coupled_structure.CoupledStructure`, which a runner attaches to
the DEM and steps. Before the run, :meth:`Structure.check` finds what it can without
building (files, builder parameters, tags present in the mesh, the wall conductivity).
"""
from __future__ import annotations

import inspect
import math
import pathlib
from dataclasses import dataclass
from typing import Any, Optional


from gsi.config.schema import between, nonnegative, one_of, param, positive
from gsi.case.walls import Motion
from gsi.errors import GsiInputError
from gsi.fem.options import AUTO_LARGE_DOFS, SOLVERS, petsc_option_strings

__all__ = ["Structure", "Load", "Convection", "FixedTemperature", "Flux", "Radiation",
           "StructureThermal",
           "Contact", "CoupledStructure"]

Vec3 = tuple[float, ...]
SCHEMES = ("static", "newmark", "generalized_alpha")
MODES = ("mechanical", "thermal", "both")


def __getattr__(name):
    if name == "CoupledStructure":
        from gsi.coupling.coupled_structure import CoupledStructure
        return CoupledStructure
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _check_geometry_value(key: str, value, default, *, positive: bool = True) -> None:
    """A builder parameter has the kind of its default: a string, a list of positive
    integers (a tuple default), or a number (m; > 0 for a builder); a .geo constant
    (``positive=False``) is any number. Nothing reaches gmsh as the wrong type."""
    if isinstance(default, str):
        if not isinstance(value, str):
            raise GsiInputError(f"{key} = {value!r}: must be a string (e.g. {default!r})")
        return
    if isinstance(default, tuple):
        if not (isinstance(value, list) and len(value) == len(default)
                and all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in value)):
            raise GsiInputError(f"{key} = {value!r}: must be a list of {len(default)} positive "
                                f"integers (e.g. {list(default)})")
        return
    if not _is_number(value):
        raise GsiInputError(f"{key} = {value!r}: must be a number (m)")
    if isinstance(default, int) and not isinstance(default, bool) and not isinstance(value, int):
        raise GsiInputError(f"{key} = {value!r}: must be an integer (e.g. {default})")
    if positive and value <= 0:
        raise GsiInputError(f"{key} = {value!r}: must be > 0 (m)")


@dataclass(kw_only=True)
class Load:
    """A uniform surface traction on a tag (``[[structures.loads]]``)."""

    tag: str = param(doc="surface tag the traction acts on")
    traction: Vec3 = param(unit="Pa", length=3, sane=False, doc="traction vector (force per area)")


@dataclass(kw_only=True)
class Convection:
    """Convective cooling h (T - T_ambient) out through a tag."""

    tag: str = param(doc="surface tag")
    h: float = param(unit="W/(m^2 K)", check=nonnegative(), doc="heat transfer coefficient")
    T_ambient: float = param(unit="K", check=positive(), doc="ambient temperature")


@dataclass(kw_only=True)
class FixedTemperature:
    """A fixed temperature on a tag (Dirichlet)."""

    tag: str = param(doc="surface tag")
    T: float = param(unit="K", check=positive(), doc="temperature")


@dataclass(kw_only=True)
class Flux:
    """A prescribed heat flux into the body through a tag."""

    tag: str = param(doc="surface tag")
    q: float = param(unit="W/m^2", doc="heat flux into the structure")


@dataclass(kw_only=True)
class Radiation:
    """Radiation eps sigma (T^4 - T_ambient^4) out through a tag (explicit in T)."""

    tag: str = param(doc="surface tag")
    emissivity: float = param(unit="-", check=between(0.0, 1.0, open_lo=True),
                              doc="surface emissivity")
    T_ambient: float = param(unit="K", check=nonnegative(),
                             doc="temperature of the surroundings it radiates to")


@dataclass(kw_only=True)
class StructureThermal:
    """Heat in the structure (``[structures.thermal]``)."""

    T_ref: float = param(293.15, unit="K", check=positive(),
                         doc="stress-free temperature and zero of the stored energies")
    T_initial: Optional[float] = param(None, unit="K", check=positive(),
                                       doc="initial temperature (default T_ref)")
    theta: float = param(1.0, unit="-", check=between(0.0, 1.0),
                         doc="heat time scheme: 1 backward Euler, 0.5 Crank-Nicolson, 0 explicit "
                             "(dt_FE under its stability limit)")
    convection: list[Convection] = param(default_factory=list,
                                         doc="[[structures.thermal.convection]] tag, h, T_ambient")
    fixed: list[FixedTemperature] = param(default_factory=list,
                                          doc="[[structures.thermal.fixed]] tag, T")
    flux: list[Flux] = param(default_factory=list, doc="[[structures.thermal.flux]] tag, q")
    radiation: list[Radiation] = param(default_factory=list,
                                       doc="[[structures.thermal.radiation]] tag, emissivity, "
                                           "T_ambient")
    petsc: dict[str, Any] = param(default_factory=dict,
                                  doc="PETSc options of the heat solver without the '-', "
                                      "e.g. {ksp_rtol = 1e-12}")

    def tags_used(self) -> list[tuple[str, str]]:
        return ([(f"thermal.convection[{i}].tag", c.tag) for i, c in enumerate(self.convection)]
                + [(f"thermal.fixed[{i}].tag", c.tag) for i, c in enumerate(self.fixed)]
                + [(f"thermal.flux[{i}].tag", c.tag) for i, c in enumerate(self.flux)]
                + [(f"thermal.radiation[{i}].tag", c.tag) for i, c in enumerate(self.radiation)])


@dataclass(kw_only=True)
class Contact:
    """The structure's surface that touches the particles (``[structures.contact]``)."""

    tags: list[str] = param(default_factory=lambda: ["contact"],
                            doc="surface tags touching the particles (one wall of all their "
                                "facets), e.g. [\"contact\"]")
    mode: str = param("mechanical", check=one_of(*MODES),
                      doc="coupling: mechanical (forces, motion), thermal (heat) or both")
    wall_material: Optional[str] = param(None, doc="[materials.X] of the wall in DEM contacts "
                                         "(default: the structure's E, nu, rho, k, c with e, mu, mu_r below)")
    e: float = param(0.5, unit="-", check=between(0.0, 1.0, open_lo=True),
                     doc="restitution of the derived wall material")
    mu: float = param(0.5, unit="-", check=nonnegative(),
                      doc="sliding friction of the derived wall material")
    mu_r: float = param(0.0, unit="-", check=nonnegative(),
                        doc="rolling friction of the derived wall material")
    n_sub: Optional[int] = param(None, check=positive(),
                                 doc="DEM steps per FE step (default: from steps_per_period)")
    steps_per_period: float = param(20.0, unit="-", check=positive(),
                                    doc="FE steps per lowest structural period (sets n_sub)")
    relaxation: float = param(1.0, unit="-", check=between(0.0, 1.0, open_lo=True),
                              doc="under-relaxation of the quasi-static (static scheme) update; "
                                  "a soft structure under stiff particles needs ~0.01-0.1")
    motion: Optional[Motion] = param(None, doc="rotation of a thermal-only contact wall (a "
                                     "rotary kiln's shell): a [[walls]] motion of kind rotation "
                                     "or schedule with axis and centre; the FE is the body's frame")


@dataclass(kw_only=True)
class Structure:
    """One FE structure (see the module docstring for the TOML form and the set-up)."""

    name: str = param("structure", doc="output prefix: <name>.xdmf, <name>_coupling.csv, ...")
    mesh: Optional[str] = param(None, doc="shipped builder: membrane, hopper, silo, shell, drum, "
                                "box (or give file)")
    file: Optional[str] = param(None, doc="user gmsh .geo or .msh with physical groups, "
                                "relative to the case file (or give mesh)")
    geometry: dict[str, Any] = param(default_factory=dict,
                                     doc="builder keyword parameters (lengths in m), or .geo "
                                         "DefineConstant overrides")
    translate: Vec3 = param((0.0, 0.0, 0.0), unit="m", length=3,
                            doc="shift of the mesh after it is built or read (places a shipped "
                                "builder's body, e.g. a hopper above a membrane)")
    tags: dict[str, str] = param(default_factory=dict,
                                 doc="gsi name -> physical-group name of the mesh, "
                                     "e.g. {support = \"clamped_ends\"}")
    material: str = param("steel", doc="library material (steel, aluminium, rubber, concrete) "
                          "or base of the overrides")
    E: Optional[float] = param(None, unit="Pa", check=positive(), doc="Young's modulus override")
    nu: Optional[float] = param(None, unit="-", check=between(-1.0, 0.5, open_lo=True, open_hi=True),
                                doc="Poisson's ratio override")
    rho: Optional[float] = param(None, unit="kg/m^3", check=positive(), doc="density override")
    alpha: Optional[float] = param(None, unit="1/K", check=nonnegative(),
                                   doc="thermal expansion override")
    k: Optional[float] = param(None, unit="W/(m K)", check=positive(), doc="conductivity override")
    c: Optional[float] = param(None, unit="J/(kg K)", check=positive(),
                               doc="specific heat capacity override")
    degree: int = param(2, check=one_of(1, 2), doc="Lagrange degree (P2: no bending locking)")
    scheme: str = param("generalized_alpha", check=one_of(*SCHEMES),
                        doc="static (quasi-static coupling), newmark or generalized_alpha")
    rho_inf: float = param(0.3, unit="-", check=between(0.0, 1.0),
                           doc="generalized-alpha spectral radius at infinite frequency")
    rayleigh: Vec3 = param((0.0, 0.0), unit="1/s, s", length=2, check=nonnegative(),
                           doc="Rayleigh damping C = a0 M + a1 K: [a0, a1]")
    damping_ratio: Optional[float] = param(None, unit="-", check=between(0.0, 1.0),
                                           doc="sets a0 = 2 zeta omega_1 instead of rayleigh[0]")
    self_weight: bool = param(False, doc="load the structure with its own weight (gravity)")
    solver: str = param("auto", check=one_of(*SOLVERS),
                        doc="linear solver: direct (MUMPS; SuperLU_DIST on several ranks; "
                            "factorized once), out_of_core (MUMPS Cholesky, the factor on "
                            "disk), iterative (CG + algebraic multigrid, built once) or auto "
                            f"(from {AUTO_LARGE_DOFS['elasticity']} dofs out of core for "
                            "elasticity, iterative for heat)")
    petsc: dict[str, Any] = param(default_factory=dict,
                                  doc="PETSc options of the elasticity solver without the '-', "
                                      "e.g. {ksp_rtol = 1e-12} (heat: thermal.petsc)")
    supports: list[str] = param(default_factory=lambda: ["support"],
                                doc="surface tags clamped (u = 0)")
    loads: list[Load] = param(default_factory=list, doc="[[structures.loads]] tag, traction (Pa)")
    thermal: Optional[StructureThermal] = param(None, doc="heat in the structure")
    contact: Contact = param(default_factory=Contact, doc="the surface touching the particles")

    # ------------------------------------------------------------------ validation
    def validate(self, path: str = "structure") -> None:
        """Checks of the values alone (the schema calls it with the key path)."""
        from gsi import meshes
        self._key = path or "structure"
        key = self._key
        if not self.name or any(ch in self.name for ch in "/\\ ") or self.name.startswith("."):
            raise GsiInputError(f"{key}.name = {self.name!r}: must be a plain file-name stem "
                                "(no spaces or slashes)")
        if (self.mesh is None) == (self.file is None):
            raise GsiInputError(f"{key}.mesh = {self.mesh!r}, {key}.file = {self.file!r}: give "
                                "exactly one (a shipped builder or a gmsh file)")
        if self.mesh is not None:
            if self.mesh not in meshes.BUILDERS:
                raise GsiInputError(f"{key}.mesh = {self.mesh!r}: must be one of "
                                    f"{', '.join(sorted(meshes.BUILDERS))}")
            allowed = [k for k in inspect.signature(meshes.BUILDERS[self.mesh]).parameters
                       if k not in ("comm", "root")]
            params = inspect.signature(meshes.BUILDERS[self.mesh]).parameters
            for k, v in self.geometry.items():
                if k not in allowed:
                    raise GsiInputError(f"{key}.geometry.{k} = {v!r}: not a parameter of the "
                                        f"'{self.mesh}' builder; allowed: {', '.join(allowed)}")
                _check_geometry_value(f"{key}.geometry.{k}", v, params[k].default)
        elif pathlib.Path(self.file).suffix.lower() not in (".geo", ".msh"):
            raise GsiInputError(f"{key}.file = {self.file!r}: must be a gmsh .geo or .msh file")
        else:
            for k, v in self.geometry.items():
                _check_geometry_value(f"{key}.geometry.{k}", v, None, positive=False)
        if self.damping_ratio is not None and self.rayleigh[0] > 0:
            raise GsiInputError(f"{key}.damping_ratio = {self.damping_ratio}: give either "
                                "damping_ratio or rayleigh[0] (a0), not both")
        if not self.contact.tags:
            raise GsiInputError(f"{key}.contact.tags = []: give at least one surface tag")
        petsc_option_strings(self.petsc, f"{key}.petsc")
        if self.petsc and not self.has_elasticity:
            raise GsiInputError(f"{key}.petsc: contact.mode = 'thermal' has no elasticity; give "
                                f"the heat solver's options as {key}.thermal.petsc")
        if self.thermal is not None:
            petsc_option_strings(self.thermal.petsc, f"{key}.thermal.petsc")
        mech = self.contact.mode in ("mechanical", "both")
        if mech and not self.supports:
            raise GsiInputError(f"{key}.supports = []: give at least one clamped surface tag")
        if self.contact.mode == "mechanical" and self.thermal is not None:
            raise GsiInputError(f"{key}.contact.mode = 'mechanical': the [thermal] table needs "
                                "mode = 'both' (or 'thermal')")
        if self.contact.mode == "thermal":
            if self.loads or self.self_weight:
                raise GsiInputError(f"{key}.contact.mode = 'thermal': the structure has no "
                                    "elasticity; remove loads/self_weight or use mode = 'both'")
            if self.contact.n_sub is None:
                raise GsiInputError(f"{key}.contact.n_sub: missing; a thermal-only structure "
                                    "has no vibration period to choose it from")
        mo = self.contact.motion
        if mo is not None:
            if self.contact.mode != "thermal":
                raise GsiInputError(f"{key}.contact.motion: only with contact.mode = 'thermal' "
                                    "(the mechanical coupling moves the wall with the FE)")
            mo.validate(f"{key}.contact.motion", has_axis=False)
            if mo.kind not in ("rotation", "schedule") or (mo.kind == "schedule" and any(
                    any(e.velocity) for e in mo.events)):
                raise GsiInputError(f"{key}.contact.motion.kind = {mo.kind!r}: the wall of an "
                                    "FE structure may only turn about its axis (rotation, or a "
                                    "schedule of rotations without velocity)")
        self.material_spec()

    @property
    def key(self) -> str:
        """Key path of this table in error messages (e.g. ``structures[0]``)."""
        return getattr(self, "_key", "structure")

    def material_spec(self):
        """The material for :func:`gsi.fem.materials.get_material`: a name or overrides."""
        from gsi.fem.materials import get_material
        over = {k: getattr(self, k) for k in ("E", "nu", "rho", "alpha", "k", "c")
                if getattr(self, k) is not None}
        spec = dict(base=self.material, **over) if over else self.material
        try:
            get_material(spec)
        except GsiInputError as exc:
            raise GsiInputError(str(exc).replace("structure.material", f"{self.key}.material")
                                .replace("structure.", f"{self.key}.")) from None
        return spec

    def structural_material(self):
        """The physical (unscaled) :class:`gsi.fem.materials.StructuralMaterial`."""
        from gsi.fem.materials import get_material
        return get_material(self.material_spec())

    @property
    def has_elasticity(self) -> bool:
        return self.contact.mode in ("mechanical", "both")

    @property
    def has_heat(self) -> bool:
        return self.contact.mode in ("thermal", "both")

    def referenced_tags(self) -> list[tuple[str, str]]:
        """(key path, tag) of every surface tag the table names."""
        refs = [(f"contact.tags[{i}]", t) for i, t in enumerate(self.contact.tags)]
        if self.has_elasticity:
            refs += [(f"supports[{i}]", t) for i, t in enumerate(self.supports)]
            refs += [(f"loads[{i}].tag", ld.tag) for i, ld in enumerate(self.loads)]
        if self.thermal is not None:
            refs += self.thermal.tags_used()
        return refs

    # ------------------------------------------------------------------ checks
    def file_path(self, base_dir) -> pathlib.Path:
        return pathlib.Path(base_dir) / self.file

    def _mesh_groups(self, base_dir) -> tuple[list[str], str]:
        """(surface group names of the mesh, what to call the mesh in messages)."""
        from gsi import meshes
        if self.mesh is not None:
            return list(meshes.GROUPS[self.mesh]), f"the '{self.mesh}' builder"
        f = self.file_path(base_dir)
        if not f.is_file():
            raise GsiInputError(f"{self.key}.file = '{self.file}': no such file (looked in "
                                f"{pathlib.Path(base_dir).resolve()})")
        g = meshes.physical_groups(f, params=self.geometry, key=self.key)
        if not g["volumes"]:
            raise GsiInputError(f"{self.key}.file = '{self.file}': no physical volume; add a "
                                "'Physical Volume(\"name\") = {...};'")
        return list(g["surfaces"]), f.name

    def check_tags(self, groups: list[str], where: str) -> None:
        listed = ", ".join(groups) or "none"
        for k, v in self.tags.items():
            if v not in groups:
                raise GsiInputError(f"{self.key}.tags.{k} = '{v}': no physical surface group "
                                    f"of that name in {where}; its groups: {listed}")
        names = set(groups) | set(self.tags)
        for sub, t in self.referenced_tags():
            if t not in names:
                raise GsiInputError(
                    f"{self.key}.{sub} = '{t}': not a surface group of {where} nor a key of "
                    f"{self.key}.tags; its groups: {listed} (map one: tags = {{{t} = \"...\"}})")

    def check(self, path: str | None = None, *, base_dir=".", materials: dict | None = None) -> None:
        """What can be found before a run without building (one process, cheap):
        the values (:meth:`validate`), the file readable and its parameters known, every
        tag present in the mesh, and with ``materials`` (the case's DEM materials) the
        wall material (:meth:`dem_wall_material`). Raises a one-line GsiInputError."""
        self.validate(path or self.key)
        groups, where = self._mesh_groups(base_dir)
        self.check_tags(groups, where)
        if materials is not None:
            self.dem_wall_material(materials)

    # ------------------------------------------------------------------ DEM wall
    def apply_motion(self, wall, t: float) -> None:
        """Set the rotation of the DEM ``wall`` (the contact wall, rank ``root``) to the
        state of ``contact.motion`` at time ``t`` (s); nothing without a motion.  The wall's
        triangles turn with it; the FE problem lives in the body's own frame (a rigid
        rotation carries the shell's temperature field along)."""
        mo = self.contact.motion
        if mo is None or wall is None:
            return
        _, omega, c = mo.state_at(t)
        wall.set_motion(omega=omega, centre=c)

    def wall_material_name(self) -> str:
        """Name of the wall's DEM material: ``contact.wall_material`` or ``<name>_wall``."""
        return self.contact.wall_material or f"{self.name}_wall"

    def dem_wall_material(self, dem_materials: dict):
        """(name, gsi.dem.Material) of the wall, for the runner to register before the DEM
        is built. ``dem_materials``: the case's DEM materials by name (objects with E, nu,
        rho, e, mu, mu_r, k, cp). A given ``contact.wall_material`` must be one of them and,
        with heat coupling, have the structure's conductivity k (the particle-wall
        conductance uses it); otherwise the wall material is derived from the structure's
        E, nu, rho, k and c with ``contact.e``, ``mu``, ``mu_r``."""
        from gsi.dem import Material
        mat = self.structural_material()
        name = self.wall_material_name()
        if self.contact.wall_material is not None:
            if name not in dem_materials:
                raise GsiInputError(f"{self.key}.contact.wall_material = '{name}': not a "
                                    f"[materials.X] table; defined: "
                                    f"{', '.join(sorted(dem_materials))}")
            m = dem_materials[name]
            if self.has_heat and not math.isclose(m.k, mat.k, rel_tol=1e-9):
                raise GsiInputError(
                    f"materials.{name}.k = {m.k}: must equal {self.key}.k (the structure's "
                    f"conductivity, {mat.k} W/(m K)) for contact.mode = '{self.contact.mode}'; "
                    f"or omit {self.key}.contact.wall_material to derive it")
            if isinstance(m, Material):
                return name, m
            return name, Material(E=m.E, nu=m.nu, rho=m.rho, e=m.e, mu=m.mu, mu_r=m.mu_r,
                                  k=m.k, cp=m.cp)
        derived = Material(E=mat.E, nu=mat.nu, rho=mat.rho, e=self.contact.e, mu=self.contact.mu,
                           mu_r=self.contact.mu_r, k=mat.k, cp=mat.c)
        if name in dem_materials and dem_materials[name] != derived:
            raise GsiInputError(f"materials.{name}: the name of {self.key}'s derived wall "
                                "material is taken; rename the table or set "
                                f"{self.key}.contact.wall_material = '{name}'")
        return name, derived

    # ------------------------------------------------------------------ build
    def thermal_table(self):
        """The ``thermal`` table, its defaults when the structure has heat but no table
        (None without heat)."""
        if self.has_heat and self.thermal is None:
            return StructureThermal()
        return self.thermal

    def load_mesh(self, *, comm, base_dir=".", root: int = 0):
        """The distributed mesh with the ``tags`` mapping applied (collective;
        :func:`gsi.case.build_structure.load_mesh`)."""
        from gsi.case.build_structure import load_mesh
        return load_mesh(self, comm=comm, base_dir=base_dir, root=root)

    def build(self, *, comm, dt_dem: float, gravity=(0.0, 0.0, -9.81), base_dir=".",
              heat_scale: float = 1.0, root: int = 0):
        """The structure set-up (collective; see the module docstring).

        Parameters
        ----------
        comm : MPI communicator of the FE.
        dt_dem : float
            DEM time step (s); dt_FE = n_sub dt_dem.
        gravity : (3,) float
            Gravity (m/s^2): the self-weight (``self_weight``) and the direction of the
            trial shape of the period estimate.
        base_dir : path
            Directory of the case file (``file`` is relative to it).
        heat_scale : float
            Heat-capacity scale s: the structure's c / s (the particles' cp / s is the
            runner's, :func:`gsi.coupling.thermal.scale_heat_capacity`).
        root : int
            Rank of gmsh and of the DEM.

        Returns
        -------
        gsi.coupling.coupled_structure.CoupledStructure
        """
        from gsi.case.build_structure import build_structure
        return build_structure(self, comm=comm, dt_dem=dt_dem, gravity=gravity,
                               base_dir=base_dir, heat_scale=heat_scale, root=root)
