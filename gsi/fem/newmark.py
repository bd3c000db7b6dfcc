r"""The time scheme of :class:`gsi.fem.elasticity.Elasticity`: generalized-alpha (Chung &
Hulbert 1993) with Newmark's updates, ``"newmark"`` its average-acceleration special case
(formulas: the elasticity module's docstring).

With c0 = 1/(beta dt^2), c1 = 1/(beta dt), c2 = 1/(2 beta) - 1, c4 = gamma/(beta dt),
c5 = gamma/beta - 1, c6 = dt (gamma/(2 beta) - 1) and Rayleigh damping C = a0 M + a1 K,
a step solves (c_M M + c_K K) u_{n+1} = b with

.. math::
    c_M = (1 - \alpha_m) c_0 + (1 - \alpha_f) c_4 a_0, \quad
    c_K = (1 - \alpha_f)(1 + c_4 a_1),

    b = (1 - \alpha_f) f_{n+1} + \alpha_f f_n + M w_M + K w_K,

    w_C = (1 - \alpha_f)(c_4 u_n + c_5 v_n + c_6 a_n) - \alpha_f v_n, \quad
    w_M = (1 - \alpha_m)(c_0 u_n + c_1 v_n + c_2 a_n) - \alpha_m a_n + a_0 w_C, \quad
    w_K = a_1 w_C - \alpha_f u_n .
"""
from __future__ import annotations

import numpy as np

from gsi.errors import GsiInputError

SCHEMES = ("static", "newmark", "generalized_alpha")


def check_scheme(scheme: str, dt, rayleigh) -> None:
    """Refuse an unknown ``scheme``, a dynamic one without a step ``dt`` > 0 (s), and a
    Rayleigh pair ``rayleigh`` that is not two numbers >= 0."""
    if scheme not in SCHEMES:
        raise GsiInputError(f"structure.scheme = {scheme!r}: must be one of {list(SCHEMES)}")
    if scheme != "static" and not (dt is not None and np.isfinite(dt) and dt > 0):
        raise GsiInputError(f"structure.dt = {dt!r}: must be > 0 (s) for scheme {scheme!r}")
    if len(rayleigh) != 2 or min(rayleigh) < 0:
        raise GsiInputError(f"structure.rayleigh = {rayleigh!r}: must be two numbers >= 0 "
                            "(a0 1/s, a1 s)")


def newmark_parameters(scheme: str, rho_inf: float = 1.0) -> dict:
    """alpha_m, alpha_f, beta, gamma of the named scheme."""
    if scheme == "newmark":
        return dict(alpha_m=0.0, alpha_f=0.0, beta=0.25, gamma=0.5)
    if scheme == "generalized_alpha":
        if not 0.0 <= rho_inf <= 1.0:
            raise GsiInputError(f"structure.rho_inf = {rho_inf!r}: must be in [0, 1]")
        am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
        af = rho_inf / (rho_inf + 1.0)
        return dict(alpha_m=am, alpha_f=af, beta=0.25 * (1.0 - am + af) ** 2,
                    gamma=0.5 - am + af)
    raise GsiInputError(f"structure.scheme = {scheme!r}: must be one of {list(SCHEMES)}")


class Newmark:
    """The scheme's coefficients for step ``dt`` (s) and Rayleigh damping ``rayleigh`` =
    (a0 (1/s), a1 (s)); ``params``: :func:`newmark_parameters`."""

    def __init__(self, params: dict, dt: float, rayleigh: tuple[float, float]):
        self.params, self.dt, self.rayleigh = params, dt, rayleigh
        p = params
        beta, gamma = p["beta"], p["gamma"]
        self.c0, self.c1, self.c2 = 1.0 / (beta * dt**2), 1.0 / (beta * dt), 0.5 / beta - 1.0
        self.c4, self.c5 = gamma / (beta * dt), gamma / beta - 1.0
        self.c6 = dt * (0.5 * gamma / beta - 1.0)

    def matrix_weights(self) -> tuple[float, float]:
        """(c_M, c_K) of the effective matrix c_M M + c_K K."""
        p, (a0, a1) = self.params, self.rayleigh
        c_M = (1.0 - p["alpha_m"]) * self.c0 + (1.0 - p["alpha_f"]) * self.c4 * a0
        c_K = (1.0 - p["alpha_f"]) * (1.0 + self.c4 * a1)
        return c_M, c_K

    def history(self, un, vn, an, wM, wK, tmp) -> None:
        """w_M into ``wM`` and w_K into ``wK`` (PETSc vectors) from u_n, v_n, a_n;
        ``tmp`` is scratch."""
        am, af = self.params["alpha_m"], self.params["alpha_f"]
        a0, a1 = self.rayleigh
        wM.array[:] = 0.0
        wM.axpy((1.0 - am) * self.c0, un)
        wM.axpy((1.0 - am) * self.c1, vn)
        wM.axpy((1.0 - am) * self.c2 - am, an)
        # C w_C = a0 M w_C + a1 K w_C: w_C goes to tmp
        tmp.array[:] = 0.0
        tmp.axpy((1.0 - af) * self.c4, un)
        tmp.axpy((1.0 - af) * self.c5 - af, vn)
        tmp.axpy((1.0 - af) * self.c6, an)
        wM.axpy(a0, tmp)
        wK.array[:] = 0.0
        wK.axpy(a1, tmp)
        wK.axpy(-af, un)

    def update(self, u_new, u_old, v_old, a_old):
        """Newmark's updates: (v_{n+1}, a_{n+1}) from u_{n+1} and the old fields
        (arrays)."""
        gamma, dt = self.params["gamma"], self.dt
        a_new = self.c0 * (u_new - u_old) - self.c1 * v_old - self.c2 * a_old
        return v_old + dt * ((1.0 - gamma) * a_old + gamma * a_new), a_new
