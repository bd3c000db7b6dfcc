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
import scipy.constants
import ufl
from mpi4py import MPI
from petsc4py import PETSc

from gsi.errors import GsiInputError

from . import compat
from .heat_bounds import eigenvalue_bound, facet_factor
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
    factorization : {"lu", "cholesky"}
        MUMPS factorization (direct solver).
    solver : {"auto", "direct", "out_of_core", "iterative"}
        Linear solver: MUMPS factorized once, the same with the factor on disk (MUMPS
        Cholesky, any number of ranks), CG + algebraic multigrid built once with a warm
        start, or by size ("auto": iterative from
        ``gsi.fem.options.AUTO_LARGE_DOFS["heat"]`` dofs on).
    petsc_options : dict, optional
        PETSc options without the leading dash, under this problem's own prefix.
    rtol : float, optional
        Iterative solver: the residual falls to rtol times that of the warm start (default
        ``gsi.fem.options.ITERATIVE_RTOL``; ``ksp_rtol`` in ``petsc_options`` overrides it).
    options_key : str
        TOML key of ``petsc_options`` named by errors.
    theta_key : str
        Key named by the stability error (e.g. ``structures[0].thermal.theta``).

    Notes
    -----
    Under MPI every method is collective except ``set_*``/``add_nodal_heat``.
    """

    kind = "heat"

    def __init__(self, structure, material, *, dt: float, theta: float = 1.0,
                 T_initial: float = 0.0, degree: int = 1, factorization: str = "lu",
                 solver: str = "auto", petsc_options: dict | None = None,
                 options_key: str = "structure.petsc", rtol: float | None = None,
                 theta_key: str = "structure.heat.theta"):
        if not (dt is not None and np.isfinite(dt) and dt > 0):
            raise GsiInputError(f"structure.heat.dt = {dt!r}: must be > 0 (s)")
        if not 0.0 <= theta <= 1.0:
            raise GsiInputError(f"{theta_key} = {theta!r}: must be in [0, 1]")
        if degree not in (1, 2):
            raise GsiInputError(f"structure.heat.degree = {degree!r}: must be 1 or 2")
        if theta < 0.5 and degree != 1:
            raise GsiInputError(f"{theta_key} = {theta!r}: below 0.5 (explicit) needs degree 1 "
                                f"(its stability bound is for P1); use degree = 1 or theta >= 0.5")
        self.theta_key = theta_key
        self._init_problem(structure, material, factorization=factorization, solver=solver,
                           petsc_options=petsc_options, options_key=options_key, rtol=rtol)
        mesh = self.mesh
        self.dt, self.theta, self.degree = float(dt), float(theta), degree
        self.V = compat.scalar_space(mesh, degree)
        self.T = compat.function(self.V, "temperature")
        self.T.x.array[:] = float(T_initial)
        self.T_old = compat.function(self.V, "temperature_old")
        names = [n for n in structure.tags if n != "volume"]
        self.h = {n: 0.0 for n in names}
        self.T_amb = {n: compat.constant(mesh, 0.0) for n in names}
        self.q = {n: compat.constant(mesh, 0.0) for n in names}
        self.radiation = {}          # tag -> (emissivity, T_ambient Constant)
        self.source = compat.constant(mesh, 0.0)
        self._init_loads()
        self.bcs = []
        self._bc_dofs_by_tag: dict[str, np.ndarray] = {}
        #: the :class:`gsi.fem.contact_heat.ContactHeatSystem` that steps this body (None:
        #: it steps alone)
        self.contact_system = None
        #: heat (W) the FE-FE contacts put into each owned dof over the last step
        #: (theta-weighted; set by the contact system, zero otherwise)
        self.contact_heat = np.zeros(compat.dof_index_map(self.V)[0].size_local)

    # ------------------------------------------------------------------ set-up API
    def _check_not_set_up(self, what):
        if self.is_set_up:
            raise GsiInputError(f"structure.heat.{what}: must be set before the first step "
                                "(the matrix is factorized once)")

    def fix_temperature(self, tag: str, T: float) -> None:
        """Dirichlet: temperature ``T`` on surface ``tag`` (K or degC)."""
        self._check_not_set_up("fixed_temperature")
        tv = self.structure.facet_tag(tag)
        facets = compat.meshtag_find(self.structure.facet_tags, tv)
        dofs = compat.locate_dofs_topological(self.V, self.mesh.topology.dim - 1, facets)
        bc = compat.dirichletbc(PETSc.ScalarType(T), dofs, self.V)
        self.bcs.append(bc)
        self._bc_dofs_by_tag[tag] = compat.bc_dofs_owned(bc)

    def set_convection(self, tag: str, h: float, T_ambient: float) -> None:
        """Convection on ``tag``: flux out h (T - T_ambient); h in W/(m^2 K).

        h is fixed at the first step; T_ambient may change later."""
        self.structure.facet_tag(tag)
        if not (np.isfinite(h) and h >= 0):
            raise GsiInputError(f"structure.heat.convection.{tag}.h = {h!r}: must be >= 0 (W/(m^2 K))")
        if self.is_set_up and h != self.h[tag]:
            self._check_not_set_up(f"convection.{tag}.h")
        self.h[tag] = float(h)
        self.T_amb[tag].value = float(T_ambient)

    def set_flux(self, tag: str, q: float) -> None:
        """Prescribed heat flux into the body through ``tag`` (W/m^2); may change every step."""
        self.structure.facet_tag(tag)
        self.q[tag].value = float(q)

    def set_radiation(self, tag: str, emissivity: float, T_ambient: float) -> None:
        """Radiation out through ``tag``: flux eps sigma (T^4 - T_ambient^4) (W/m^2), T in K,
        explicit in T (module docstring). The emissivity is fixed at the first step;
        T_ambient may change later."""
        self.structure.facet_tag(tag)
        if not (np.isfinite(emissivity) and 0.0 < emissivity <= 1.0):
            raise GsiInputError(f"structure.heat.radiation.{tag}.emissivity = {emissivity!r}: "
                                "must be in (0, 1]")
        if not (np.isfinite(T_ambient) and T_ambient >= 0.0):
            raise GsiInputError(f"structure.heat.radiation.{tag}.T_ambient = {T_ambient!r}: "
                                "must be >= 0 (K)")
        if tag in self.radiation:
            if self.is_set_up and emissivity != self.radiation[tag][0]:
                self._check_not_set_up(f"radiation.{tag}.emissivity")
            self.radiation[tag][1].value = float(T_ambient)
            return
        self._check_not_set_up(f"radiation.{tag}")
        self.radiation[tag] = (float(emissivity), compat.constant(self.mesh, float(T_ambient)))

    def set_source(self, s: float) -> None:
        """Uniform volumetric heat source (W/m^3)."""
        self.source.value = float(s)

    def add_nodal_heat(self, global_ids, Q) -> None:
        """Add heat loads ``Q`` (n,) (W, into the body) at global vertex ids (n,)."""
        self.nodal.add(global_ids, Q)

    def clear_nodal_heat(self) -> None:
        self.nodal.clear()

    @property
    def fixed_tags(self) -> tuple[str, ...]:
        """Tags with a fixed temperature (:meth:`fix_temperature`)."""
        return tuple(self._bc_dofs_by_tag)

    def exchange_tags(self) -> list[str]:
        """Tags through which heat can cross the boundary: convection (h > 0), a nonzero
        prescribed flux, or a fixed temperature (the others are insulated)."""
        return [n for n in self.h if self.h[n] > 0.0 or self.q[n].value != 0.0
                or n in self._bc_dofs_by_tag or n in self.radiation]

    def volume(self) -> float:
        """Volume of the body (m^3) (collective; computed once)."""
        if getattr(self, "_volume", None) is None:
            self._volume = compat.assemble_scalar(
                compat.form(compat.constant(self.mesh, 1.0) * compat.measure("dx", self.mesh)),
                self.comm)
        return self._volume

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
        tags = self.structure.tags
        self._ds = ds
        c_form = rho_c * T * w * dx
        k_form = k * ufl.inner(ufl.grad(T), ufl.grad(w)) * dx
        for n, h in self.h.items():
            if h > 0.0:
                k_form += compat.constant(self.mesh, h) * T * w * ds(tags[n])
        f_form = self.source * w * dx
        for n in self.h:
            f_form += self.q[n] * w * ds(tags[n])
            if self.h[n] > 0.0:
                f_form += compat.constant(self.mesh, self.h[n]) * self.T_amb[n] * w * ds(tags[n])
        for n, (eps, T_amb) in self.radiation.items():
            f_form += self._radiation_flux(n) * w * ds(tags[n])
        theta, dt = self.theta, self.dt
        self.check_stability()
        a_form = (1.0 / dt) * c_form if theta == 0.0 else (1.0 / dt) * c_form + theta * k_form
        self._a = compat.form(a_form)
        self._C = compat.assemble_matrix(compat.form(c_form))
        self._Kmat = compat.assemble_matrix(compat.form(k_form))
        self._f = compat.form(f_form)
        self._A = compat.assemble_matrix(self._a, self.bcs)
        self._b = compat.create_vector(self._f)
        self._F = self._b.duplicate()
        self._tmp = self._b.duplicate()
        self._lift = compat.create_vector(self._f)
        with self._lift.localForm() as loc:
            loc.set(0.0)
        compat.apply_lifting_and_accumulate(self._lift, self._a, self.bcs)
        self._make_solver(self._A)

    def _radiation_flux(self, tag):
        """eps sigma (T_amb^4 - T_n^4): the radiative flux into the body over the step
        (UFL; T_n is T_old, which begin_step sets before assembling)."""
        eps, T_amb = self.radiation[tag]
        es = compat.constant(self.mesh, eps * scipy.constants.Stefan_Boltzmann)
        return es * (T_amb ** 4 - self.T_old ** 4)

    def radiation_heat_flow(self, tag: str) -> float:
        """Radiative heat flow into the body through ``tag`` over the last step (W), as the
        step applied it (evaluated at its T_n; collective)."""
        self._setup()
        if not hasattr(self, "_rad_forms"):
            self._rad_forms = {}
        if tag not in self._rad_forms:
            self._rad_forms[tag] = compat.form(
                self._radiation_flux(tag) * self._ds(self.structure.tags[tag]))
        return compat.assemble_scalar(self._rad_forms[tag], self.comm)

    def check_radiation_step(self) -> None:
        """Refuse a step with dt lambda_rad > 1 (module docstring; collective)."""
        if not self.radiation:
            return
        if not hasattr(self, "_rad_factor"):
            self._rad_factor = {n: self.comm.allreduce(facet_factor(
                self.mesh, self.structure, n, self.material), op=MPI.MAX)
                                for n in self.radiation}
        T_max = max(self.min_max()[1], max(T.value for _, T in self.radiation.values()))
        for n, (eps, _) in self.radiation.items():
            lam = 4.0 * eps * scipy.constants.Stefan_Boltzmann * T_max ** 3 * self._rad_factor[n]
            if self.dt * lam > 1.0:
                raise GsiInputError(
                    f"structure.heat.radiation.{n}: the step dt = {self.dt:.4g} s is above the "
                    f"explicit radiation limit 1/lambda = {1.0 / lam:.4g} s at T_max = "
                    f"{T_max:.4g} K; lower dt (structures[].contact.n_sub)")

    def stable_dt(self) -> float:
        """Largest stable step (s) of the theta-scheme for theta < 1/2 (inf for theta >=
        1/2): 2/((1 - 2 theta) lambda), lambda the element bound of the module docstring
        (P1 cells, convection included; collective)."""
        if self.theta >= 0.5:
            return np.inf
        lam = self.eigenvalue_bound()
        return 2.0 / ((1.0 - 2.0 * self.theta) * lam) if lam > 0 else np.inf

    def eigenvalue_bound(self) -> float:
        """Upper bound (1/s) of the largest eigenvalue of C^-1 K (module docstring; P1
        simplices; collective)."""
        if compat.geometry_dofmap(self.mesh).shape[1] != self.mesh.topology.dim + 1:
            raise GsiInputError(f"{self.theta_key} = {self.theta!r}: the explicit stability "
                                "bound needs straight P1 simplices (this mesh has curved cells)")
        local = eigenvalue_bound(self.mesh, self.structure, self.material, self.h)
        return self.comm.allreduce(local, op=MPI.MAX)

    def check_stability(self) -> None:
        """Refuse (GsiInputError naming ``theta_key``) a theta < 1/2 step above
        :meth:`stable_dt` (collective; nothing to check for theta >= 1/2)."""
        if self.theta >= 0.5:
            return
        limit = self.stable_dt()
        if self.dt > limit:
            raise GsiInputError(
                f"{self.theta_key} = {self.theta:g}: the step dt = {self.dt:.4g} s is above the "
                f"explicit stability limit {limit:.4g} s (2/((1 - 2 theta) lambda_max), P1 "
                f"element bound); lower dt or use theta >= 0.5")

    def _assemble_load(self, out):
        compat.assemble_vector_ghosted(out, self._f)
        out.array[:] += self.nodal.values

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

    def bc_dofs(self) -> np.ndarray:
        """Owned dofs with a fixed temperature (local indices)."""
        return np.unique(np.concatenate([np.zeros(0, np.int32)]
                                        + list(self._bc_dofs_by_tag.values()))).astype(np.int64)

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
        if tag is None:
            dofs = np.unique(np.concatenate([np.zeros(0, np.int64)] + list(self._bc_dofs_by_tag.values())))
        else:
            dofs = self._bc_dofs_by_tag[tag]
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
        if tag in self._bc_dofs_by_tag:
            return self.dirichlet_heat_flow(tag)
        self.structure.facet_tag(tag)
        if not hasattr(self, "_bflux_forms"):
            self._bflux_forms = {}
        if tag not in self._bflux_forms:
            ds = self._ds(self.structure.tags[tag])
            expr = self.q[tag] * ds
            if self.h[tag] > 0.0:
                expr += compat.constant(self.mesh, self.h[tag]) * (self.T_amb[tag] - self.T) * ds
            self._bflux_forms[tag] = compat.form(expr)
        return compat.assemble_scalar(self._bflux_forms[tag], self.comm)

    def nodal_heat(self) -> float:
        """Total of the nodal heat loads currently applied (W)."""
        return self.comm.allreduce(float(self.nodal.values.sum()), op=MPI.SUM)

    def surface_heat_flow(self, tag: str) -> float:
        """Conductive heat flow into the body through surface ``tag``, int k grad T . n ds
        (W), from the gradient of the discrete field (first order on P1)."""
        self._setup()
        if not hasattr(self, "_flux_forms"):
            n = ufl.FacetNormal(self.mesh)
            self._flux_forms = {
                name: compat.form(self._k * ufl.dot(ufl.grad(self.T), n) * self._ds(v))
                for name, v in self.structure.tags.items() if name != "volume"}
        return compat.assemble_scalar(self._flux_forms[tag], self.comm)

    def stored_heat(self) -> float:
        """int rho c T dx (J) relative to T = 0."""
        self._setup()
        if not hasattr(self, "_energy_form"):
            m = self.material
            self._energy_form = compat.form(
                compat.constant(self.mesh, m.rho * m.c) * self.T * compat.measure("dx", self.mesh))
        return compat.assemble_scalar(self._energy_form, self.comm)

    def min_max(self) -> tuple[float, float]:
        """(min, max) of the nodal temperatures over all ranks."""
        n = compat.dof_index_map(self.V)[0].size_local
        Tl = self.T.x.array[:n]
        lo = float(Tl.min()) if n else np.inf
        hi = float(Tl.max()) if n else -np.inf
        return self.comm.allreduce(lo, op=MPI.MIN), self.comm.allreduce(hi, op=MPI.MAX)
