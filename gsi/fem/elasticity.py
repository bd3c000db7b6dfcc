r"""Linear elasticity on tetrahedra: static ``K u = f`` and dynamic ``M a + C v + K u = f``.

Equations (docs/design.md, "Structure (FE) physics"), small strain, isotropic:

.. math::
    \varepsilon(u) = \tfrac12(\nabla u + \nabla u^T), \quad
    \sigma = 2\mu\,\varepsilon + \lambda\,\mathrm{tr}(\varepsilon) I
             - (3\lambda + 2\mu)\,\alpha\,(T - T_{ref})\, I

    K = \int \sigma(u):\varepsilon(v), \quad M = \int \rho\, u\cdot v, \quad
    C = a_0 M + a_1 K \ \text{(Rayleigh)}

    f = \int \rho g\cdot v + \sum_{tags} \int t_{tag}\cdot v\, ds_{tag}
        + \int (3\lambda+2\mu)\alpha (T - T_{ref})\, \mathrm{div}\, v + \text{nodal loads}

Time integration: generalized-alpha (Chung & Hulbert 1993),

.. math::
    M a_{n+1-\alpha_m} + C v_{n+1-\alpha_f} + K u_{n+1-\alpha_f} = f_{n+1-\alpha_f}

with Newmark's updates (beta, gamma). ``scheme="newmark"`` is the average-acceleration
rule (alpha_m = alpha_f = 0, beta = 1/4, gamma = 1/2: unconditionally stable, no numerical
damping, energy-conserving); ``scheme="generalized_alpha"`` takes the spectral radius at
infinity ``rho_inf`` in [0, 1] (alpha_m = (2 rho_inf - 1)/(rho_inf + 1),
alpha_f = rho_inf/(rho_inf + 1), gamma = 1/2 - alpha_m + alpha_f,
beta = (1 - alpha_m + alpha_f)^2 / 4).

The effective matrix ``c_M M + c_K K`` (Dirichlet rows/columns eliminated) is assembled
and factorized once (``solver="direct"``), or its algebraic-multigrid preconditioner
(BoomerAMG, systems form; GAMG with the rigid-body near-nullspace with
``pc_type = "gamg"``) is built once (``solver="iterative"``: CG
warm-started from u_n); each step builds only the right-hand side

    b = f_{n+1-alpha_f} + M w_M + K w_K - A g

from two matrix-vector products with the unconstrained M and K. M and K are assembled
after the factorization, not before: its working memory is the run's peak, which they
would add to (one-layer P2 silo, 2 ranks, block low-rank factor on disk: 3.46 -> 2.99 GB
at 4e5 dofs, 7.34 GB at 1e6; docs' performance page). The run starts from
rest unless ``u``/``v`` are set; the initial acceleration is zero (it is not solved
for: that would need a second factorization; the resulting start-up error is O(dt)).
"""
from __future__ import annotations

import numpy as np
import ufl
from mpi4py import MPI

from gsi.errors import GsiInputError

from . import compat
from .newmark import SCHEMES, Newmark, check_scheme, newmark_parameters
from .problem import Problem
from .solvers import rigid_body_modes

__all__ = ["Elasticity", "SCHEMES", "newmark_parameters", "epsilon", "sigma_mech", "von_mises"]


def epsilon(u):
    """Small-strain tensor (-)."""
    return ufl.sym(ufl.grad(u))


def sigma_mech(u, mu, lmbda):
    """Mechanical Cauchy stress 2 mu eps + lambda tr(eps) I (Pa)."""
    return 2.0 * mu * epsilon(u) + lmbda * ufl.tr(epsilon(u)) * ufl.Identity(len(u))


def von_mises(s):
    """von Mises equivalent stress sqrt(3/2 s_dev : s_dev) (Pa)."""
    s_dev = s - ufl.tr(s) / 3.0 * ufl.Identity(3)
    return ufl.sqrt(1.5 * ufl.inner(s_dev, s_dev))


