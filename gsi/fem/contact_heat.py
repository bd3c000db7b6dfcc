r"""Heat across the contact of two meshed bodies (the FDEM contact-heat model).

Joulin, Xiang, Latham et al., "Capturing heat transfer for complex-shaped multibody
contact problems, a new FDEM approach", Comp. Part. Mech. 7 (2020), section 3 (eqs.
24-30). Two :class:`gsi.fem.heat.Heat` bodies A and B whose boundary meshes overlap
slightly (a penetration p) exchange heat through the overlap,

.. math::
    q^c = \Delta T_c / R_c \qquad (R_c \text{ in m}^2\,\text{K/W}).

Contact surface (the paper's "Contact surface area")
----------------------------------------------------
A contact k is a couple of tetrahedra (alpha of A, beta of B). Every boundary facet of A
on its contact tags is intersected with every cell of B (the facet triangle clipped by
the four half-spaces of the tetrahedron, Sutherland-Hodgman): the polygon area is the
target surface S_tar^k of the couple (owner cell of the facet, beta); the same with the
roles swapped gives S_con^k. Then

.. math::
    S_c^k = \tfrac12 (S_{tar}^k + S_{con}^k).           \qquad \text{(eq. 26)}

Summed over the couples, S_tar is the area of A's contact surface inside B and S_con that
of B's inside A, each exactly (the tetrahedra of B tile its volume, so no piece of a
facet is lost or counted twice): a flat overlap gives S_c = the overlapped area whatever
the meshes, a curved one the area of the faceted surfaces (O(h^2) from the true one).

Heat flow (eqs. 24-29)
----------------------
The *surface nodes* of a cell are its vertices on its body's contact tags (three for a
cell with a contact facet; a cell touching the surface by an edge or a vertex has two or
one; a cell with none, which only a deep overlap produces, takes its four vertices). With
``temperature = "local"`` (the paper's model)

.. math::
    Q^k = \frac{S_c^k}{R_c}\,(\bar T^k_{A} - \bar T^k_{B}), \qquad
    \bar T^k_{A} = \frac{1}{n_\alpha}\sum_{l \in \alpha} T_l

flows from A to B; each surface node of alpha gives Q^k/n_alpha and each of beta takes
Q^k/n_beta (with three nodes a side this is eq. 28, 1/(18 R_c) (S_tar + S_con) times
the sum of the six node temperature differences). In matrix form Q = D T over all the
contacts, D = [W_A, -W_B] (n_contacts x n_dofs, the rows of W the node weights 1/n), and
the contact heat into the nodes is -G T with the interaction matrix (eq. 30)

.. math::
    G = D^T \,\mathrm{diag}(S_c^k/R_c)\, D ,

symmetric positive semi-definite with G 1 = 0: the heat given by A is exactly the heat
taken by B (conservative to round-off, as the paper notes under "Algorithm limitations").

With ``temperature = "mean"`` (the variant of the paper's section 5, used against the
pipe-network model) Delta T_c is the difference of the bodies' volume-mean temperatures,
Q^k = S_c^k/R_c (mean T_A - mean T_B), split to the same surface nodes.

Time integration: one PETSc system (the choice)
-----------------------------------------------
The bodies' theta-steps (C/dt + theta K) T_n+1 = (C/dt - (1 - theta) K) T_n + F and the
contact term theta G T_n+1 + (1 - theta) G T_n are assembled into ONE sparse system over
the dofs of all bodies of a contact group and factorized once (MUMPS LU): the geometry is
fixed (bodies in heat contact do not move in gsi; the paper's validations are static
too), so G is constant. A staggered scheme (each body a step with the other's surface
temperature from the previous step) would add an explicit contact term whose stability
needs dt < C_node R_c / S_node: for the near-perfect contacts of the paper's validation
(tiny R_c) that is a step orders of magnitude below the bodies' own, and it would break
the exact balance within a step. The monolithic system keeps theta = 1 unconditionally
stable for any R_c and the exchanged heat equal and opposite in every step. Dirichlet
rows keep their identity row (the contact heat reaching a fixed-temperature node is
reported in its Dirichlet reaction, :meth:`gsi.fem.heat.Heat.dirichlet_heat_flow`).

The ``mean`` variant is a dense rank-one coupling; it is applied explicitly, from T_n
(the paper runs it with the explicit theta = 0), and refused when dt exceeds 1/lambda,
lambda = sum_k S_c^k/R_c (1/C_A + 1/C_B) the rate of the two means (C the bodies' heat
capacities), above which the explicit mean exchange overshoots.

theta < 1/2 (explicit bodies, the paper's forward difference) is refused above
dt = 2/((1 - 2 theta)(lambda_K + lambda_G)), lambda_K the bodies' element bound
(:meth:`gsi.fem.heat.Heat.eigenvalue_bound`) and lambda_G >= lambda_max(G, C) by
Gershgorin on D_c^-1/2 G D_c^-1/2, D_c = (row sums of C)/5 <= C (the smallest
eigenvalue of a P1 tetrahedron's capacity matrix rho c V/20 (I + 1 1^T) is rho c V/20).

Limits: one MPI rank (the contact group is assembled serially); P1 bodies; the
geometry is that of the meshes when the group is built.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.sparse
from petsc4py import PETSc

from gsi.errors import GsiInputError

from . import compat
from .solvers import FactorOnceSolver

__all__ = ["ThermalContact", "ContactHeatSystem", "triangle_tetra_area", "TEMPERATURES"]

TEMPERATURES = ("local", "mean")

#: tetrahedron faces (vertex indices) opposite vertices 0..3
_TET_FACES = ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))


def _clip(poly: np.ndarray, normal: np.ndarray, offset: float, tol: float) -> np.ndarray:
    """The part of the planar polygon ``poly`` (m, 3) with normal . x <= offset (+ tol)
    (Sutherland-Hodgman, one plane)."""
    if len(poly) == 0:
        return poly
    d = poly @ normal - offset
    inside = d <= tol
    if inside.all():
        return poly
    if not inside.any():
        return poly[:0]
    out = []
    m = len(poly)
    for i in range(m):
        p, q = poly[i], poly[(i + 1) % m]
        dp, dq = d[i], d[(i + 1) % m]
        if dp <= tol:
            out.append(p)
        if (dp <= tol) != (dq <= tol):
            out.append(p + (dp / (dp - dq)) * (q - p))
    return np.array(out)


def _polygon_area(poly: np.ndarray) -> float:
    """Area of a planar polygon (m, 3) (m^2)."""
    if len(poly) < 3:
        return 0.0
    e = poly[1:] - poly[0]
    return 0.5 * float(np.linalg.norm(np.cross(e[:-1], e[1:]).sum(axis=0)))


def triangle_tetra_area(tri: np.ndarray, tet: np.ndarray, *, tol: float = 0.0) -> float:
    """Area (m^2) of the part of triangle ``tri`` (3, 3) inside tetrahedron ``tet`` (4, 3):
    the intersection polygon of the paper's Fig. 3."""
    poly = np.asarray(tri, float)
    for skip, face in enumerate(_TET_FACES):
        a, b, c = tet[face[0]], tet[face[1]], tet[face[2]]
        n = np.cross(b - a, c - a)
        if n @ (tet[skip] - a) > 0.0:        # make n point away from the opposite vertex
            n = -n
        nn = np.linalg.norm(n)
        if nn == 0.0:
            return 0.0
        n = n / nn
        poly = _clip(poly, n, float(n @ a), tol)
        if len(poly) < 3:
            return 0.0
    return _polygon_area(poly)


