"""The walls of a DEM simulation: :class:`Walls` registers planes and mesh walls, keeps
their state bundles (:data:`gsi.dem.state.Planes`, :data:`gsi.dem.state.Mesh`) and
sizes the particles' wall-contact storage to them."""
import numpy as np

from gsi.errors import GsiInputError
from gsi.dem.state import MAX_WALL_SLOTS, append_plane, empty_mesh, empty_planes, mesh_bundle
from gsi.dem.walls import MeshWall, PlaneWall, triangle_edges, vec3

#: most plane walls (a particle's plane contacts are the bits of one int64)
MAX_PLANES = 63


class Walls:
    """Planes and mesh walls of one simulation.

    ``store``: the particles' :class:`gsi.dem.storage.ParticleStore` (its wall-contact
    fields are re-shaped when a plane or the first mesh wall is added)."""

    def __init__(self, store):
        self.store = store
        self.planes = []
        self.mesh_walls = []
        self.plane_state = empty_planes()
        self.mesh_state = empty_mesh()
        #: heat from walls into the particles (J) in accumulators reset since the start
        #: (the energy book, :mod:`gsi.dem.energy`; in checkpoints)
        self.heat_reset = 0.0

    def book_reset_heat(self, heat) -> None:
        """Keep the heat (J) of a wall accumulator about to be reset for the energy book."""
        self.heat_reset += float(heat)

    @property
    def n_planes(self) -> int:
        return len(self.planes)

    def slot(self, wall) -> int:
        """The wall's index among all walls, planes first (the contact log's and the
        extrapolation's wall numbering)."""
        if isinstance(wall, PlaneWall):
            return wall.index
        return self.n_planes + wall.index

    def add_plane(self, point, normal, *, mtype: int, material: str, temperature=None,
                  velocity=(0.0, 0.0, 0.0)) -> PlaneWall:
        """A plane through ``point`` with unit ``normal`` into the domain (material index
        ``mtype``)."""
        p = vec3(point, "plane.point")
        nrm = vec3(normal, "plane.normal")
        ln = np.linalg.norm(nrm)
        if ln == 0:
            raise GsiInputError(f"plane.normal = {normal}: must be non-zero")
        if self.n_planes >= MAX_PLANES:
            raise GsiInputError(f"planes: at most {MAX_PLANES} plane walls; use a mesh wall "
                                "for more")
        vel = vec3(velocity, "plane.velocity")
        self.store.set_wall_counts(n_planes=self.n_planes + 1)
        self.plane_state = append_plane(self.plane_state, p, nrm / ln, vel, mtype,
                                        None if temperature is None else float(temperature))
        wall = PlaneWall(self, self.n_planes, material)
        self.planes.append(wall)
        return wall

    def add_mesh_wall(self, wall: MeshWall, *, mtype: int) -> MeshWall:
        """Append ``wall``'s vertices and triangles to the mesh state (material index
        ``mtype``) and attach the wall to this registry (its data live here)."""
        if not self.mesh_walls:
            self.store.set_wall_counts(slots=MAX_WALL_SLOTS)
        M = self.mesh_state
        v0, t0 = len(M.x), len(M.tri)
        widx = len(self.mesh_walls)
        nv = wall.n_vertices
        T0 = wall.initial_temperature
        T = np.zeros(nv) if T0 is None else np.broadcast_to(T0, (nv,))
        p6, lam = wall.parent_nodes, wall.parent_coords
        tri = np.vstack([M.tri, wall.triangles + v0])
        walls = (np.append(M.wall_type, mtype), np.append(M.wall_has_T, T0 is not None),
                 np.append(M.wall_rigid, 0), np.vstack([M.wall_velocity, np.zeros(3)]),
                 np.vstack([M.wall_omega, np.zeros(3)]), np.vstack([M.wall_centre, np.zeros(3)]),
                 np.vstack([M.wall_force, np.zeros(3)]), np.vstack([M.wall_torque, np.zeros(3)]),
                 np.vstack([M.wall_impulse, np.zeros(3)]), np.append(M.wall_heat, 0.0),
                 np.append(M.wall_friction_heat, 0.0), np.append(M.wall_work, 0.0))
        walls = tuple(np.ascontiguousarray(a, b.dtype) for a, b in zip(walls, M[13:]))
        new = mesh_bundle(
            np.vstack([M.x, wall.vertices]), np.vstack([M.v, np.zeros((nv, 3))]),
            np.concatenate([M.T, T]), np.concatenate([M.vertex_wall, np.full(nv, widx)]),
            tri, triangle_edges(tri),
            np.concatenate([M.tri_wall, np.full(wall.n_triangles, widx)]),
            np.vstack([M.tri_p6, np.where(p6 >= 0, p6 + v0, -1)]),
            np.concatenate([M.tri_lam, lam]), walls)
        new.vertex_impulse[:v0] = M.vertex_impulse
        new.vertex_heat[:v0] = M.vertex_heat
        self.mesh_state = new
        wall.attach(self, widx, v0, t0)
        self.mesh_walls.append(wall)
        return wall

    def moved_beyond(self, half_skin: float) -> bool:
        """Whether a mesh vertex moved more than ``half_skin`` (m) since the last
        neighbour build."""
        M = self.mesh_state
        if not len(M.x):
            return False
        return ((M.x - M.x0) ** 2).sum(1).max() > half_skin ** 2

    def first_triangles(self) -> np.ndarray:
        """Row of each mesh wall's first triangle in the mesh state."""
        return np.array([w.first_triangle for w in self.mesh_walls], np.int64)

    def mean_temperatures(self) -> np.ndarray:
        """Each mesh wall's mean vertex temperature (0 for a wall without vertices)."""
        M = self.mesh_state
        return np.array([M.T[M.vertex_wall == w].mean() if (M.vertex_wall == w).any()
                         else 0.0 for w in range(len(M.wall_type))])


class WallViews:
    """Named views of a simulation's walls (``self.walls``, a :class:`Walls`), as
    :class:`gsi.dem.storage.ParticleViews` offers its particles."""

    @property
    def plane_state(self):
        """The planes (:data:`gsi.dem.state.Planes`)."""
        return self.walls.plane_state

    @property
    def mesh_state(self):
        """The mesh walls (:data:`gsi.dem.state.Mesh`)."""
        return self.walls.mesh_state

    @property
    def planes(self):
        """The :class:`PlaneWall` handles, in order."""
        return self.walls.planes

    @property
    def mesh_walls(self):
        """The :class:`MeshWall` handles, in order."""
        return self.walls.mesh_walls

    @property
    def n_planes(self):
        """Number of plane walls."""
        return self.walls.n_planes

    def wall_slot(self, wall):
        """The wall's index among all walls, planes first (as the contact log numbers
        them)."""
        return self.walls.slot(wall)
