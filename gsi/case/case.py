"""A case: a study composed of parts, from a TOML file or from Python.

A case file is a set of TOML tables, each of which is one object of this package::

    [case]            CaseInfo        name, description
    [run]             Run             duration, dt, seed, threads, heat_time_scale
    [dem]             Dem             contact law, rolling, heat model, gravity, domain
    [materials.NAME]  Material        particle and rigid-wall materials
    [[pairs]]         Pair            e, mu, mu_r of one material pair
    [[particles]]     ParticleSource  fills, streams, particles from a file
    [[walls]]         Wall            planes, mesh files, built shapes; each with a Motion
    [[structures]]    Structure       FE bodies (builder or the user's .geo/.msh), coupled
    [[thermal_contacts]] ThermalContact heat across the overlap of two structures (R_c)
    [[monitors]]      Monitor         time series to CSV
    [output]          Output          interval, fields, pictures
    [extrapolation]   Extrapolation   long-time heat extrapolation (seed 003)
    [quick]           (overrides)     keys that replace the case's own with ``--quick``

The TOML is a thin layer: :func:`load_case` hands each table to
:func:`gsi.config.schema.load`, which builds the same dataclasses a Python user builds::

    from gsi.case import Case, CaseInfo, Run, Dem, Material, ParticleSource, Size, Region, \
        Wall, Output
    case = Case(case=CaseInfo(name="box"), run=Run(duration=0.3),
                dem=Dem(domain_lo=(0, 0, 0), domain_hi=(0.1, 0.1, 0.2)),
                materials={"glass": Material(E=5e6, nu=0.3, rho=2500)},
                particles=[ParticleSource(material="glass", count=500,
                                          size=Size(radius=2e-3),
                                          region=Region(kind="box", lo=(0, 0, 0.05),
                                                        hi=(0.1, 0.1, 0.2)))],
                walls=[Wall(kind="box", material="glass", lo=(0, 0, 0), hi=(0.1, 0.1, 0.2))],
                output=Output(interval=0.05))
    gsi.run_case(case, out="out/box")

``[quick]`` holds a partial case whose keys replace the case's own when the case runs
with ``--quick`` (arrays of tables merge element by element: ``[[quick.particles]]
count = 400`` changes the first source's count). Without a ``[quick]`` table, --quick
runs a fifth of the duration.

Heat-capacity time scaling (``run.heat_time_scale`` = s, a documented alternative to the
long-time extrapolation of seed 003): particle c_p and structure c are divided by s, so
every thermal time constant (conduction, contact, convection) shrinks by s; temperatures
at simulated time t are those of the physical system at s t, heat flows (W) are
physical, stored energies are the physical ones divided by s. The mechanics is not
scaled.
"""
from __future__ import annotations

import copy
import dataclasses
import math
import pathlib
import tomllib
import warnings
from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

from gsi.case.extrapolation import Extrapolation
from gsi.case.materials import Material, Pair
from gsi.case.monitors import Monitor
from gsi.case.settings import CaseInfo, Dem, Output, Run
from gsi.case.sources import ParticleSource
from gsi.case.structure import Structure
from gsi.case.thermal_contacts import ThermalContact
from gsi.case.walls import Wall
from gsi.config.schema import load, param
from gsi.errors import GsiInputError

__all__ = ["Case", "load_case", "case_from_table", "case_to_table", "merge_tables", "validated",
           "DT_WARN", "DT_DEFAULT", "DT_REFUSE", "MAX_OVERLAP", "MAX_SKIN",
           "MAX_IMPACT_OVERLAP"]

# the one time-step rule's thresholds (fractions of the Rayleigh time / linear contact time)
from gsi.dem.materials import (DT_DEFAULT, DT_LINEAR_DEFAULT, DT_LINEAR_REFUSE,  # noqa: E402
                               DT_REFUSE, DT_WARN)
from gsi.case.sources import MAX_OVERLAP  # noqa: E402  (the sources check it; one constant)
from gsi.case import case_checks  # noqa: E402
from gsi.case.case_checks import MAX_IMPACT_OVERLAP, MAX_SKIN  # noqa: E402,F401
from gsi.case import input_checks, sizes  # noqa: E402
from gsi.case.input_checks import check_output_names  # noqa: E402
from gsi.case.structure_checks import check_structures  # noqa: E402
#: more particles than this in one case is refused before any allocation
MAX_PARTICLES = 20_000_000