class _Body:
    """Geometry of one body's contact side: facets, their owner cells, surface nodes."""

    def __init__(self, heat, tags, key):
        mesh = heat.mesh
        if heat.degree != 1:
            raise GsiInputError(f"{key}: FE-FE contact heat needs degree 1 (P1) bodies")
        self.heat = heat
        tdim = mesh.topology.dim
        fdim = tdim - 1
        st = heat.structure
        facets = []
        for t in tags:
            try:
                tv = st.facet_tag(t)
            except GsiInputError:
                raise GsiInputError(f"{key} = {t!r}: not a surface tag of the body; its tags: "
                                    f"{', '.join(n for n in st.tags if n != 'volume')}") from None
            facets.append(compat.meshtag_find(st.facet_tags, tv))
        facets = np.unique(np.concatenate(facets)) if facets else np.zeros(0, np.int32)
        if facets.size == 0:
            raise GsiInputError(f"{key} = {list(tags)}: no facets carry these tags")
        mesh.topology.create_connectivity(fdim, tdim)
        f2c = mesh.topology.connectivity(fdim, tdim)
        self.x = compat.geometry_x(mesh)
        self.cells = compat.geometry_dofmap(mesh)[:, :4]
        self.facet_nodes = compat.entities_to_geometry(mesh, fdim, facets)
        self.facet_owner = np.array([f2c.links(f)[0] for f in facets], np.int64)
        on_surface = np.zeros(self.x.shape[0], bool)
        on_surface[self.facet_nodes.ravel()] = True
        self.on_surface = on_surface
        self.node_dof = heat.vmap.node_dof
        X = self.x[self.cells]
        self.cell_lo, self.cell_hi = X.min(axis=1), X.max(axis=1)
        self.scale = float(np.ptp(self.x, axis=0).max())

    def surface_weights(self, cell):
        """(dofs, weights) of the surface nodes of ``cell`` (module docstring)."""
        nodes = self.cells[cell]
        s = nodes[self.on_surface[nodes]]
        if s.size == 0:
            s = nodes
        return self.node_dof[s], np.full(s.size, 1.0 / s.size)


