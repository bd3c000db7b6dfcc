"""Walls of the DEM: infinite planes and triangle meshes.

Both kinds call the simulation's single contact law; only the geometry differs.

Plane (:class:`PlaneWall`): a point and the unit normal pointing INTO the domain (where
the particles are); optional translation velocity (m/s); scalar temperature (K or
degC, as the particles) or None (adiabatic).

Mesh (:class:`MeshWall`): vertices (nv, 3) and triangles (nt, 3).  A particle touches a
triangle at its closest point (face, edge or vertex region).  Duplicate contacts on one
smooth surface are removed per particle and wall: face contacts first; an edge or
vertex contact is dropped when a face contact of a triangle containing that edge or
vertex exists, or when the same edge/vertex (or the same point) already gave one.

Motion: ``set_motion(velocity, omega, centre)`` makes a wall rigid: every step its
vertices translate by velocity dt and rotate exactly by omega dt about the centre,
and their velocity is v = velocity + omega x (x - centre).  ``set_vertices(x, v)``
replaces positions and velocities (the coupling calls it every FE step); between
calls the vertices move on with their velocities (x += v dt), so the DEM sees the wall
move with the FE velocity.  The wall velocity at the contact point (barycentric mean
of the vertex velocities) enters the relative velocity.

Outputs after each step (the force BY the particles ON the wall):
``force`` (3,) N, ``torque`` (3,) N m about ``centre`` (mesh; default origin) or the
plane's point; mesh walls also ``triangle_force`` (nt, 3).  Accumulators (summed
until ``reset_accumulators()``): ``vertex_impulse`` (nv, 3) N s = sum of
-F_on_particle w_k dt, ``vertex_heat`` (nv,) J = sum of -Q_to_particle w_k dt,
``impulse_on_particles`` (3,) N s, ``heat_to_particles`` J.  Thus
vertex_impulse.sum(0) == -impulse_on_particles and vertex_heat.sum() ==
-heat_to_particles to round-off.
"""
import numpy as np

from gsi.errors import GsiInputError


def vec3(value, key):
    """``value`` as a (3,) float array, or a one-line GsiInputError naming ``key``."""
    a = np.asarray(value, float).reshape(-1)
    if a.shape != (3,) or not np.isfinite(a).all():
        raise GsiInputError(f"{key} = {value}: must be 3 finite numbers")
    return a


class PlaneWall:
    """An infinite plane wall (see module docstring).  Made by ``Simulation.add_plane``;
    its data are row ``index`` of the simulation's ``plane_state`` bundle."""

    def __init__(self, walls, index, material):
        self._walls = walls           # the registry holding the state bundle
        self._p = index
        self.material = material

    @property
    def index(self):
        """The plane's index among the simulation's planes."""
        return self._p

    @property
    def point(self):
        """A point of the plane (m), moves with the velocity."""
        return self._walls.plane_state.point[self._p].copy()

    @property
    def normal(self):
        """Unit normal into the domain."""
        return self._walls.plane_state.normal[self._p].copy()

    @property
    def velocity(self):
        return self._walls.plane_state.velocity[self._p].copy()

    def set_motion(self, velocity=(0.0, 0.0, 0.0)):
        """Translate the plane with ``velocity`` (m/s)."""
        self._walls.plane_state.velocity[self._p] = vec3(velocity, "plane.velocity")

    @property
    def temperature(self):
        """Wall temperature or None (adiabatic)."""
        return float(self._walls.plane_state.T[self._p]) if self._walls.plane_state.has_T[self._p] else None

    @temperature.setter
    def temperature(self, value):
        self._walls.plane_state.has_T[self._p] = value is not None
        self._walls.plane_state.T[self._p] = 0.0 if value is None else float(value)

    @property
    def force(self):
        """Force of the particles on the plane at the last step (N)."""
        return self._walls.plane_state.force[self._p].copy()

    @property
    def torque(self):
        """Torque of the particles on the plane about ``point`` at the last step (N m)."""
        return self._walls.plane_state.torque[self._p].copy()

    @property
    def impulse_on_particles(self):
        """Accumulated impulse of the plane on the particles (N s)."""
        return self._walls.plane_state.impulse[self._p].copy()

    @property
    def heat_to_particles(self):
        """Accumulated heat from the plane into the particles (J)."""
        return float(self._walls.plane_state.heat[self._p])

    @property
    def friction_heat(self):
        """Frictional heat the plane took since the start (J; never reset)."""
        return float(self._walls.plane_state.friction_heat[self._p])

    @property
    def work_on_particles(self):
        """Work of the moving plane on the particles since the start (J; never reset)."""
        return float(self._walls.plane_state.work[self._p])

    def reset_accumulators(self):
        self._walls.book_reset_heat(self._walls.plane_state.heat[self._p])
        self._walls.plane_state.impulse[self._p] = 0.0
        self._walls.plane_state.heat[self._p] = 0.0