@dataclass(kw_only=True)
class Case:
    """A study composed of parts (see the module docstring)."""

    case: CaseInfo = param(default_factory=CaseInfo, doc="the [case] table")
    run: Run = param(doc="the [run] table")
    dem: Dem = param(doc="the [dem] table")
    materials: dict[str, Material] = param(doc="[materials.NAME] tables")
    pairs: list[Pair] = param(default_factory=list, doc="[[pairs]] tables")
    particles: list[ParticleSource] = param(default_factory=list, doc="[[particles]] tables")
    walls: list[Wall] = param(default_factory=list, doc="[[walls]] tables")
    structures: list[Structure] = param(default_factory=list, doc="[[structures]] tables")
    thermal_contacts: list[ThermalContact] = param(default_factory=list,
                                                   doc="[[thermal_contacts]] tables")
    monitors: list[Monitor] = param(default_factory=list, doc="[[monitors]] tables")
    output: Output = param(doc="the [output] table")
    extrapolation: Optional[Extrapolation] = param(
        None, doc="[extrapolation]: long-time heat extrapolation (gsi.case.extrapolation)")
    quick: dict[str, Any] = param(default_factory=dict,
                                  doc="[quick]: keys replacing the case's own with --quick")
    #: directory of the case file: relative paths (mesh and particle files) resolve here
    base_dir: pathlib.Path = dataclasses.field(default=pathlib.Path("."), init=False,
                                               repr=False, compare=False)

    # ------------------------------------------------------------------ schema checks
    def validate(self, path: str) -> None:
        """Cross-table checks of the schema: names that must exist and be unique."""
        if not self.materials:
            raise GsiInputError("materials: missing; give at least one [materials.NAME] table")
        for i, p in enumerate(self.particles):     # default names: particles<i>, walls<i>
            p.name = p.group(i)
        for i, w in enumerate(self.walls):
            w.name = w.name if w.name is not None else f"walls{i}"
        known = ", ".join(sorted(self.materials))
        for section in ("particles", "walls"):
            for i, item in enumerate(getattr(self, section)):
                if item.material not in self.materials:
                    raise GsiInputError(f"{section}[{i}].material = '{item.material}': not a "
                                        f"[materials.X] table; defined: {known}")
        for i, p in enumerate(self.pairs):
            for m in p.materials:
                if m not in self.materials and m not in self.structure_names():
                    raise GsiInputError(f"pairs[{i}].materials = {list(p.materials)}: '{m}' is "
                                        f"not a [materials.X] table; defined: {known}")
        for section, attr in (("particles", "name"), ("walls", "name"),
                              ("structures", "name"), ("monitors", "name")):
            seen = {}
            for i, item in enumerate(getattr(self, section)):
                name = getattr(item, attr)
                if name is None:
                    continue
                if name in seen:
                    raise GsiInputError(f"{section}[{i}].name = {name!r}: already used by "
                                        f"{section}[{seen[name]}]; names must be unique")
                seen[name] = i
        check_output_names(self)
        if not self.particles:
            raise GsiInputError("particles: missing; give at least one [[particles]] table")
        if self.dem.radiation:
            for i, p in enumerate(self.particles):
                if self.materials[p.material].emissivity is None:
                    raise GsiInputError(
                        f"materials.{p.material}.emissivity: missing; dem.radiation = true "
                        f"needs the emissivity (0-1) of every particle material "
                        f"(particles[{i}])")
        if self.output.interval > self.run.duration:
            raise GsiInputError(f"output.interval = {self.output.interval}: must be <= "
                                f"run.duration = {self.run.duration} (s)")

    def structure_names(self) -> list[str]:
        return [s.name for s in self.structures]

    def wall_names(self) -> list[str]:
        return [w.name for w in self.walls]

    def group_names(self) -> list[str]:
        return [p.name for p in self.particles]

    @property
    def thermal(self) -> bool:
        """True if the particles conduct heat (``dem.heat`` is not 'none')."""
        return self.dem.heat != "none"

    # ------------------------------------------------------------------ materials, dt
    def dem_materials(self) -> dict:
        """Every DEM material by name (gsi.dem.Material): the case's and the structures'
        contact-wall materials, with c_p divided by ``run.heat_time_scale``."""
        s = self.run.heat_time_scale
        mats = {name: m.to_dem(heat_scale=s) for name, m in self.materials.items()}
        for st in self.structures:
            name, mat = st.dem_wall_material(mats)
            if name not in mats:
                mats[name] = mat
        return mats

    def pair_overrides(self) -> dict:
        """``{(a, b): {"e": .., ...}}`` for :class:`gsi.dem.Simulation`."""
        return {tuple(p.materials): p.overrides() for p in self.pairs}

    def source_radii(self, i: int) -> tuple[float, float]:
        """Smallest and largest radius (m) of particle source i (its size table, or its
        file)."""
        p = self.particles[i]
        if p.size is not None:
            return p.size.smallest, p.size.largest
        from gsi.case.sources import read_particle_file
        r = read_particle_file(self.base_dir / p.file, key=f"particles[{i}].file")["radius"]
        return float(r.min()), float(r.max())

    def source_smallest_radius(self, i: int) -> float:
        return self.source_radii(i)[0]

    def smallest_radius(self) -> float:
        return min(self.source_smallest_radius(i) for i in range(len(self.particles)))

    def rayleigh_times(self) -> list[float]:
        """Rayleigh time t_R (s) of the smallest particle of each source."""
        from gsi.dem.materials import rayleigh_time
        mats = self.dem_materials()
        return [rayleigh_time(self.source_smallest_radius(i), mats[p.material])
                for i, p in enumerate(self.particles)]

    def contact_time_linear(self) -> float:
        """Linear law: the shortest pair contact t_c = pi sqrt(m*/k_n), m* = m_min/2 (s)."""
        m_min = min(self.materials[p.material].rho * 4.0 / 3.0 * math.pi
                    * self.source_smallest_radius(i) ** 3 for i, p in enumerate(self.particles))
        return math.pi * math.sqrt(0.5 * m_min / self.dem.k_n)

    def time_step(self) -> float:
        """The DEM step the case runs with (s); the one time-step rule of gsi.

        Hertz (t_R: the smallest Rayleigh time of the particles): the default step is
        0.2 t_R; up to 0.3 t_R is accepted, up to :data:`DT_REFUSE` = 0.5 t_R with a
        warning (contacts are resolved coarsely); above 0.5 t_R the case is refused unless
        ``dem.force_dt`` (a step of 0.95 t_R blows up a pour, 1.5-3 t_R empties its box);
        with ``force_dt`` it runs with a warning that says the results are not to be
        trusted. Linear law (t_c = pi sqrt(m*/k_n), m* = m_min/2): default t_c/50; above
        t_c/50 a warning; above t_c/10 refused unless ``force_dt``.
        """
        if self.dem.contact == "linear":
            t_ref, name, default, warn = self.contact_time_linear(), "the linear contact time " \
                "t_c = pi sqrt(m*/k_n)", DT_LINEAR_DEFAULT, DT_LINEAR_DEFAULT
            limit = DT_LINEAR_REFUSE
        else:
            t_ref, name, default, warn = min(self.rayleigh_times()), "the Rayleigh time t_R", \
                DT_DEFAULT, DT_WARN
            limit = DT_REFUSE
        dt = self.run.dt if self.run.dt is not None else default * t_ref
        if dt > limit * t_ref * (1 + 1e-12):
            over = 1.0 if self.dem.contact != "linear" and dt > t_ref else limit
            msg = (f"run.dt = {dt:g}: above {over:g} x {name} = {t_ref:.3g} s; use "
                   f"run.dt <= {default * t_ref:.3g}")
            if not self.dem.force_dt:
                raise GsiInputError(msg + " (or dem.force_dt = true to run anyway)")
            warnings.warn(f"dem.force_dt = true: {msg}; particles may fly apart or be lost and "
                          f"the results are not to be trusted ({dt / t_ref:.3g} x the limit "
                          f"reference)", stacklevel=2)
        elif dt > warn * t_ref * (1 + 1e-12):
            warnings.warn(f"run.dt = {dt:g} s is above {warn:g} x {name} = {t_ref:.3g} s: "
                          f"contacts are resolved coarsely; run.dt <= {default * t_ref:.3g} s "
                          f"is safe", stacklevel=2)
        return dt

    # ------------------------------------------------------------------ pre-run checks
    def check(self) -> float:
        """Everything that can be found before a run (``gsi check``); returns the DEM step.

        Files readable, mesh tags present, regions inside the domain, particles that fit
        their region, a radius that looks like millimetres, absurd counts, a schedule
        event after the end, monitors naming things that exist, a Verlet skin far above the
        particle size, a material too soft for the impact speed, particles of files that
        overlap, a stream asked for more particles per step than its region holds, the
        time step (:meth:`time_step`); and the same for the ``[quick]`` form.
        """
        dom = dict(domain_lo=self.dem.domain_lo, domain_hi=self.dem.domain_hi)
        for i, p in enumerate(self.particles):
            p.check(f"particles[{i}]", base_dir=self.base_dir, duration=self.run.duration,
                    **dom)
        for i, w in enumerate(self.walls):
            w.check(f"walls[{i}]", base_dir=self.base_dir, duration=self.run.duration, **dom)
        for i, st in enumerate(self.structures):
            st.check(f"structures[{i}]", base_dir=self.base_dir, materials=self.materials)
            if st.has_heat and not self.thermal:
                raise GsiInputError(f"structures[{i}].contact.mode = {st.contact.mode!r}: a "
                                    f"thermal contact needs dem.heat = 'area', 'radius' or "
                                    f"'constant'")
        by_name = {st.name: st for st in self.structures}
        for i, c in enumerate(self.thermal_contacts):
            c.check(f"thermal_contacts[{i}]", structures=by_name)
        for i, m in enumerate(self.monitors):
            m.check(f"monitors[{i}]", walls=set(self.wall_names()),
                    structures=set(self.structure_names()), groups=set(self.group_names()),
                    thermal=self.thermal or self.dem.radiation,
                    driven={w.name for w in self.walls if w.motion.driven})
        if self.quick:
            q = self.quick_variant()
            if q.run.duration > self.run.duration:
                raise GsiInputError(f"quick.run.duration = {q.run.duration}: longer than "
                                    f"run.duration = {self.run.duration} (s); --quick must be "
                                    f"shorter")
        case_checks.check_skin(self)
        case_checks.check_speeds(self)
        case_checks.check_placed_overlaps(self)
        input_checks.check_geometry(self)
        dt = self.time_step()
        case_checks.check_streams(self, dt)
        case_checks.check_radiation(self, dt)
        input_checks.check_stability(self, dt)
        if self.extrapolation is not None:
            self.extrapolation.check(dt=dt, duration=self.run.duration, heat=self.dem.heat,
                                     structures=self.structures)
        size_warnings = sizes.check_sizes(self, dt)
        n_steps = self.run.duration / dt
        if n_steps > 1e10:
            raise GsiInputError(f"run.duration = {self.run.duration}: {n_steps:.2g} DEM steps "
                                f"of {dt:.3g} s; shorten the run or raise run.dt")
        outputs = self.run.duration / self.output.interval
        if outputs > 100_000:
            raise GsiInputError(f"output.interval = {self.output.interval}: {outputs:.3g} "
                                f"outputs; raise it (e.g. to {self.run.duration / 200:.3g} s)")
        if self.output.interval < dt:
            raise GsiInputError(f"output.interval = {self.output.interval}: shorter than the "
                                f"DEM step {dt:.3g} s")
        if self.quick:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")     # the case's own warnings were given
                try:
                    q.check_quick_form()
                except GsiInputError as exc:
                    raise GsiInputError(f"{exc} (with the [quick] overrides)") from None
        for words in size_warnings:
            warnings.warn(words, stacklevel=2)
        return dt

    def check_quick_form(self) -> None:
        """The checks of :meth:`check` that a ``[quick]`` override can break (sizes, counts,
        materials, the step), without those a shorter run breaks on purpose (a stream or a
        schedule event after its end)."""
        dom = dict(domain_lo=self.dem.domain_lo, domain_hi=self.dem.domain_hi)
        for i, p in enumerate(self.particles):
            p.check(f"particles[{i}]", base_dir=self.base_dir, **dom)
        check_structures(self)
        case_checks.check_skin(self)
        case_checks.check_stiffness(self)
        case_checks.check_placed_overlaps(self)
        dt = self.time_step()
        case_checks.check_streams(self, dt)
        case_checks.check_radiation(self, dt)
        input_checks.check_stability(self, dt)
        if self.extrapolation is not None:
            self.extrapolation.check(dt=dt, duration=self.run.duration, heat=self.dem.heat,
                                     structures=self.structures)
        sizes.check_sizes(self, dt, quick=True)
        if self.output.interval < dt:
            raise GsiInputError(f"output.interval = {self.output.interval}: shorter than the "
                                f"DEM step {dt:.3g} s")

    def source_largest_radius(self, i: int) -> float:
        return self.source_radii(i)[1]

    def largest_radius(self) -> float:
        return max(self.source_largest_radius(i) for i in range(len(self.particles)))

    def impact_speed(self, i: int) -> float:
        """Speed (m/s) at which particles of source i may meet: their initial speed plus a
        free fall through the domain's height along gravity."""
        p = self.particles[i]
        g = np.asarray(self.dem.gravity, float)
        gn = float(np.linalg.norm(g))
        height = float(np.abs(g / gn) @ (np.asarray(self.dem.domain_hi) -
                                         np.asarray(self.dem.domain_lo))) if gn > 0 else 0.0
        return float(np.linalg.norm(p.velocity)) + math.sqrt(2.0 * gn * height)

    def radiation_options(self) -> dict | None:
        """Keywords of :meth:`gsi.dem.Simulation.set_radiation` (None: no radiation):
        the emissivity of every material that has one (walls of materials without one
        do not radiate), the cut-off, the evaluation interval and the enclosure."""
        if not self.dem.radiation:
            return None
        from gsi.dem.radiation import CUTOFF_DEFAULT
        d = self.dem
        return dict(emissivity={k: m.emissivity for k, m in self.materials.items()
                                if m.emissivity is not None},
                    cutoff=CUTOFF_DEFAULT if d.radiation_cutoff is None else d.radiation_cutoff,
                    every=1 if d.radiation_every is None else d.radiation_every,
                    T_enclosure=d.radiation_T_enclosure)

    # ------------------------------------------------------------------ quick form
    def quick_variant(self) -> "Case":
        """The case with its ``[quick]`` overrides (or a fifth of the duration)."""
        table = case_to_table(self)
        table.pop("quick", None)
        if self.quick:
            table = merge_tables(table, self.quick)
        else:
            table["run"]["duration"] = self.run.duration / 5
            table["output"]["interval"] = min(self.output.interval, self.run.duration / 5)
        try:
            return case_from_table(table, base_dir=self.base_dir)
        except GsiInputError as exc:
            raise GsiInputError(f"quick.{exc} (a [quick] override)") from None