def _facet_cell_areas(a: _Body, b: _Body, tol: float):
    """{(owner cell of the facet of a, cell of b): area of the facet inside the cell}."""
    out = {}
    for f, nodes in enumerate(a.facet_nodes):
        tri = a.x[nodes]
        lo, hi = tri.min(axis=0) - tol, tri.max(axis=0) + tol
        cand = np.flatnonzero(np.all(b.cell_hi >= lo, axis=1) & np.all(b.cell_lo <= hi, axis=1))
        for c in cand:
            s = triangle_tetra_area(tri, b.x[b.cells[c]], tol=tol)
            if s > 0.0:
                key = (int(a.facet_owner[f]), int(c))
                out[key] = out.get(key, 0.0) + s
    return out


class ThermalContact:
    """The contact of body ``a`` and body ``b`` (see the module docstring).

    Parameters
    ----------
    heat_a, heat_b : gsi.fem.heat.Heat
        The two bodies (P1, one MPI rank), in their contact position.
    tags_a, tags_b : sequence of str
        Surface tags of each body where they touch (the facets searched for overlap).
    R_c : float
        Contact resistance (m^2 K/W), > 0.
    temperature : {"local", "mean"}
        Delta T_c from the couples' surface nodes (the paper's model) or from the bodies'
        mean temperatures (its section 5 variant).
    key : str
        Key path named by errors (e.g. ``thermal_contacts[0]``).

    Attributes
    ----------
    S_tar, S_con, area : float
        A's contact surface inside B, B's inside A, and S_c = (S_tar + S_con)/2 (m^2).
    conductance : ndarray (n_contacts,)
        S_c^k / R_c of each couple (W/K).
    """

    def __init__(self, heat_a, heat_b, *, tags_a, tags_b, R_c: float,
                 temperature: str = "local", key: str = "thermal_contact"):
        if not (isinstance(R_c, (int, float)) and math.isfinite(R_c) and R_c > 0):
            raise GsiInputError(f"{key}.R_c = {R_c!r}: must be > 0 (m^2 K/W)")
        if temperature not in TEMPERATURES:
            raise GsiInputError(f"{key}.temperature = {temperature!r}: must be one of "
                                f"{', '.join(repr(t) for t in TEMPERATURES)}")
        if heat_a is heat_b:
            raise GsiInputError(f"{key}.structures: a body cannot touch itself; name two bodies")
        for h in (heat_a, heat_b):
            if h.comm.size != 1:
                raise GsiInputError(f"{key}: FE-FE contact heat runs on one MPI rank (the "
                                    "contact group is assembled serially); run without mpirun")
        tags_a = (tags_a,) if isinstance(tags_a, str) else tuple(tags_a)
        tags_b = (tags_b,) if isinstance(tags_b, str) else tuple(tags_b)
        self.key = key
        self.heat_a, self.heat_b = heat_a, heat_b
        self.R_c = float(R_c)
        self.temperature = temperature
        a = _Body(heat_a, tags_a, f"{key}.tags[0]")
        b = _Body(heat_b, tags_b, f"{key}.tags[1]")
        tol = 1e-12 * max(a.scale, b.scale)
        tar = _facet_cell_areas(a, b, tol)                   # (alpha, beta) -> S_tar
        con = {(al, be): s for (be, al), s in _facet_cell_areas(b, a, tol).items()}
        couples = sorted(set(tar) | set(con))
        if not couples:
            raise GsiInputError(f"{key}: the surfaces {list(tags_a)} and {list(tags_b)} do not "
                                "overlap; place the bodies so that their meshes penetrate "
                                "slightly (structures[].translate)")
        self.couples = np.array(couples, np.int64)
        self.s_tar = np.array([tar.get(c, 0.0) for c in couples])
        self.s_con = np.array([con.get(c, 0.0) for c in couples])
        self.S_tar, self.S_con = float(self.s_tar.sum()), float(self.s_con.sum())
        self.area = 0.5 * (self.S_tar + self.S_con)
        self.conductance = 0.5 * (self.s_tar + self.s_con) / self.R_c
        n_a, n_b = _n_dofs(heat_a), _n_dofs(heat_b)
        self.W_a = self._weights(a, self.couples[:, 0], n_a)
        self.W_b = self._weights(b, self.couples[:, 1], n_b)

    @staticmethod
    def _weights(body, cells, n):
        rows, cols, vals = [], [], []
        for k, c in enumerate(cells):
            dofs, w = body.surface_weights(c)
            rows += [k] * len(dofs)
            cols += dofs.tolist()
            vals += w.tolist()
        return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(len(cells), n))

    @property
    def total_conductance(self) -> float:
        """sum_k S_c^k / R_c = S_c / R_c (W/K)."""
        return float(self.conductance.sum())

    def delta_T(self) -> np.ndarray:
        """Delta T_c of each couple at the current temperatures (K)."""
        Ta, Tb = _T(self.heat_a), _T(self.heat_b)
        if self.temperature == "mean":
            return np.full(len(self.conductance),
                           self.heat_a.mean_temperature() - self.heat_b.mean_temperature())
        return self.W_a @ Ta - self.W_b @ Tb

    def heat_flow(self) -> float:
        """Heat flowing from A into B at the current temperatures (W)."""
        return float(self.conductance @ self.delta_T())


