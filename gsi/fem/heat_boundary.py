"""The surface conditions of a heat problem besides fixed temperatures
(:class:`gsi.fem.dirichlet.Dirichlet`): convection, a prescribed flux, radiation to
surroundings, and the volumetric source (:class:`HeatBoundary`); the equations are in
:mod:`gsi.fem.heat`."""
from __future__ import annotations

import numpy as np
import scipy.constants
from mpi4py import MPI

from gsi.errors import GsiInputError

from . import compat
from .heat_bounds import facet_factor


def refuse_after_set_up(what: str) -> None:
    """The error of a setting that the factorized matrix has already used."""
    raise GsiInputError(f"structure.heat.{what}: must be set before the first step "
                        "(the matrix is factorized once)")


class HeatBoundary:
    """Convection, flux and radiation on the surface tags of ``structure``, and the
    source.

    Attributes
    ----------
    h : dict of str -> float
        Convection coefficient of each tag (W/(m^2 K); 0: none).
    T_amb, q : dict of str -> Constant
        Ambient temperature of the convection, prescribed flux into the body (W/m^2).
    radiation : dict of str -> (float, Constant)
        Emissivity and surroundings' temperature (K) of each radiating tag.
    source : Constant
        Volumetric heat source (W/m^3).
    """

    def __init__(self, structure, mesh):
        self.structure, self.mesh = structure, mesh
        names = [n for n in structure.tags if n != "volume"]
        self.h = {n: 0.0 for n in names}
        self.T_amb = {n: compat.constant(mesh, 0.0) for n in names}
        self.q = {n: compat.constant(mesh, 0.0) for n in names}
        self.radiation = {}          # tag -> (emissivity, T_ambient Constant)
        self.source = compat.constant(mesh, 0.0)
        self._rad_factor = None

    # ------------------------------------------------------------------ settings
    def set_convection(self, tag: str, h: float, T_ambient: float, *, set_up: bool) -> None:
        """Convection on ``tag``; ``set_up``: whether the matrix is built (h is then fixed)."""
        self.structure.facet_tag(tag)
        if not (np.isfinite(h) and h >= 0):
            raise GsiInputError(f"structure.heat.convection.{tag}.h = {h!r}: must be >= 0 (W/(m^2 K))")
        if set_up and h != self.h[tag]:
            refuse_after_set_up(f"convection.{tag}.h")
        self.h[tag] = float(h)
        self.T_amb[tag].value = float(T_ambient)

    def set_flux(self, tag: str, q: float) -> None:
        """Prescribed heat flux into the body through ``tag`` (W/m^2)."""
        self.structure.facet_tag(tag)
        self.q[tag].value = float(q)

    def set_radiation(self, tag: str, emissivity: float, T_ambient: float, *,
                      set_up: bool) -> None:
        """Radiation out through ``tag``; ``set_up``: whether the matrix is built (the
        emissivity is then fixed)."""
        self.structure.facet_tag(tag)
        if not (np.isfinite(emissivity) and 0.0 < emissivity <= 1.0):
            raise GsiInputError(f"structure.heat.radiation.{tag}.emissivity = {emissivity!r}: "
                                "must be in (0, 1]")
        if not (np.isfinite(T_ambient) and T_ambient >= 0.0):
            raise GsiInputError(f"structure.heat.radiation.{tag}.T_ambient = {T_ambient!r}: "
                                "must be >= 0 (K)")
        if tag in self.radiation:
            if set_up and emissivity != self.radiation[tag][0]:
                refuse_after_set_up(f"radiation.{tag}.emissivity")
            self.radiation[tag][1].value = float(T_ambient)
            return
        if set_up:
            refuse_after_set_up(f"radiation.{tag}")
        self.radiation[tag] = (float(emissivity), compat.constant(self.mesh, float(T_ambient)))

    def exchange_tags(self, fixed: tuple) -> list[str]:
        """Tags through which heat can cross the boundary: convection (h > 0), a nonzero
        flux, radiation, or a fixed temperature (``fixed``: those tags)."""
        return [n for n in self.h if self.h[n] > 0.0 or self.q[n].value != 0.0
                or n in fixed or n in self.radiation]

    # ------------------------------------------------------------------ forms
    def add_matrix_terms(self, k_form, T, w, ds):
        """``k_form`` plus the convection terms h T w ds (T: the trial function)."""
        tags = self.structure.tags
        for n, h in self.h.items():
            if h > 0.0:
                k_form += compat.constant(self.mesh, h) * T * w * ds(tags[n])
        return k_form

    def add_load_terms(self, f_form, w, ds, T_old):
        """``f_form`` plus q w ds, h T_amb w ds and the radiative flux at ``T_old`` (T_n)."""
        tags = self.structure.tags
        for n in self.h:
            f_form += self.q[n] * w * ds(tags[n])
            if self.h[n] > 0.0:
                f_form += compat.constant(self.mesh, self.h[n]) * self.T_amb[n] * w * ds(tags[n])
        for n in self.radiation:
            f_form += self.radiation_flux(n, T_old) * w * ds(tags[n])
        return f_form

    def radiation_flux(self, tag: str, T_old):
        """eps sigma (T_amb^4 - T_n^4): the radiative flux into the body over the step
        (UFL; ``T_old`` is T_n)."""
        eps, T_amb = self.radiation[tag]
        es = compat.constant(self.mesh, eps * scipy.constants.Stefan_Boltzmann)
        return es * (T_amb ** 4 - T_old ** 4)

    def flow_form(self, tag: str, T, ds):
        """int q + h (T_ambient - T) ds over ``tag`` (UFL): the heat flow into the body by
        the boundary data."""
        ds_tag = ds(self.structure.tags[tag])
        expr = self.q[tag] * ds_tag
        if self.h[tag] > 0.0:
            expr += compat.constant(self.mesh, self.h[tag]) * (self.T_amb[tag] - T) * ds_tag
        return expr

    # ------------------------------------------------------------------ stability
    def check_radiation_step(self, dt: float, T_max_body: float, material, comm) -> None:
        """Refuse a step ``dt`` (s) with dt lambda_rad > 1, lambda_rad = 4 eps sigma T_max^3
        times the facet factor of the tag (:mod:`gsi.fem.heat`), T_max the larger of the
        body's ``T_max_body`` and the surroundings (collective)."""
        if not self.radiation:
            return
        if self._rad_factor is None:
            self._rad_factor = {n: comm.allreduce(facet_factor(
                self.mesh, self.structure, n, material), op=MPI.MAX) for n in self.radiation}
        T_max = max(T_max_body, max(T.value for _, T in self.radiation.values()))
        for n, (eps, _) in self.radiation.items():
            lam = 4.0 * eps * scipy.constants.Stefan_Boltzmann * T_max ** 3 * self._rad_factor[n]
            if dt * lam > 1.0:
                raise GsiInputError(
                    f"structure.heat.radiation.{n}: the step dt = {dt:.4g} s is above the "
                    f"explicit radiation limit 1/lambda = {1.0 / lam:.4g} s at T_max = "
                    f"{T_max:.4g} K; lower dt (structures[].contact.n_sub)")
