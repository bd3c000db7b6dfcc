r"""Transient heat conduction in the structure, theta-scheme, factorized once.

.. math::
    \rho c\, \partial_t T = \nabla\cdot(k \nabla T) + s \quad \text{in the body}

    T = T_D \ \text{(Dirichlet tags)}, \quad
    -k\nabla T\cdot n = -q \ \text{(prescribed flux } q \text{ into the body, W/m}^2), \quad
    -k\nabla T\cdot n = h (T - T_\infty) \ \text{(convection)}

plus nodal heat loads (W) at vertices, and surface radiation to surroundings at T_amb,

.. math::
    -k\nabla T\cdot n = \varepsilon \sigma (T^4 - T_{amb}^4) \quad \text{(radiation tags)},

applied explicitly: the flux of a step is evaluated at T_n (the matrix stays factorized
once; a Newton or per-step linearisation would refactorize every step). The explicit term
is stable and monotone for dt lambda_rad <= 1, lambda_rad = 4 eps sigma T_max^3 times the
facet term of the element bound below (checked at every step with the current T_max;
above it the step is refused naming the tag). With the capacity matrix C and the conduction +
convection matrix K, one step of size dt is

.. math::
    (C/dt + \theta K)\, T_{n+1} = (C/dt - (1-\theta) K)\, T_n + F

where F (flux, convective ambient term, source, nodal loads) is held over the step.
theta = 1 (backward Euler, default) is L-stable and does not oscillate after a sudden
change of a boundary temperature; theta = 1/2 (Crank-Nicolson) is second order.
The matrix C/dt + theta K is assembled and factorized once (``solver="direct"``), or its
algebraic-multigrid preconditioner (hypre BoomerAMG; GAMG without hypre) is built once for
CG warm-started from T_n (``solver="iterative"``); h of each tag must be set
before the first step (T_ambient, q and the nodal loads may change every step).

theta < 1/2 (theta = 0: the explicit forward difference of seed 002, the FDEM
contact-heat paper, eq. "{T}_{n+1} = {T}_n + dt {T'}_n", with {T'}_n solved from the
consistent capacity matrix as the paper's Eq. 14) is only conditionally stable. A mode
of the generalised problem K v = lambda C v is amplified by
g = (1 - (1 - theta) lambda dt)/(1 + theta lambda dt), and |g| <= 1 for every mode iff

.. math::
    dt \le \frac{2}{(1 - 2\theta)\,\lambda_{max}} .

The bound used (:meth:`Heat.stable_dt`, P1 simplices only) is the element eigenvalue
bound lambda_max <= max over cells e of lambda_e (the Rayleigh quotient of the assembled
pair is a ratio of sums of element quotients; Dirichlet constraints only lower it).
For a P1 simplex of dimension d, volume V and barycentric gradients g_0..g_d (G the
(d+1) x d matrix of them), K_e = k V G G^T and C_e = rho c V/((d+1)(d+2)) (I + 1 1^T);
K_e 1 = 0 and C_e = rho c V/((d+1)(d+2)) I on the complement of 1, so exactly

.. math::
    \lambda_e = (d+1)(d+2)\, \alpha\, \lambda_{max}(G^T G), \qquad \alpha = k/(\rho c),

plus, for each facet of the cell under convection h (its matrix h A/(d(d+1)) (I + 1 1^T),
largest eigenvalue h A/d, against the smallest eigenvalue of C_e),
(d+1)(d+2) h A/(d rho c V). In 1D this is the classical consistent-mass limit
dt <= h^2/(6 alpha), a third of the lumped-mass h^2/(2 alpha) of the textbook rule
dt <= h^2/(2 d alpha); lambda_max(G^T G) <= sum_i 1/h_i^2 (h_i the cell's heights)
relates it to the cell sizes in 3D. Above the bound :class:`Heat` refuses to step
(GsiInputError naming ``theta_key``).
"""
from __future__ import annotations


import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

from gsi.errors import GsiInputError

from . import compat
from .heat_boundary import HeatBoundary, refuse_after_set_up
from .heat_bounds import check_explicit_step, check_options, eigenvalue_bound, stable_dt
from .problem import Problem