def _n_dofs(heat) -> int:
    return compat.dof_index_map(heat.V)[0].size_local


def _T(heat) -> np.ndarray:
    return heat.T.x.array[:_n_dofs(heat)]


class ContactHeatSystem:
    """Bodies joined by :class:`ThermalContact` s, stepped as one PETSc system.

    Parameters
    ----------
    contacts : sequence of ThermalContact
        The contacts; the group is every body they name (same dt and theta, P1, one rank).
    key : str
        Key path named by errors.

    Notes
    -----
    :meth:`step` replaces the bodies' own :meth:`gsi.fem.heat.Heat.step` (each body
    refuses to step alone once in a group). After a step, each body's ``contact_heat``
    holds the theta-weighted heat (W) the contacts put into each of its dofs over it.
    """

    def __init__(self, contacts, *, key: str = "thermal_contacts"):
        contacts = list(contacts)
        if not contacts:
            raise GsiInputError(f"{key}: no contact")
        bodies = []
        for c in contacts:
            for h in (c.heat_a, c.heat_b):
                if not any(h is b for b in bodies):
                    bodies.append(h)
        h0 = bodies[0]
        for h in bodies[1:]:
            if not math.isclose(h.dt, h0.dt, rel_tol=1e-12) or h.theta != h0.theta:
                raise GsiInputError(
                    f"{key}: bodies in heat contact step together; they need the same FE step "
                    f"and theta (dt {h0.dt:g} vs {h.dt:g} s, theta {h0.theta:g} vs "
                    f"{h.theta:g}); give their structures the same contact.n_sub and "
                    "thermal.theta")
        for h in bodies:
            if h.contact_system is not None:
                raise GsiInputError(f"{key}: a body is already in another contact group")
        self.key = key
        self.contacts = contacts
        self.bodies = bodies
        self.dt, self.theta = h0.dt, h0.theta
        self._offsets = np.cumsum([0] + [_n_dofs(h) for h in bodies])
        n = int(self._offsets[-1])
        self.n_dofs = n
        local, mean = scipy.sparse.csr_matrix((n, n)), []
        for c in contacts:
            D = self._embed(c)
            if c.temperature == "local":
                local = local + D.T @ scipy.sparse.diags(c.conductance) @ D
            else:
                mean.append((c, D))
        self.G = local.tocsr()
        self._mean = mean
        self._solver = None
        for h in bodies:
            h.contact_system = self

    def _embed(self, c) -> scipy.sparse.csr_matrix:
        """D = [.., W_a, .., -W_b, ..] of contact ``c`` over the group's dofs."""
        ia = next(i for i, h in enumerate(self.bodies) if h is c.heat_a)
        ib = next(i for i, h in enumerate(self.bodies) if h is c.heat_b)
        blocks = [None] * len(self.bodies)
        for i, h in enumerate(self.bodies):
            blocks[i] = scipy.sparse.csr_matrix((len(c.conductance), _n_dofs(h)))
        blocks[ia] = c.W_a
        blocks[ib] = -c.W_b
        return scipy.sparse.hstack(blocks).tocsr()

    # ------------------------------------------------------------------ set-up
    def _bc_mask(self) -> np.ndarray:
        mask = np.zeros(self.n_dofs, bool)
        for i, h in enumerate(self.bodies):
            mask[self._offsets[i] + h.bc_dofs()] = True
        return mask

    def eigenvalue_bound(self) -> float:
        """Upper bound of lambda_max((K + G), C) over the group (1/s) (module docstring)."""
        lam_K = max(h.eigenvalue_bound() for h in self.bodies)
        d = np.concatenate([h.capacity_row_sums() for h in self.bodies]) / 5.0
        s = 1.0 / np.sqrt(d)
        Gs = scipy.sparse.diags(s) @ abs(self.G) @ scipy.sparse.diags(s)
        lam_G = float(np.asarray(Gs.sum(axis=1)).max()) if self.G.nnz else 0.0
        return lam_K + lam_G

    def mean_rate(self) -> float:
        """Rate of the explicit mean exchange, sum over ``mean`` contacts of
        S_c/R_c (1/C_A + 1/C_B) (1/s)."""
        lam = 0.0
        for c, _ in self._mean:
            lam += c.total_conductance * sum(1.0 / h.heat_capacity()
                                             for h in (c.heat_a, c.heat_b))
        return lam

    def check_stability(self) -> None:
        """Refuse a step above the explicit limits of the module docstring."""
        if self.theta < 0.5:
            lam = self.eigenvalue_bound()
            limit = 2.0 / ((1.0 - 2.0 * self.theta) * lam)
            if self.dt > limit:
                raise GsiInputError(
                    f"{self.key}: theta = {self.theta:g} with the contact: the step dt = "
                    f"{self.dt:.4g} s is above the explicit stability limit {limit:.4g} s of "
                    "the bodies and their contact; lower dt, raise R_c or use theta >= 0.5")
        lam = self.mean_rate()
        if lam > 0 and self.dt * lam > 1.0:
            raise GsiInputError(
                f"{self.key}: temperature = 'mean' is applied explicitly; the step dt = "
                f"{self.dt:.4g} s is above 1/rate = {1.0 / lam:.4g} s of the mean exchange; "
                "lower dt, raise R_c or use temperature = 'local'")

    def _setup(self) -> None:
        if self._solver is not None:
            return
        blocks = []
        for h in self.bodies:
            A = h.system_matrix()
            indptr, indices, data = A.getValuesCSR()
            blocks.append(scipy.sparse.csr_matrix((data, indices, indptr), shape=A.getSize()))
        M = scipy.sparse.block_diag(blocks, format="csr")
        self._bc = self._bc_mask()
        free = scipy.sparse.diags((~self._bc).astype(float))
        if self.theta > 0.0:
            M = M + self.theta * (free @ self.G)
        M = M.tocsr()
        M.sort_indices()
        self._free = free
        self.check_stability()
        self._A = PETSc.Mat().createAIJ(size=M.shape, csr=(M.indptr.astype(PETSc.IntType),
                                                          M.indices.astype(PETSc.IntType),
                                                          M.data), comm=PETSc.COMM_SELF)
        self._A.assemble()
        self._x = self._A.createVecRight()
        self._b = self._A.createVecLeft()
        self._solver = FactorOnceSolver(self._A, self.bodies[0].comm)
        self._solver.factorize()

    # ------------------------------------------------------------------ stepping
    def temperatures(self) -> np.ndarray:
        """The group's dof temperatures, body after body (K)."""
        return np.concatenate([_T(h) for h in self.bodies])

    def step(self) -> None:
        """Advance every body one step dt together (contacts implicit with the bodies'
        theta, ``mean`` contacts explicit)."""
        self._setup()
        Tn = self.temperatures()
        b = np.concatenate([h.begin_step().array for h in self.bodies])
        q_old = -(self.G @ Tn)                       # contact heat into the dofs at T_n
        q_mean = np.zeros(self.n_dofs)
        for c, D in self._mean:
            dT = c.heat_a.mean_temperature() - c.heat_b.mean_temperature()
            q_mean -= D.T @ (c.conductance * dT)
        b += (~self._bc) * ((1.0 - self.theta) * q_old + q_mean)
        self._b.array[:] = b
        self._solver.solve(self._b, self._x)
        T1 = self._x.array.copy()
        q = self.theta * -(self.G @ T1) + (1.0 - self.theta) * q_old + q_mean
        for i, h in enumerate(self.bodies):
            sl = slice(self._offsets[i], self._offsets[i + 1])
            h.contact_heat[:] = q[sl]
            h.end_step(T1[sl])

    def heat_flows(self) -> list[float]:
        """Heat flow A -> B of each contact at the current temperatures (W)."""
        return [c.heat_flow() for c in self.contacts]