# ---------------------------------------------------------------------- TOML <-> Case
def _to_plain(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if dataclasses.is_dataclass(value):
        return {f.name: _to_plain(getattr(value, f.name)) for f in dataclasses.fields(value)
                if f.init and getattr(value, f.name) is not None}
    if isinstance(value, dict):
        return {k: _to_plain(v) for k, v in value.items() if v is not None}
    if isinstance(value, (list, tuple)):
        return [_to_plain(v) for v in value]
    return copy.deepcopy(value)


def case_to_table(case: Case) -> dict:
    """The case as a plain TOML-like table (the inverse of :func:`case_from_table`)."""
    return _to_plain(case)


def merge_tables(base: dict, over: dict) -> dict:
    """``over`` merged into ``base``: tables recursively, arrays of tables element by
    element (by position), anything else replaced."""
    out = dict(base)
    for key, value in over.items():
        old = out.get(key)
        if isinstance(value, dict) and isinstance(old, dict):
            out[key] = merge_tables(old, value)
        elif isinstance(value, list) and isinstance(old, list) and \
                all(isinstance(v, dict) for v in value) and all(isinstance(v, dict) for v in old):
            merged = [merge_tables(o, v) for o, v in zip(old, value)]
            out[key] = merged + old[len(value):] + value[len(old):]
        else:
            out[key] = value
    return out


def validated(case: Case) -> Case:
    """A case built in Python, checked exactly as its TOML twin would be: it goes through
    the same schema (every field's unit check and every table's ``validate``)."""
    out = case_from_table(case_to_table(case), base_dir=case.base_dir)
    return out


def case_from_table(table: dict, *, base_dir: pathlib.Path | str = ".") -> Case:
    """Validate an already parsed TOML table into a :class:`Case`."""
    case = load(Case, table)
    case.base_dir = pathlib.Path(base_dir)
    return case


def load_case(path: str | pathlib.Path) -> Case:
    """Read and validate a case file; one-line GsiInputError on any problem."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise GsiInputError(f"{path}: no such case file")
    try:
        text = path.read_bytes().decode("utf-8-sig")      # a byte-order mark is read
    except UnicodeDecodeError as exc:
        raise GsiInputError(f"{path}: not UTF-8 text (byte {exc.start}); save the case file "
                            f"as UTF-8") from None
    except OSError as exc:
        raise GsiInputError(f"{path}: cannot read ({exc.strerror})") from None
    try:
        table = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise GsiInputError(f"{path}: not valid TOML: {exc}") from None
    return case_from_table(table, base_dir=path.parent)