class MeshWall:
    """A triangle-mesh wall (see module docstring).

    Parameters
    ----------
    vertices : array_like (nv, 3)
        Vertex positions (m).
    triangles : array_like (nt, 3)
        Vertex indices of each triangle.
    material : str
        Material name (a key of the simulation's materials).
    vertex_temperature : array_like (nv,), optional
        Vertex temperatures; None = adiabatic.
    parent_nodes, parent_coords : array_like (nt, 6) int and (nt, 3, 3), optional
        Quadratic load weights (the P2 coupling): triangle t is part of a six-node
        parent triangle with vertex nodes a, b, c and edge-midpoint nodes ab, bc, ca
        (``parent_nodes[t]``, wall vertex indices); ``parent_coords[t, k]`` are the
        barycentric coordinates (l_a, l_b, l_c) in the parent of the triangle's
        vertex k.  A contact at weights w of triangle t has parent coordinates
        l = sum_k w_k parent_coords[t, k], and its impulse and heat go to the six parent
        nodes with the P2 basis values l_a(2 l_a - 1), ..., 4 l_a l_b, 4 l_b l_c,
        4 l_c l_a instead of w.  A row of -1 in ``parent_nodes`` keeps the linear
        weights for that triangle.
    """

    def __init__(self, vertices, triangles, *, material, vertex_temperature=None,
                 parent_nodes=None, parent_coords=None):
        self._x = np.array(vertices, float)
        self._t = np.array(triangles, np.int64)
        if self._x.ndim != 2 or self._x.shape[1] != 3 or not np.isfinite(self._x).all():
            raise GsiInputError(f"mesh_wall.vertices shape {self._x.shape}: must be (nv, 3) finite (m)")
        if (self._t.ndim != 2 or self._t.shape[1] != 3 or self._t.size == 0
                or self._t.min() < 0 or self._t.max() >= len(self._x)):
            raise GsiInputError(
                f"mesh_wall.triangles shape {self._t.shape}: must be (nt, 3) vertex indices in [0, nv)")
        self._p6, self._lam = _parent_map(parent_nodes, parent_coords, len(self._t),
                                          len(self._x))
        self.material = material
        self._T0 = None if vertex_temperature is None else np.asarray(vertex_temperature, float)
        self._walls = None
        self._w = None

    @classmethod
    def from_file(cls, path, *, material, scale=1.0, vertex_temperature=None):
        """Read the triangles of a mesh file with meshio (STL, OBJ, VTU, gmsh ...).

        ``scale`` multiplies the coordinates (e.g. 1e-3 for a file in mm).
        """
        import meshio

        from gsi.readers import ReadFailed, guarded
        try:
            m = guarded(meshio.read, path)
        except ReadFailed as exc:  # meshio raises many kinds, SystemExit included
            raise GsiInputError(f"mesh_wall.file = {path}: meshio cannot read it "
                                f"({exc})") from None
        tris = [c.data for c in m.cells if c.type == "triangle"]
        if not tris:
            raise GsiInputError(f"mesh_wall.file = {path}: holds no triangles")
        t = np.concatenate(tris)
        used, inv = np.unique(t, return_inverse=True)
        x = np.asarray(m.points, float)[used] * scale
        if x.shape[1] == 2:
            x = np.column_stack([x, np.zeros(len(x))])
        return cls(x, inv.reshape(-1, 3), material=material,
                   vertex_temperature=vertex_temperature)

    # ---- after the wall is added to a simulation, its data live in the registry's mesh_state
    def attach(self, walls, index, v0, t0):
        """Called by the wall registry (:class:`gsi.dem.wall_registry.Walls`) that adds
        the wall: the wall is its mesh wall ``index``, its vertices and triangles start at
        rows ``v0`` and ``t0`` of the registry's mesh state."""
        self._walls = walls
        self._w = index
        self._v0, self._v1 = v0, v0 + len(self._x)
        self._t0, self._t1 = t0, t0 + len(self._t)

    @property
    def index(self):
        """The wall's index among the simulation's mesh walls (None before it is added)."""
        return self._w

    @property
    def first_triangle(self):
        """Row of the wall's first triangle in the simulation's mesh state."""
        return self._t0

    @property
    def n_triangles(self):
        return len(self._t)

    @property
    def initial_temperature(self):
        """The vertex temperatures given at construction (None: adiabatic)."""
        return self._T0

    @property
    def parent_nodes(self):
        """(nt, 6) int32 P2 parent nodes of each triangle (-1: linear weights)."""
        return self._p6

    @property
    def parent_coords(self):
        """(nt, 3, 3) barycentric coordinates of each triangle's vertices in its parent."""
        return self._lam

    def _vs(self):
        return slice(self._v0, self._v1)

    def _ts(self):
        return slice(self._t0, self._t1)

    @property
    def n_vertices(self):
        return len(self._x)

    @property
    def triangles(self):
        return self._t.copy()

    @property
    def vertices(self):
        """Current vertex positions (nv, 3) (m)."""
        return self._walls.mesh_state.x[self._vs()].copy() if self._walls is not None else self._x.copy()

    @property
    def vertex_velocity(self):
        return self._walls.mesh_state.v[self._vs()].copy()

    def set_vertices(self, x, v=None):
        """Replace vertex positions (m) and velocities (m/s; None keeps the current ones).
        The next step sees them; its neighbour lists are rebuilt first if a vertex moved
        more than half the skin (:meth:`gsi.dem.Simulation.wall_moved`)."""
        s = self._walls
        x = np.asarray(x, float)
        if x.shape != (self.n_vertices, 3):
            raise GsiInputError(f"wall.set_vertices x shape {x.shape}: must be ({self.n_vertices}, 3)")
        s.mesh_state.x[self._vs()] = x
        if v is not None:
            v = np.asarray(v, float)
            if v.shape != x.shape:
                raise GsiInputError(f"wall.set_vertices v shape {v.shape}: must be ({self.n_vertices}, 3)")
            s.mesh_state.v[self._vs()] = v
        s.mesh_state.wall_rigid[self._w] = 0

    def set_motion(self, velocity=(0.0, 0.0, 0.0), omega=(0.0, 0.0, 0.0), centre=None):
        """Rigid motion: translation ``velocity`` (m/s), rotation ``omega`` (rad/s) about
        ``centre`` (m; default: the current centre, initially the origin)."""
        s = self._walls
        s.mesh_state.wall_velocity[self._w] = vec3(velocity, "wall.velocity")
        s.mesh_state.wall_omega[self._w] = vec3(omega, "wall.omega")
        if centre is not None:
            s.mesh_state.wall_centre[self._w] = vec3(centre, "wall.centre")
        s.mesh_state.wall_rigid[self._w] = 1
        c = s.mesh_state.wall_centre[self._w]
        r = s.mesh_state.x[self._vs()] - c
        s.mesh_state.v[self._vs()] = s.mesh_state.wall_velocity[self._w] + np.cross(s.mesh_state.wall_omega[self._w], r)

    @property
    def centre(self):
        """Reference point of ``torque`` and of the rotation (m)."""
        return self._walls.mesh_state.wall_centre[self._w].copy()

    @property
    def vertex_temperature(self):
        s = self._walls
        return s.mesh_state.T[self._vs()].copy() if s.mesh_state.wall_has_T[self._w] else None

    @vertex_temperature.setter
    def vertex_temperature(self, value):
        s = self._walls
        if value is None:
            s.mesh_state.wall_has_T[self._w] = 0
            return
        value = np.broadcast_to(np.asarray(value, float), (self.n_vertices,))
        s.mesh_state.T[self._vs()] = value
        s.mesh_state.wall_has_T[self._w] = 1

    @property
    def force(self):
        """Force of the particles on the wall at the last step (N)."""
        return self._walls.mesh_state.wall_force[self._w].copy()

    @property
    def torque(self):
        """Torque of the particles on the wall about ``centre`` at the last step (N m)."""
        return self._walls.mesh_state.wall_torque[self._w].copy()

    @property
    def triangle_force(self):
        """Force of the particles on each triangle at the last step (nt, 3) (N)."""
        return self._walls.mesh_state.tri_force[self._ts()].copy()

    @property
    def vertex_impulse(self):
        """Accumulated -F_on_particle w_k dt per vertex (nv, 3) (N s)."""
        return self._walls.mesh_state.vertex_impulse[self._vs()].copy()

    @property
    def vertex_heat(self):
        """Accumulated -Q_to_particle w_k dt per vertex (nv,) (J)."""
        return self._walls.mesh_state.vertex_heat[self._vs()].copy()

    @property
    def impulse_on_particles(self):
        """Accumulated impulse of this wall on the particles (N s)."""
        return self._walls.mesh_state.wall_impulse[self._w].copy()

    @property
    def heat_to_particles(self):
        """Accumulated heat from this wall into the particles (J)."""
        return float(self._walls.mesh_state.wall_heat[self._w])

    @property
    def friction_heat(self):
        """Frictional heat the wall took since the start (J; never reset; its nodal share
        is in :attr:`vertex_heat`)."""
        return float(self._walls.mesh_state.wall_friction_heat[self._w])

    @property
    def work_on_particles(self):
        """Work of the moving wall on the particles since the start (J; never reset)."""
        return float(self._walls.mesh_state.wall_work[self._w])

    def reset_accumulators(self):
        s = self._walls
        s.book_reset_heat(s.mesh_state.wall_heat[self._w])
        s.mesh_state.vertex_impulse[self._vs()] = 0.0
        s.mesh_state.vertex_heat[self._vs()] = 0.0
        s.mesh_state.wall_impulse[self._w] = 0.0
        s.mesh_state.wall_heat[self._w] = 0.0


