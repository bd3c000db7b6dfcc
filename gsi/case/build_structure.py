"""The FE side of a ``[[structures]]`` entry (:class:`gsi.case.structure.Structure`, the
TOML table): its mesh (:func:`load_mesh`) and the coupled structure with its FE problems,
interface and couplings (:func:`build_structure`)."""
from __future__ import annotations

import dataclasses
import math
import pathlib

import numpy as np

from gsi.errors import GsiInputError


def load_mesh(spec, *, comm, base_dir=".", root: int = 0):
    """The distributed mesh of ``spec`` (a :class:`gsi.case.structure.Structure`) with its
    ``tags`` mapping applied (collective): every key of ``tags`` becomes one more name of
    its group, so either name works."""
    from gsi import meshes
    if spec.mesh is not None:
        sm = meshes.build(spec.mesh, comm=comm, **spec.geometry)
    else:
        f = spec.file_path(base_dir)
        msg = None
        if comm.rank == root and not f.is_file():
            msg = (f"{spec.key}.file = '{spec.file}': no such file (looked in "
                   f"{pathlib.Path(base_dir).resolve()})")
        msg = comm.bcast(msg, root=root)
        if msg:
            raise GsiInputError(msg)
        sm = meshes.load_file(f, params=spec.geometry, comm=comm, root=root, key=spec.key)
    groups = [n for n in sm.tags if n != "volume"]
    where = spec.mesh and f"the '{spec.mesh}' builder" or pathlib.Path(spec.file).name
    spec.check_tags(groups, where)
    for k, v in spec.tags.items():
        if k in sm.tags and sm.tags[k] != sm.tags[v]:
            raise GsiInputError(f"{spec.key}.tags.{k} = '{v}': the mesh already has a "
                                f"group '{k}'; map another name")
        sm.tags[k] = sm.tags[v]
    if any(spec.translate):
        from gsi.fem import compat
        x = compat.geometry_x(sm.mesh)
        x[:, :3] += np.asarray(spec.translate, float)
    return sm


def build_structure(spec, *, comm, dt_dem: float, gravity=(0.0, 0.0, -9.81), base_dir=".",
                    heat_scale: float = 1.0, root: int = 0):
    """The structure set-up of ``spec`` (collective; see
    :meth:`gsi.case.structure.Structure.build`)."""
    from gsi.coupling.interface import SurfaceInterface
    from gsi.coupling.staggered import choose_n_sub, lowest_period
    from gsi.coupling.coupled_structure import CoupledStructure
    from gsi.fem.elasticity import Elasticity
    from gsi.fem.heat import Heat
    spec.validate(spec.key)
    if not (dt_dem > 0 and math.isfinite(dt_dem)):
        raise GsiInputError(f"run.dt = {dt_dem!r}: must be > 0 (s)")
    if not (heat_scale > 0 and math.isfinite(heat_scale)):
        raise GsiInputError(f"heat_scale = {heat_scale!r}: must be > 0")
    sm = spec.load_mesh(comm=comm, base_dir=base_dir, root=root)
    mat = spec.structural_material()
    co, th = spec.contact, spec.thermal_table()
    T_ref = th.T_ref if th is not None else 0.0
    T_init = (th.T_initial if th.T_initial is not None else th.T_ref) if th is not None else None
    g = np.asarray(gravity, float)
    el = None
    T_1, a0 = math.nan, spec.rayleigh[0]
    if spec.has_elasticity:
        solve = dict(solver=spec.solver, petsc_options=spec.petsc,
                     options_key=f"{spec.key}.petsc")
        static = Elasticity(sm, mat, degree=spec.degree, T_ref=T_ref, **solve)
        for tag in spec.supports:
            static.clamp(tag)
        direction = g if np.any(g) else (0.0, 0.0, -1.0)
        T_1 = lowest_period(static, direction=direction)
        n_sub = co.n_sub or choose_n_sub(dt_dem, T_1, steps_per_period=co.steps_per_period)
        if spec.damping_ratio is not None:
            a0 = 2.0 * spec.damping_ratio * 2.0 * math.pi / T_1
        body = g if spec.self_weight else (0.0, 0.0, 0.0)
        if spec.scheme == "static":
            el = static
            el.set_gravity(body)
        else:
            el = Elasticity(sm, mat, degree=spec.degree, scheme=spec.scheme,
                            dt=n_sub * dt_dem, rho_inf=spec.rho_inf,
                            rayleigh=(a0, spec.rayleigh[1]), gravity=body, T_ref=T_ref,
                            **solve)
            for tag in spec.supports:
                el.clamp(tag)
        for ld in spec.loads:
            el.set_traction(ld.tag, ld.traction)
        if T_init is not None:
            el.set_temperature(T_init)
    else:
        n_sub = co.n_sub
    heat = None
    if spec.has_heat:
        heat = Heat(sm, dataclasses.replace(mat, c=mat.c / heat_scale), dt=n_sub * dt_dem,
                    theta=th.theta, T_initial=T_init,
                    theta_key=f"{spec.key}.thermal.theta", solver=spec.solver,
                    petsc_options=th.petsc, options_key=f"{spec.key}.thermal.petsc")
        for cv in th.convection:
            heat.set_convection(cv.tag, cv.h, cv.T_ambient)
        for fx in th.fixed:
            heat.fix_temperature(fx.tag, fx.T)
        for fl in th.flux:
            heat.set_flux(fl.tag, fl.q)
        for rd in th.radiation:
            heat.set_radiation(rd.tag, rd.emissivity, rd.T_ambient)
        heat.check_stability()          # theta < 0.5: dt_FE under the explicit limit
    itf = SurfaceInterface(el, heat=heat, tag=co.tags)
    return CoupledStructure(
        name=spec.name, mesh=sm, material=mat, elasticity=el, heat=heat, interface=itf,
        n_sub=n_sub, dt_dem=dt_dem, T_1=T_1, a0=a0, mode=co.mode,
        wall_material=spec.wall_material_name(), relaxation=co.relaxation, T_ref=T_ref,
        heat_scale=heat_scale, root=root)