class Heat(Problem):
    """Transient heat conduction.

    Parameters
    ----------
    structure : gsi.meshes.StructureMesh
    material : StructuralMaterial or str or dict
        Uses rho (kg/m^3), c (J/(kg K)) and k (W/(m K)).
    dt : float
        Time step (s).
    theta : float
        0 <= theta <= 1 (default 1, backward Euler); below 0.5 only P1 and only with
        dt <= :meth:`stable_dt` (0: explicit forward difference).
    T_initial : float
        Uniform initial temperature (K or degC).
    degree : int
        Lagrange degree 1 or 2.
    factorization, solver, petsc_options, rtol, options_key
        The linear solver (:class:`gsi.fem.problem.Problem`; the iterative one here is CG
        + algebraic multigrid; "auto" is iterative from
        ``gsi.fem.options.AUTO_LARGE_DOFS["heat"]`` dofs on).
    theta_key : str
        Key named by the stability error (e.g. ``structures[0].thermal.theta``).

    Notes
    -----
    Under MPI every method is collective except ``set_*``/``add_nodal_heat``.
    """

    kind = "heat"

    def __init__(self, structure, material, *, dt: float, theta: float = 1.0,
                 T_initial: float = 0.0, degree: int = 1, factorization: str | None = None,
                 solver: str = "auto", petsc_options: dict | None = None,
                 options_key: str = "structure.petsc", rtol: float | None = None,
                 theta_key: str = "structure.heat.theta"):
        check_options(dt, theta, degree, theta_key)
        self.theta_key = theta_key
        self._init_problem(structure, material, factorization=factorization, solver=solver,
                           petsc_options=petsc_options, options_key=options_key, rtol=rtol)
        mesh = self.mesh
        self.dt, self.theta, self.degree = float(dt), float(theta), degree
        self.V = compat.scalar_space(mesh, degree)
        self.T = compat.function(self.V, "temperature")
        self.T.x.array[:] = float(T_initial)
        self.T_old = compat.function(self.V, "temperature_old")
        #: convection, flux, radiation and source (:class:`gsi.fem.heat_boundary.HeatBoundary`)
        self.boundary = HeatBoundary(structure, mesh)
        self.radiation = self.boundary.radiation      # tag -> (emissivity, T_ambient)
        self._init_loads()
        #: the :class:`gsi.fem.contact_heat.ContactHeatSystem` that steps this body (None:
        #: it steps alone)
        self.contact_system = None
        #: heat (W) the FE-FE contacts put into each owned dof over the last step
        #: (theta-weighted; set by the contact system, zero otherwise)
        self.contact_heat = np.zeros(compat.dof_index_map(self.V)[0].size_local)

    # ------------------------------------------------------------------ set-up API
    def _check_not_set_up(self, what):
        if self.is_set_up:
            refuse_after_set_up(what)

    def fix_temperature(self, tag: str, T: float) -> None:
        """Dirichlet: temperature ``T`` on surface ``tag`` (K or degC)."""
        self._check_not_set_up("fixed_temperature")
        self.dirichlet.prescribe(tag, self.V, T)

    def set_convection(self, tag: str, h: float, T_ambient: float) -> None:
        """Convection on ``tag``: flux out h (T - T_ambient); h in W/(m^2 K).

        h is fixed at the first step; T_ambient may change later."""
        self.boundary.set_convection(tag, h, T_ambient, set_up=self.is_set_up)

    def set_flux(self, tag: str, q: float) -> None:
        """Prescribed heat flux into the body through ``tag`` (W/m^2); may change every step."""
        self.boundary.set_flux(tag, q)

    def set_radiation(self, tag: str, emissivity: float, T_ambient: float) -> None:
        """Radiation out through ``tag``: flux eps sigma (T^4 - T_ambient^4) (W/m^2), T in K,
        explicit in T (module docstring). The emissivity is fixed at the first step;
        T_ambient may change later."""
        self.boundary.set_radiation(tag, emissivity, T_ambient, set_up=self.is_set_up)

    def set_source(self, s: float) -> None:
        """Uniform volumetric heat source (W/m^3)."""
        self.boundary.source.value = float(s)

    #: add heat loads Q (n,) (W, into the body) at global vertex ids (n,)
    add_nodal_heat = Problem.add_nodal_loads
    clear_nodal_heat = Problem.clear_nodal_loads

    @property
    def fixed_tags(self) -> tuple[str, ...]:
        """Tags with a fixed temperature (:meth:`fix_temperature`)."""
        return self.dirichlet.tags

    def exchange_tags(self) -> list[str]:
        """Tags through which heat can cross the boundary: convection (h > 0), a nonzero
        prescribed flux, radiation, or a fixed temperature (the others are insulated)."""
        return self.boundary.exchange_tags(self.dirichlet.tags)

    def mean_temperature(self) -> float:
        """Volume mean of the temperature, int rho c T dx / (rho c V) (collective)."""
        m = self.material
        return self.stored_heat() / (m.rho * m.c * self.volume())

    # ------------------------------------------------------------------ assembly
    def _setup(self):
        if self.is_set_up:
            return
        m = self.material
        rho_c = compat.constant(self.mesh, m.rho * m.c)
        k = compat.constant(self.mesh, m.k)
        self._k = k
        T, w = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        dx = compat.measure("dx", self.mesh)
        ds = compat.measure("ds", self.mesh, self.structure.facet_tags)
        self._ds = ds
        c_form = rho_c * T * w * dx
        k_form = self.boundary.add_matrix_terms(
            k * ufl.inner(ufl.grad(T), ufl.grad(w)) * dx, T, w, ds)
        f_form = self.boundary.add_load_terms(self.boundary.source * w * dx, w, ds, self.T_old)
        theta, dt = self.theta, self.dt
        self.check_stability()
        a_form = (1.0 / dt) * c_form if theta == 0.0 else (1.0 / dt) * c_form + theta * k_form
        self._a = compat.form(a_form)
        self._C = compat.assemble_matrix(compat.form(c_form))
        self._Kmat = compat.assemble_matrix(compat.form(k_form))
        self._A = compat.assemble_matrix(self._a, self.bcs)
        self._init_vectors(compat.form(f_form), self._a)
        self._make_solver(self._A)

    def radiation_heat_flow(self, tag: str) -> float:
        """Radiative heat flow into the body through ``tag`` over the last step (W), as the
        step applied it (evaluated at its T_n; collective)."""
        self._setup()
        return self.integral(("radiation", tag), lambda: self.boundary.radiation_flux(
            tag, self.T_old) * self._ds(self.structure.tags[tag]))

    def check_radiation_step(self) -> None:
        """Refuse a step with dt lambda_rad > 1 (module docstring; collective)."""
        if self.radiation:
            self.boundary.check_radiation_step(self.dt, self.min_max()[1], self.material,
                                               self.comm)

    def stable_dt(self) -> float:
        """Largest stable step (s) of the theta-scheme for theta < 1/2 (inf for theta >=
        1/2): 2/((1 - 2 theta) lambda), lambda the element bound of the module docstring
        (P1 cells, convection included; collective)."""
        return np.inf if self.theta >= 0.5 else stable_dt(self.theta, self.eigenvalue_bound())

    def eigenvalue_bound(self) -> float:
        """Upper bound (1/s) of the largest eigenvalue of C^-1 K (module docstring; P1
        simplices; collective)."""
        if compat.geometry_dofmap(self.mesh).shape[1] != self.mesh.topology.dim + 1:
            raise GsiInputError(f"{self.theta_key} = {self.theta!r}: the explicit stability "
                                "bound needs straight P1 simplices (this mesh has curved cells)")
        local = eigenvalue_bound(self.mesh, self.structure, self.material, self.boundary.h)
        return self.comm.allreduce(local, op=MPI.MAX)

    def check_stability(self) -> None:
        """Refuse (GsiInputError naming ``theta_key``) a theta < 1/2 step above
        :meth:`stable_dt` (collective; nothing to check for theta >= 1/2)."""
        if self.theta < 0.5:
            check_explicit_step(self.dt, self.theta, self.stable_dt(), self.theta_key)

    def step(self):
        """Advance one step dt; returns the temperature Function."""
        if self.contact_system is not None:
            raise RuntimeError("Heat.step: this body is in a contact group; step the group "
                               "(ContactHeatSystem.step)")
        b = self.begin_step()
        self._solver.solve(b, compat.petsc_vec(self.T))
        self.end_step()
        return self.T

    def begin_step(self) -> PETSc.Vec:
        """The right-hand side of the step from T_n, (C/dt - (1 - theta) K) T_n + F with
        the Dirichlet values set (a vector owned by this object, valid until the next
        call); T_old takes T_n. :meth:`step` is ``begin_step``, a solve with
        :meth:`system_matrix` into T, :meth:`end_step`."""
        self._setup()
        theta, dt = self.theta, self.dt
        Tn = compat.petsc_vec(self.T)
        self.T_old.x.array[:] = self.T.x.array
        self.check_radiation_step()
        self._assemble_load(self._F)
        b, tmp = self._b, self._tmp
        self._F.copy(b)
        self._C.mult(Tn, tmp)
        b.axpy(1.0 / dt, tmp)
        if theta < 1.0:
            self._Kmat.mult(Tn, tmp)
            b.axpy(-(1.0 - theta), tmp)
        b.axpy(1.0, self._lift)
        compat.set_bc(b, self.bcs)
        return b

    def end_step(self, T_new=None) -> None:
        """Finish the step: T takes ``T_new`` (owned dofs; default: T as solved in place),
        the ghosts are updated, t and the step count advance."""
        if T_new is not None:
            self.T.x.array[:len(T_new)] = T_new
        compat.scatter_forward(self.T)
        self.advance_time(self.dt)

    def system_matrix(self) -> PETSc.Mat:
        """The step matrix C/dt + theta K with the Dirichlet rows and columns replaced by
        the identity (assembled once)."""
        self._setup()
        return self._A

    def matrices(self) -> tuple[PETSc.Mat, PETSc.Mat]:
        """The capacity matrix C and the conduction + convection matrix K, without
        Dirichlet conditions (assembled once)."""
        self._setup()
        return self._C, self._Kmat

    def bc_dofs(self) -> np.ndarray:
        """Owned dofs with a fixed temperature (local indices)."""
        return self.dirichlet.dofs()

    def capacity_row_sums(self) -> np.ndarray:
        """Row sums of the capacity matrix C at the owned dofs, int rho c N_i dx (J/K)."""
        self._setup()
        ones, out = self._C.createVecRight(), self._C.createVecLeft()
        ones.set(1.0)
        self._C.mult(ones, out)
        return out.array.copy()

    def heat_capacity(self) -> float:
        """Heat capacity of the body, int rho c dx (J/K) (collective)."""
        m = self.material
        return m.rho * m.c * self.volume()

    # ------------------------------------------------------------------ state
    def _state_fields(self) -> dict:
        return {"T": self.T, "T_old": self.T_old}

    # ------------------------------------------------------------------ results
    def dirichlet_heat_flow(self, tag: str | None = None) -> float:
        """Heat flow into the body through the fixed-temperature dofs (W) over the last
        step: the residual C (T_{n+1} - T_n)/dt + K T_theta - F at those dofs (consistent
        with the discrete energy balance)."""
        self._setup()
        dofs = self.dirichlet.dofs(tag, key="structure.heat.dirichlet_heat_flow tag")
        theta, dt = self.theta, self.dt
        Tn1 = self.T.x.array.copy()
        dT = compat.function(self.V)
        dT.x.array[:] = (Tn1 - self.T_old.x.array) / dt
        tmp = self._tmp
        self._C.mult(compat.petsc_vec(dT), tmp)
        res = tmp.array.copy()
        dT.x.array[:] = theta * Tn1 + (1.0 - theta) * self.T_old.x.array
        self._Kmat.mult(compat.petsc_vec(dT), tmp)
        res += tmp.array
        self._assemble_load(self._F)
        res -= self._F.array
        res[:self.contact_heat.size] -= self.contact_heat
        return self.comm.allreduce(float(res[dofs].sum()), op=MPI.SUM)

    def heat_flow(self, tag: str) -> float:
        """Heat flow into the body through surface ``tag`` (W), from the boundary data:
        the Dirichlet residual (:meth:`dirichlet_heat_flow`) on fixed-temperature tags,
        int q + h (T_ambient - T) ds on the others (0 on insulated tags). Nodal heat loads
        are not included (see :meth:`nodal_heat`)."""
        self._setup()
        if tag in self.dirichlet.tags:
            return self.dirichlet_heat_flow(tag)
        self.structure.facet_tag(tag)
        return self.integral(("boundary flow", tag),
                             lambda: self.boundary.flow_form(tag, self.T, self._ds))

    def nodal_heat(self) -> float:
        """Total of the nodal heat loads currently applied (W)."""
        return self.comm.allreduce(float(self.nodal.values.sum()), op=MPI.SUM)

    def surface_heat_flow(self, tag: str) -> float:
        """Conductive heat flow into the body through surface ``tag``, int k grad T . n ds
        (W), from the gradient of the discrete field (first order on P1)."""
        self._setup()
        v = self.structure.tags[tag]
        return self.integral(("surface flow", tag), lambda: self._k * ufl.dot(
            ufl.grad(self.T), ufl.FacetNormal(self.mesh)) * self._ds(v))

    def stored_heat(self) -> float:
        """int rho c T dx (J) relative to T = 0."""
        self._setup()
        m = self.material
        return self.integral("stored heat", lambda: compat.constant(
            self.mesh, m.rho * m.c) * self.T * compat.measure("dx", self.mesh))

    def min_max(self) -> tuple[float, float]:
        """(min, max) of the nodal temperatures over all ranks."""
        n = compat.dof_index_map(self.V)[0].size_local
        Tl = self.T.x.array[:n]
        lo = float(Tl.min()) if n else np.inf
        hi = float(Tl.max()) if n else -np.inf
        return self.comm.allreduce(lo, op=MPI.MIN), self.comm.allreduce(hi, op=MPI.MAX)