class Elasticity(Problem):
    """Linear elastic structure, static or dynamic.

    Parameters
    ----------
    structure : gsi.meshes.StructureMesh
        Mesh with facet tags (names in ``structure.tags``).
    material : StructuralMaterial or str or dict
        Material (library name, table, or object).
    degree : int
        Lagrange degree, 1 or 2 (P2 avoids the bending stiffness of P1 thin walls).
    scheme : {"static", "newmark", "generalized_alpha"}
        Static solve or time integrator.
    dt : float
        Time step (s), required by the dynamic schemes.
    rho_inf : float
        Spectral radius at infinite frequency for "generalized_alpha" (default 1: none of
        the high-frequency damping; 0.8 is common).
    rayleigh : (float, float)
        Rayleigh damping C = a0 M + a1 K: (a0 (1/s), a1 (s)).
    gravity : sequence of 3 float
        Body acceleration (m/s^2); default none.
    T_ref : float
        Stress-free temperature (K or degC, as the temperatures given).
    factorization, solver, petsc_options, rtol, options_key
        The linear solver (:class:`gsi.fem.problem.Problem`; the iterative one here is
        CG + BoomerAMG (:data:`gsi.fem.options.ITERATIVE_PC`); "auto" goes out of core from
        ``gsi.fem.options.AUTO_LARGE_DOFS["elasticity"]`` dofs on).

    Notes
    -----
    Under MPI every method is collective (call it on every rank), except
    ``add_nodal_loads``, ``clear_nodal_loads``, ``set_traction`` and ``set_gravity``
    (local). Set the supports
    (:meth:`clamp`) before the first :meth:`solve`/:meth:`step`; tractions, gravity,
    temperature and nodal loads may change between steps.
    """

    kind = "elasticity"

    def __init__(self, structure, material, *, degree: int = 1, scheme: str = "static",
                 dt: float | None = None, rho_inf: float = 1.0, rayleigh=(0.0, 0.0),
                 gravity=(0.0, 0.0, 0.0), T_ref: float = 0.0, factorization: str | None = None,
                 solver: str = "auto", petsc_options: dict | None = None,
                 options_key: str = "structure.petsc", rtol: float | None = None):
        if degree not in (1, 2):
            raise GsiInputError(f"structure.degree = {degree!r}: must be 1 or 2")
        check_scheme(scheme, dt, rayleigh)
        self._init_problem(structure, material, factorization=factorization, solver=solver,
                           petsc_options=petsc_options, options_key=options_key, rtol=rtol)
        mesh = self.mesh
        self.degree, self.scheme, self.dt = degree, scheme, dt
        self.params = newmark_parameters(scheme, rho_inf) if scheme != "static" else {}
        self.rayleigh = (float(rayleigh[0]), float(rayleigh[1]))

        self.V = compat.vector_space(mesh, degree)
        self.u = compat.function(self.V, "displacement")
        self.v = compat.function(self.V, "velocity")
        self.a = compat.function(self.V, "acceleration")
        self.Q = compat.scalar_space(mesh, 1)
        self.T = compat.function(self.Q, "temperature")
        self.T_ref = compat.constant(mesh, float(T_ref))
        self.T.x.array[:] = float(T_ref)
        self.g = compat.constant(mesh, np.asarray(gravity, dtype=float))
        self.tractions = {name: compat.constant(mesh, np.zeros(3))
                          for name in structure.tags if name != "volume"}
        self._init_loads()
        self.newmark = Newmark(self.params, dt, self.rayleigh) if scheme != "static" else None

    # ------------------------------------------------------------------ set-up API
    def clamp(self, tag: str, *, components=None, value=None) -> None:
        """Prescribe the displacement on the surface ``tag`` (Dirichlet support).

        Parameters
        ----------
        tag : str
            Surface name, e.g. "support".
        components : sequence of int, optional
            Constrained components (0 = x, 1 = y, 2 = z); default all three (clamped).
        value : sequence of float, optional
            Prescribed displacement per constrained component (m); default 0.
        """
        self._check_not_set_up("clamp")
        self.structure.facet_tag(tag)
        comps = (0, 1, 2) if components is None else tuple(int(c) for c in components)
        if not comps or any(c not in (0, 1, 2) for c in comps) or len(set(comps)) != len(comps):
            raise GsiInputError(f"structure.supports.{tag}.components = {components!r}: "
                                "must be distinct values of 0, 1, 2")
        val = np.zeros(len(comps)) if value is None else np.asarray(value, dtype=float).ravel()
        if val.size != len(comps):
            raise GsiInputError(f"structure.supports.{tag}.value = {value!r}: must have "
                                f"{len(comps)} entries (m)")
        self.dirichlet.prescribe(tag, self.V, val, components=comps)

    def set_traction(self, tag: str, traction) -> None:
        """Uniform surface traction on ``tag`` (Pa), vector (3,); may change every step."""
        if tag not in self.tractions:
            self.structure.facet_tag(tag)
        t = np.asarray(traction, dtype=float).ravel()
        if t.size != 3 or not np.all(np.isfinite(t)):
            raise GsiInputError(f"structure.tractions.{tag} = {traction!r}: must be 3 numbers (Pa)")
        self.tractions[tag].value[:] = t

    def set_gravity(self, g) -> None:
        """Body acceleration (m/s^2), vector (3,)."""
        self.g.value[:] = np.asarray(g, dtype=float).ravel()

    def set_temperature(self, T) -> None:
        """Temperature field loading the thermal strain: a Function on the same mesh, or a
        number (uniform) (K or degC, as ``T_ref``)."""
        if np.ndim(T) == 0 and not hasattr(T, "function_space"):
            self.T.x.array[:] = float(T)
        else:
            compat.interpolate_function(self.T, T)
        compat.scatter_forward(self.T)

    @property
    def supports(self) -> tuple[str, ...]:
        """Tags with a prescribed displacement (:meth:`clamp`), in the order given."""
        return self.dirichlet.tags

    def has_prescribed_motion(self) -> bool:
        """True if some support prescribes a nonzero displacement (local, no MPI call)."""
        return self.dirichlet.moves()

    # ------------------------------------------------------------------ assembly
    def _check_not_set_up(self, what: str) -> None:
        if self.is_set_up:
            raise GsiInputError(f"structure.{what}: supports must be set before the first solve "
                                "(the matrix is factorized once)")

    def _setup(self) -> None:
        if self.is_set_up:
            return
        m = self.material
        mu = compat.constant(self.mesh, m.mu)
        lmbda = compat.constant(self.mesh, m.lmbda)
        rho = compat.constant(self.mesh, m.rho)
        kappa = compat.constant(self.mesh, (3.0 * m.lmbda + 2.0 * m.mu) * m.alpha)
        self._mu, self._lmbda, self._kappa = mu, lmbda, kappa
        u, w = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        dx = compat.measure("dx", self.mesh)
        ds = compat.measure("ds", self.mesh, self.structure.facet_tags)
        k_form = ufl.inner(sigma_mech(u, mu, lmbda), epsilon(w)) * dx
        m_form = rho * ufl.inner(u, w) * dx
        c_M, c_K = (0.0, 1.0) if self.newmark is None else self.newmark.matrix_weights()
        a_eff = c_K * k_form if c_M == 0.0 else c_M * m_form + c_K * k_form
        f_form = ufl.inner(rho * self.g, w) * dx \
            + kappa * (self.T - self.T_ref) * ufl.div(w) * dx
        for name, t in self.tractions.items():
            f_form += ufl.inner(t, w) * ds(self.structure.tags[name])
        self._a_eff = compat.form(a_eff)
        A = compat.assemble_matrix(self._a_eff, self.bcs)
        self._A = A
        self._init_vectors(compat.form(f_form), self._a_eff)
        self._F_old = self._b.duplicate()        # f_n
        self._F_old.set(0.0)
        self._wM = self._b.duplicate()
        self._wK = self._b.duplicate()
        self._make_solver(A, self._a_eff, near_nullspace=lambda: rigid_body_modes(self.V, A))
        self._K = compat.assemble_matrix(compat.form(k_form))
        self._M = compat.assemble_matrix(compat.form(m_form)) if self.scheme != "static" else None

    def load_sum(self) -> np.ndarray:
        """Sum over all vertices of the assembled load vector per component (N), (3,)."""
        F = self.load_vector().array.reshape(-1, 3)
        return self.comm.allreduce(F.sum(axis=0), op=MPI.SUM)

    # ------------------------------------------------------------------ solving
    def solve(self):
        """Static solve K u = f. Returns the displacement Function (m)."""
        if self.scheme != "static":
            raise GsiInputError(f"structure.scheme = {self.scheme!r}: call step(), not solve()")
        self._setup()
        self._assemble_load(self._F)
        b = self._b
        self._F.copy(b)
        b.axpy(1.0, self._lift)
        compat.set_bc(b, self.bcs)
        self._solver.solve(b, compat.petsc_vec(self.u))
        compat.scatter_forward(self.u)
        return self.u

    def step(self):
        """Advance one time step dt with the current loads (held over the step).

        Returns the displacement Function at the new time (m).
        """
        if self.scheme == "static":
            raise GsiInputError("structure.scheme = 'static': call solve(), not step()")
        self._setup()
        af = self.params["alpha_f"]
        un, vn, an = (compat.petsc_vec(f) for f in (self.u, self.v, self.a))
        u_old = self.u.x.array.copy()
        v_old = self.v.x.array.copy()
        a_old = self.a.x.array.copy()
        tmp = self._tmp
        self.newmark.history(un, vn, an, self._wM, self._wK, tmp)
        self._assemble_load(self._F)
        b = self._b
        b.array[:] = (1.0 - af) * self._F.array + af * self._F_old.array
        self._M.mult(self._wM, tmp)
        b.axpy(1.0, tmp)
        self._K.mult(self._wK, tmp)
        b.axpy(1.0, tmp)
        b.axpy(1.0, self._lift)
        compat.set_bc(b, self.bcs)
        self._solver.solve(b, un)
        compat.scatter_forward(self.u)
        # Newmark updates (local arrays incl. ghosts, all consistent)
        self.v.x.array[:], self.a.x.array[:] = self.newmark.update(self.u.x.array, u_old,
                                                                   v_old, a_old)
        self._F.copy(self._F_old)
        self.advance_time(self.dt)
        return self.u

    # ------------------------------------------------------------------ state
    def _state_fields(self) -> dict:
        return {"u": self.u, "v": self.v, "a": self.a}

    def _extra_state(self) -> dict:
        """The temperature of the thermal strain (``T``, owned) and the previous load
        vector (``F_old``, once set up)."""
        d = {"T": self.T.x.array[:compat.dof_index_map(self.Q)[0].size_local].copy()}
        if self.is_set_up:
            d["F_old"] = self._F_old.array.copy()
        return d

    def _set_extra_state(self, st: dict) -> None:
        if "T" in st:
            self.T.x.array[:len(st["T"])] = st["T"]
            compat.scatter_forward(self.T)
        if "F_old" in st:
            self._setup()
            self._F_old.array[:] = st["F_old"]

    # ------------------------------------------------------------------ results
    def reaction(self, tag: str | None = None) -> np.ndarray:
        """Total support reaction force (N), (3,): the residual M a + C v + K u - f summed
        over the constrained dofs of ``tag`` (all supports if None). It is the force the
        supports exert on the structure."""
        self._setup()
        dofs = self.dirichlet.dofs(tag, key="structure.reaction tag")
        r = self._tmp
        self._K.mult(compat.petsc_vec(self.u), r)
        res = r.array.copy()
        if self._M is not None:
            a0, a1 = self.rayleigh
            self._M.mult(compat.petsc_vec(self.a), r)
            res += r.array
            if a0 or a1:
                self._M.mult(compat.petsc_vec(self.v), r)
                res += a0 * r.array
                self._K.mult(compat.petsc_vec(self.v), r)
                res += a1 * r.array
        self._assemble_load(self._F)
        res -= self._F.array
        out = np.zeros(3)
        np.add.at(out, dofs % 3, res[dofs])
        return self.comm.allreduce(out, op=MPI.SUM)

    def energies(self) -> dict:
        """Kinetic 1/2 v.Mv and strain 1/2 u.Ku energies (J); external-load potential -f.u."""
        self._setup()
        r = self._tmp
        self._K.mult(compat.petsc_vec(self.u), r)
        strain = 0.5 * r.dot(compat.petsc_vec(self.u))
        kinetic = 0.0
        if self._M is not None:
            self._M.mult(compat.petsc_vec(self.v), r)
            kinetic = 0.5 * r.dot(compat.petsc_vec(self.v))
        self._assemble_load(self._F)
        potential = -self._F.dot(compat.petsc_vec(self.u))
        return dict(kinetic=kinetic, strain=strain, load_potential=potential)

    def sigma(self):
        """UFL expression of the full stress (mechanical minus thermal) (Pa)."""
        self._setup()
        return sigma_mech(self.u, self._mu, self._lmbda) \
            - self._kappa * (self.T - self.T_ref) * ufl.Identity(3)

    def von_mises(self, out=None):
        """von Mises stress interpolated into DG0 (cell values) (Pa); returns the Function."""
        if out is None:
            if getattr(self, "_vm", None) is None:
                self._vm = compat.function(compat.scalar_space(self.mesh, 0, "DG"), "von_mises")
            out = self._vm
        compat.interpolate_expression(out, von_mises(self.sigma()))
        return out

    def max_displacement(self) -> float:
        """Largest nodal displacement magnitude over all ranks (m)."""
        imap, bs = compat.dof_index_map(self.V)
        U = self.u.x.array[: imap.size_local * bs].reshape(-1, 3)
        local = float(np.sqrt((U**2).sum(axis=1)).max()) if U.size else 0.0
        return self.comm.allreduce(local, op=MPI.MAX)

    def displacement_norm(self) -> float:
        """Euclidean norm of the global displacement dof vector (m)."""
        return compat.petsc_vec(self.u).norm()