def _parent_map(nodes, coords, nt, nv):
    """Checked (nt, 6) int32 parent nodes (-1: linear weights) and (nt, 3, 3) coordinates."""
    if nodes is None and coords is None:
        return np.full((nt, 6), -1, np.int32), np.zeros((nt, 3, 3))
    if nodes is None or coords is None:
        raise GsiInputError("mesh_wall.parent_nodes and parent_coords: give both or neither")
    p6 = np.array(nodes, np.int64)
    lam = np.array(coords, float)
    if p6.shape != (nt, 6) or lam.shape != (nt, 3, 3):
        raise GsiInputError(f"mesh_wall.parent_nodes shape {p6.shape} / parent_coords shape "
                            f"{lam.shape}: must be ({nt}, 6) and ({nt}, 3, 3)")
    quad = p6[:, 0] >= 0
    if np.any(p6[quad] < 0) or np.any(p6 >= nv) or np.any(p6[~quad] != -1):
        raise GsiInputError(f"mesh_wall.parent_nodes: must be vertex indices in [0, {nv}) "
                            "(or a whole row of -1)")
    lq = lam[quad]
    if (not np.isfinite(lq).all() or np.any(lq < -1e-12) or np.any(lq > 1 + 1e-12)
            or not np.allclose(lq.sum(axis=2), 1.0, atol=1e-12, rtol=0.0)):
        raise GsiInputError("mesh_wall.parent_coords: each row must be barycentric "
                            "coordinates in [0, 1] summing to 1")
    return p6.astype(np.int32), lam


def triangle_edges(tri):
    """Global edge ids (nt, 3) for edges ab, bc, ca of each triangle (shared edges share ids)."""
    tri = np.asarray(tri, np.int64)
    e = np.stack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]], axis=1).reshape(-1, 2)
    e.sort(axis=1)
    _, ids = np.unique(e, axis=0, return_inverse=True)
    return ids.reshape(-1, 3).astype(np.int64)
