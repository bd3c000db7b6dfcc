"""The DEM simulation: particles, walls, inserters, neighbour lists and the step loop.

Usage::

    from gsi.dem import Simulation, Material
    sim = Simulation(materials={"glass": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5)},
                     contact="hertz", rolling=False, heat=None, h_c=None, k_n=None,
                     gravity=(0, 0, -9.81), dt=2e-6, skin=4e-4,
                     domain=((0, 0, 0), (0.1, 0.1, 0.3)), force_dt=False)
    ids = sim.add_particles(x, radius, material="glass", v=None, T=None)  # -> particle ids
    floor = sim.add_plane(point=(0, 0, 0), normal=(0, 0, 1), material="glass")
    wall = sim.add_mesh_wall(vertices, triangles, material="glass")  # or add_mesh_wall_file
    wall.set_motion(velocity=(0, 0, 0), omega=(0, 0, 1.0), centre=(0, 0, 0))
    sim.add_inserter(region, rate=1000.0, radius=Uniform(1e-3, 1.5e-3), material="glass",
                     velocity=(0, 0, -1), max_count=5000)
    sim.step(1000)
    sim.time, sim.n, sim.kinetic_energy(), sim.contact_count(), sim.n_lost
    sim.start_contact_log(every=10, dt_split=1e-3)   # every contact from now ...
    sim.step(5000)
    log = sim.stop_contact_log()                     # ... to now (gsi.dem.contact_log)

Particles are addressed by *id* (stable, returned by ``add_particles``); their row in
the state arrays (``sim.x``, ``sim.v``, ... views of the first ``n`` rows) can change
when particles are deleted, and, with ``sort_particles=True``, at every neighbour
build; ``sim.index(ids)`` maps ids to rows.

Choices made here (DESIGN.md is silent):

- Time step: Hertz: warn above 0.3 t_R, refuse above t_R (GsiInputError) unless
  ``force_dt``; t_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766), min over the particles.
  Linear: the pair contact lasts t_c = pi sqrt(m*/k_n) with m* = m_min/2; refuse
  dt > t_c/10 (fewer than 10 steps per contact), warn dt > t_c/50.
- Heat: explicit Euler T += dt Q/(m c_p) each step.  ``heat_stability()`` returns
  max_i dt sum_j H_ij/(m_i c_p,i) (pairs and planes with a temperature); it is checked
  at every neighbour rebuild: above 1 a GsiRunError (unless ``force_dt``), above 0.5 a
  warning.
- Radiation (off unless ``sim.set_radiation(...)``, :mod:`gsi.dem.radiation`): its own
  cached kernels and cell list at the radiation cut-off; every ``every`` steps the step
  loop stops the compiled chunk and applies the exchange at T_n over the interval
  (operator splitting beside the engine's contact heat).
- A particle outside the domain box is deleted and counted in ``n_lost``
  (``lost="error"`` raises GsiRunError instead).  A NaN or a speed above ``v_max``
  (m/s, default 100) stops the run with GsiRunError.
- Particles can be held in place: ``sim.fix(ids)`` (they feel forces, exchange heat,
  but do not move).

State (for checkpoints, tests and new kernels; :mod:`gsi.dem.state`): five bundles,
named tuples of numpy arrays that every compiled kernel takes as one argument each:

- ``sim.particles`` (:data:`~gsi.dem.state.Particles`): per-particle arrays (x, v,
  omega, force, torque, q, radius, mass, inertia, T, mcp_inv, type, fixed, ncontact,
  x0, id), views of the first n rows;
- ``sim.wall_contacts`` (:data:`~gsi.dem.state.WallContacts`): per-particle plane
  springs and the triangle-contact slots;
- ``sim.pairs`` (:data:`~gsi.dem.state.Pairs`): slabs, the half neighbour list with
  its tangential springs and contact flags, triangle candidates with their springs;
- ``sim.plane_state`` (:data:`~gsi.dem.state.Planes`) and ``sim.mesh_state``
  (:data:`~gsi.dem.state.Mesh`): the walls (read and written by :class:`PlaneWall`
  and :class:`MeshWall`).

Also ``sim.heat_capacity`` (m c_p per particle, J/K), ``sim.material_names`` and
``sim.material_index(name)``.

How it runs (for speed, see ``benchmarks/settle.py``):

- The contact law, rolling law and heat model are compiled into one engine module per
  combination (:mod:`gsi.dem.engine_factory`), cached on disk by numba; the first run
  of a combination compiles in 15-25 s here (2 cores), the very first one in about
  30 s (it also compiles the shared kernels, cached once for all engines).
- ``sim.step(n)`` runs the n steps inside one compiled call, returning to Python only
  to rebuild the neighbour list (any particle moved more than skin/2), to delete lost
  particles or to insert particles.
- Threads: numba's (``NUMBA_NUM_THREADS``, ``numba.set_num_threads``); below
  ``parallel_min_n`` particles one thread is used.  The pair loop is parallel over
  slabs (at least one cutoff thick, a multiple of 2 x threads) in two colours (no
  atomics, no per-pair buffers), so each pair's law is evaluated once and Newton's
  third law holds exactly; each slab is integrated inside the same pass as soon as its
  forces are complete, so a step has two parallel regions.  Use at most as many
  threads as free cores: an OpenMP barrier waiting for a descheduled thread costs a
  whole scheduler time slice per parallel region.
"""
import math
import warnings

import numba
import numpy as np

from gsi.errors import GsiInputError, GsiRunError
from gsi.dem.materials import (DT_DEFAULT, DT_LINEAR_DEFAULT, DT_LINEAR_REFUSE, DT_REFUSE,
                               DT_WARN, Material, pair_table, rayleigh_time)
from gsi.dem.engine import get_engine
from gsi.dem import neighbour as nbr
from gsi.dem.walls import PlaneWall, MeshWall, triangle_edges, _vec3
from gsi.dem.state import (MAX_WALL_SLOTS, PARTICLE_FIELDS, WALL_CONTACT_FIELDS, Particles,
                           WallContacts, Pairs, append_plane, bundle_bytes, empty_mesh,
                           empty_pairs, empty_planes, mesh_bundle)
from gsi.dem import contact_log as clog


#: a step in which more than this fraction of the particles (and at least RUNAWAY_MIN)
#: leave the domain stops the run: that is a blow-up, not an outflow
RUNAWAY_FRACTION = 0.5
RUNAWAY_MIN = 10


class Simulation:
    """A DEM simulation (see the module docstring for the shape of the API).

    Parameters
    ----------
    materials : dict of str -> Material
        Particle and wall materials by name.
    contact : str, default "hertz"
        Contact law ("hertz", "linear"; see :mod:`gsi.dem.contact`).
    rolling : bool, default False
        Rolling resistance (constant directional torque, coefficient ``Material.mu_r``).
    heat : {None, "area", "radius", "constant", "pipe"}
        Contact conduction model (:mod:`gsi.dem.heat`); None: no heat.
    h_c : float, optional
        Conductance of the "constant" model (W/K).
    pipe_length, pipe_resistance : float, optional
        Pipe length w (m, > 0) and contact resistance per length R_c* (K m/W, default 0)
        of the "pipe" model.
    k_n : float, optional
        Normal stiffness of the "linear" law (N/m).
    gravity : (3,) float, default (0, 0, -9.81)
        (m/s^2).
    dt : float
        Time step (s).
    skin : float
        Neighbour-list skin (m).
    domain : ((3,), (3,))
        Lower and upper corner of the domain box (m); particles leaving it are lost.
    force_dt : bool, default False
        Run even when the time-step checks refuse.
    dt_checked : bool, default False
        The caller applied gsi's time-step rule to every particle the run will hold
        (``gsi.case.Case.time_step``): the simulation does not check it again.
    v_max : float, default 100.0
        Speed (m/s) above which a particle counts as blown up.
    lost : {"delete", "error"}
        What happens to particles leaving the domain.
    pair_overrides : dict, optional
        ``{("mat_a", "mat_b"): {"e": .., "mu": .., "mu_r": ..}}``.
    seed : int, optional
        Seed of the random generator used by inserters.
    parallel_min_n : int, default 2000
        Below this many particles the kernels run on one thread (thread start-up
        costs more than it saves for small systems).
    sort_particles : bool, default False
        Re-order the particle rows at every neighbour build into the order the force
        pass visits them (slab by slab, cell by cell): memory is then read nearly in
        sequence (measured on the settle bed, 1 thread: +10 % at 20k particles, +20 %
        at 200k, 3.9x against a random order).  Rows then change at every build:
        address particles by id (``sim.index``), and ``sim.ids`` is not sorted.
    """

    def __init__(self, materials, *, contact="hertz", rolling=False, heat=None, h_c=None,
                 pipe_length=None, pipe_resistance=0.0, k_n=None, gravity=(0.0, 0.0, -9.81), dt, skin, domain, force_dt=False,
                 v_max=100.0, lost="delete", pair_overrides=None, seed=None,
                 parallel_min_n=2000, sort_particles=False, dt_checked=False):
        if not materials:
            raise GsiInputError("materials = {}: give at least one Material")
        for name, m in materials.items():
            if not isinstance(m, Material):
                raise GsiInputError(f"materials.{name} = {m!r}: must be a gsi.dem.Material")
            m.validate(name)
        self.materials = dict(materials)
        self._mat_names = list(self.materials)
        self._mat_index = {k: i for i, k in enumerate(self._mat_names)}
        if not (dt > 0 and math.isfinite(dt)):
            raise GsiInputError(f"dt = {dt}: must be > 0 (s)")
        if not (skin > 0):
            raise GsiInputError(f"skin = {skin}: must be > 0 (m)")
        if contact == "linear" and not (k_n is not None and k_n > 0):
            raise GsiInputError(f"k_n = {k_n}: the linear law needs a normal stiffness > 0 (N/m)")
        if heat == "constant" and not (h_c is not None and h_c >= 0):
            raise GsiInputError(f"h_c = {h_c}: the constant heat model needs a conductance >= 0 (W/K)")
        if heat == "pipe" and not (pipe_length is not None and pipe_length > 0
                                   and pipe_resistance >= 0):
            raise GsiInputError(f"pipe_length = {pipe_length}: the pipe heat model needs a pipe "
                                "length > 0 (m) and pipe_resistance >= 0 (K m/W)")
        if lost not in ("delete", "error"):
            raise GsiInputError(f"lost = {lost!r}: must be 'delete' or 'error'")
        lo, hi = (np.asarray(domain[0], float), np.asarray(domain[1], float))
        if lo.shape != (3,) or hi.shape != (3,) or not (hi > lo).all():
            raise GsiInputError(f"domain = {domain}: must be ((xlo, ylo, zlo), (xhi, yhi, zhi)) with hi > lo (m)")
        self.engine = get_engine(contact, rolling, heat)
        self.contact, self.rolling, self.heat = contact, rolling, heat
        self.k_n, self.h_c = k_n, h_c
        self.g = _vec3(gravity, "gravity")
        self.dt, self.skin = float(dt), float(skin)
        self.lo, self.hi = lo, hi
        self.force_dt, self.v_max, self.lost = force_dt, float(v_max), lost
        self._overrides = {}
        for (a, b), d in (pair_overrides or {}).items():
            for mname in (a, b):
                if mname not in self._mat_index:
                    raise GsiInputError(f"pair_overrides.{a}-{b}: unknown material {mname!r}")
            self._overrides[(self._mat_index[a], self._mat_index[b])] = d
        self.table = pair_table([self.materials[k] for k in self._mat_names],
                                k_n=k_n or 0.0, h_c=h_c or 0.0, pipe_length=pipe_length or 0.0,
                                pipe_resistance=pipe_resistance or 0.0,
                                pair_overrides=self._overrides)
        self.rng = np.random.default_rng(seed)
        self.parallel_min_n = int(parallel_min_n)
        self.sort_particles = bool(sort_particles)
        self.time = 0.0
        self.step_count = 0
        self.n = 0
        self.n_lost = 0
        self._cap = 0
        self._next_id = 0
        self._npl = 0
        self._S = 0
        self._pa = {}                   # particle fields at capacity (PARTICLE_FIELDS)
        self._wa = {}                   # wall-contact fields at capacity (WALL_CONTACT_FIELDS)
        self._alloc(16)
        self.planes = []
        self.plane_state = empty_planes()
        self.mesh_walls = []
        self.mesh_state = empty_mesh()
        self._overflow = np.zeros(1, np.int64)
        self.pairs = empty_pairs(0)
        self.inserters = []
        self._need_rebuild = True
        self._forces_valid = False
        self._dt_rule_applied = bool(dt_checked)
        self._dt_checked = False
        self.n_rebuilds = 0
        self._heat_warned = False
        self._built = False
        self.radiation = None
        self._log = clog.empty_log_state()      # read only by a logging engine
        self._log_t0 = None                     # (t0, particle data) while logging

    # ------------------------------------------------------------------ storage
    def _shape(self, cap, trail):
        return (cap,) + tuple({"npl": self._npl, "S": self._S}.get(t, t) for t in trail)

    def _alloc(self, cap):
        for store, fields in ((self._pa, PARTICLE_FIELDS), (self._wa, WALL_CONTACT_FIELDS)):
            for name, (trail, dtype) in fields.items():
                arr = np.zeros(self._shape(cap, trail), dtype)
                old = store.get(name)
                if old is not None and self.n:
                    src = old[: self.n]
                    sl = tuple(slice(0, min(a, b)) for a, b in zip(src.shape, arr.shape))
                    arr[sl] = src[sl]
                store[name] = arr
        self._cap = cap

    def _realloc_field(self, name):
        """Re-shape one wall-contact field after the plane count or slot count changed
        (existing entries kept where they fit)."""
        trail, dtype = WALL_CONTACT_FIELDS[name]
        arr = np.zeros(self._shape(self._cap, trail), dtype)
        old = self._wa[name]
        sl = tuple(slice(0, min(a, b)) for a, b in zip(old.shape, arr.shape))
        arr[sl] = old[sl]
        self._wa[name] = arr

    def _p(self, name):
        return self._pa[name][: self.n]

    # ------------------------------------------------------------------ state bundles
    @property
    def particles(self):
        """Per-particle state (:data:`gsi.dem.state.Particles`): views of the first n
        rows of every field of :data:`gsi.dem.state.PARTICLE_FIELDS`."""
        n = self.n
        return Particles(*[self._pa[k][:n] for k in PARTICLE_FIELDS])

    @property
    def wall_contacts(self):
        """Per-particle wall contacts (:data:`gsi.dem.state.WallContacts`): plane springs
        and contact flags, the triangle-contact slots; views of the first n rows."""
        n = self.n
        return WallContacts(*[self._wa[k][:n] for k in WALL_CONTACT_FIELDS], self._overflow)

    def _bundles(self):
        """The engine's state arguments ``(P, pairs, pl, M, wc)``."""
        return (self.particles, self.pairs, self.plane_state, self.mesh_state,
                self.wall_contacts)

    @property
    def material_names(self):
        """Material names in index order (the particle ``type`` and pair-table rows)."""
        return list(self._mat_names)

    def material_index(self, name):
        """Index of material ``name`` (its value in ``sim.type``)."""
        return self._material(name, "material")

    @property
    def heat_capacity(self):
        """Heat capacity m c_p of each particle (n,) (J/K), a new array."""
        return 1.0 / self._p("mcp_inv")

    @property
    def x(self):
        """Positions (n, 3) (m), a view."""
        return self._p("x")

    @property
    def v(self):
        """Velocities (n, 3) (m/s), a view."""
        return self._p("v")

    @property
    def omega(self):
        """Angular velocities (n, 3) (rad/s), a view."""
        return self._p("omega")

    @property
    def force(self):
        """Total force on each particle (n, 3) (N) at the last step, incl. gravity."""
        return self._p("force")

    @property
    def torque(self):
        return self._p("torque")

    @property
    def radius(self):
        return self._p("radius")

    @property
    def mass(self):
        return self._p("mass")

    @property
    def T(self):
        """Particle temperatures (n,), a view."""
        return self._p("T")

    @property
    def ids(self):
        return self._p("id")

    @property
    def type(self):
        return self._p("type")

    @property
    def ncontact(self):
        """Contacts per particle at the last step (n,)."""
        return self._p("ncontact")

    def index(self, ids):
        """Rows of the given particle ids."""
        ids = np.asarray(ids, np.int64)
        rows = _rows_of(self.ids, ids)
        if (rows < 0).any():
            raise GsiInputError(f"particle ids {ids[rows < 0][:5].tolist()}: not present (lost or never added)")
        return rows

    # ------------------------------------------------------------------ particles
    def _material(self, name, key):
        if name not in self._mat_index:
            raise GsiInputError(f"{key} = {name!r}: unknown material, known: {self._mat_names}")
        return self._mat_index[name]

    def add_particles(self, x, radius, *, material, v=None, T=None, omega=None):
        """Add spheres.

        Parameters
        ----------
        x : array_like (k, 3)
            Centres (m), inside the domain.
        radius : float or array_like (k,)
            Radii (m), > 0.
        material : str
            Material name.
        v, omega : array_like (k, 3), optional
            Velocities (m/s), angular velocities (rad/s); default 0.
        T : float or array_like (k,), optional
            Temperatures; default 0.

        Returns
        -------
        numpy.ndarray of int64
            The new particles' ids.
        """
        x = np.atleast_2d(np.asarray(x, float))
        k = len(x)
        if x.shape != (k, 3) or not np.isfinite(x).all():
            raise GsiInputError(f"particles.x shape {x.shape}: must be (k, 3) finite (m)")
        r = np.broadcast_to(np.asarray(radius, float), (k,)).copy()
        if not (r > 0).all():
            raise GsiInputError(f"particles.radius = {r[~(r > 0)][:3].tolist()}: must be > 0 (m)")
        if ((x < self.lo) | (x > self.hi)).any():
            raise GsiInputError("particles.x: some centres lie outside the domain box; enlarge domain or move them")
        t = self._material(material, "particles.material")
        mat = self.materials[material]
        if self.n + k > self._cap:
            self._alloc(max(2 * self._cap, self.n + k))
        s = slice(self.n, self.n + k)
        for store in (self._pa, self._wa):       # every field starts at 0 ...
            for arr in store.values():
                arr[s] = 0
        a = self._pa                              # ... unless set here
        a["x"][s] = x
        a["v"][s] = 0.0 if v is None else np.broadcast_to(np.asarray(v, float), (k, 3))
        a["omega"][s] = 0.0 if omega is None else np.broadcast_to(np.asarray(omega, float), (k, 3))
        a["force"][s] = 0.0
        a["torque"][s] = 0.0
        a["radius"][s] = r
        m = mat.rho * 4.0 / 3.0 * math.pi * r ** 3
        a["mass"][s] = m
        a["inertia"][s] = 0.4 * m * r * r
        a["T"][s] = 0.0 if T is None else np.broadcast_to(np.asarray(T, float), (k,))
        a["mcp_inv"][s] = 1.0 / (m * mat.cp)
        a["type"][s] = t
        a["fixed"][s] = 0
        a["x0"][s] = x
        ids = np.arange(self._next_id, self._next_id + k, dtype=np.int64)
        a["id"][s] = ids
        self._next_id += k
        self.n += k
        self._need_rebuild = True
        self._forces_valid = False
        self._dt_checked = False
        return ids

    def fix(self, ids, fixed=True):
        """Hold particles in place (they still feel forces and exchange heat)."""
        self._pa["fixed"][self.index(ids)] = 1 if fixed else 0

    def _delete(self, mask):
        keep = ~mask
        nk = int(keep.sum())
        for store in (self._pa, self._wa):
            for arr in store.values():
                arr[:nk] = arr[: self.n][keep]
        self.n = nk
        self._need_rebuild = True

    # ------------------------------------------------------------------ walls
    def add_plane(self, point, normal, *, material, temperature=None, velocity=(0.0, 0.0, 0.0)):
        """Add an infinite plane through ``point`` (m) with unit ``normal`` into the domain.

        Returns
        -------
        PlaneWall
        """
        p = _vec3(point, "plane.point")
        nrm = _vec3(normal, "plane.normal")
        ln = np.linalg.norm(nrm)
        if ln == 0:
            raise GsiInputError(f"plane.normal = {normal}: must be non-zero")
        t = self._material(material, "plane.material")
        if self._npl >= 63:
            raise GsiInputError("planes: at most 63 plane walls; use a mesh wall for more")
        vel = _vec3(velocity, "plane.velocity")
        self._npl += 1
        self._realloc_field("plane_hist")
        self.plane_state = append_plane(self.plane_state, p, nrm / ln, vel, t,
                                        None if temperature is None else float(temperature))
        self._need_rebuild = True        # the plane candidates of the particles
        wall = PlaneWall(self, len(self.planes), material)
        self.planes.append(wall)
        self._forces_valid = False
        return wall

    def add_mesh_wall(self, vertices, triangles=None, *, material=None, vertex_temperature=None):
        """Add a triangle-mesh wall (arrays, or a :class:`MeshWall`).

        Returns
        -------
        MeshWall
        """
        wall = vertices if isinstance(vertices, MeshWall) else MeshWall(
            vertices, triangles, material=material, vertex_temperature=vertex_temperature)
        t = self._material(wall.material, "mesh_wall.material")
        if not self.mesh_walls:
            self._S = MAX_WALL_SLOTS
            for name, (trail, _) in WALL_CONTACT_FIELDS.items():
                if "S" in trail:
                    self._realloc_field(name)
        M = self.mesh_state
        v0, t0 = len(M.x), len(M.tri)
        widx = len(self.mesh_walls)
        nv = wall.n_vertices
        T = np.zeros(nv) if wall._T0 is None else np.broadcast_to(wall._T0, (nv,))
        tri = np.vstack([M.tri, wall._t + v0])
        walls = (np.append(M.wall_type, t), np.append(M.wall_has_T, wall._T0 is not None),
                 np.append(M.wall_rigid, 0), np.vstack([M.wall_velocity, np.zeros(3)]),
                 np.vstack([M.wall_omega, np.zeros(3)]), np.vstack([M.wall_centre, np.zeros(3)]),
                 np.vstack([M.wall_force, np.zeros(3)]), np.vstack([M.wall_torque, np.zeros(3)]),
                 np.vstack([M.wall_impulse, np.zeros(3)]), np.append(M.wall_heat, 0.0))
        walls = tuple(np.ascontiguousarray(a, b.dtype) for a, b in zip(walls, M[13:]))
        new = mesh_bundle(
            np.vstack([M.x, wall._x]), np.vstack([M.v, np.zeros((nv, 3))]),
            np.concatenate([M.T, T]), np.concatenate([M.vertex_wall, np.full(nv, widx)]),
            tri, triangle_edges(tri), np.concatenate([M.tri_wall, np.full(len(wall._t), widx)]),
            np.vstack([M.tri_p6, np.where(wall._p6 >= 0, wall._p6 + v0, -1)]),
            np.concatenate([M.tri_lam, wall._lam]), walls)
        new.vertex_impulse[:v0] = M.vertex_impulse
        new.vertex_heat[:v0] = M.vertex_heat
        self.mesh_state = new
        wall._attach(self, widx, v0, t0)
        self.mesh_walls.append(wall)
        self._need_rebuild = True
        self._forces_valid = False
        return wall

    def add_mesh_wall_file(self, path, *, material, scale=1.0, vertex_temperature=None):
        """Add a mesh wall read from a file with meshio (see :meth:`MeshWall.from_file`)."""
        return self.add_mesh_wall(MeshWall.from_file(path, material=material, scale=scale,
                                                     vertex_temperature=vertex_temperature))

    def _wall_moved(self):
        """A mesh wall moved between steps (``set_vertices``): rebuild the candidate lists
        if it moved more than half the skin. The forces of the last step are NOT evaluated
        again: a force evaluation advances every tangential spring by its increment, so a
        second one at the same time level would count that increment twice (and a coupled
        structure's interval boundary would perturb every contact in the DEM). The moved
        wall enters the next step's force pass: a lag of one DEM step, the staggered
        scheme's own."""
        M = self.mesh_state
        if len(M.x):
            d2 = ((M.x - M.x0) ** 2).sum(1).max()
            if d2 > (0.5 * self.skin) ** 2:
                self._need_rebuild = True

    # ------------------------------------------------------------------ inserters
    def add_inserter(self, region, rate, *, radius, material, velocity=(0.0, 0.0, 0.0),
                     max_count=None, T=None, start=None):
        """Continuous insertion (see :class:`gsi.dem.insertion.Inserter`)."""
        from gsi.dem.insertion import Inserter
        ins = Inserter(self, region, rate, radius=radius, material=material, velocity=velocity,
                       max_count=max_count, T=T, start=self.time if start is None else start)
        self.inserters.append(ins)
        return ins

    def set_radiation(self, emissivity, *, cutoff=None, every=1, T_enclosure=None):
        """Turn on particle radiation (:class:`gsi.dem.radiation.Radiation`: emissivity by
        material name, cut-off c (-, default 1.5), an evaluation every ``every`` steps,
        an optional enclosure temperature T_enclosure (K)). Returns the model."""
        from gsi.dem.radiation import CUTOFF_DEFAULT, Radiation
        self.radiation = Radiation(self, emissivity=emissivity, every=every,
                                   cutoff=CUTOFF_DEFAULT if cutoff is None else cutoff,
                                   T_enclosure=T_enclosure)
        return self.radiation

    # ------------------------------------------------------------------ checks
    def rayleigh_time(self):
        """min over particles of the Rayleigh time t_R (s) (inf without particles)."""
        tR = math.inf
        for t in np.unique(self.type):
            mat = self.materials[self._mat_names[t]]
            tR = min(tR, rayleigh_time(self.radius[self.type == t].min(), mat))
        return tR

    def _check_dt(self):
        """The time-step rule of :mod:`gsi.dem.materials` (DT_* constants; the same rule as
        ``gsi.case.Case.time_step``, which a runner applies first and then passes
        ``dt_checked=True``): refuse above DT_REFUSE t_R (linear law: DT_LINEAR_REFUSE
        t_c) unless ``force_dt``, warn above DT_WARN t_R (DT_LINEAR_DEFAULT t_c)."""
        if self.n == 0 or self._dt_checked or self._dt_rule_applied:
            return
        self._dt_checked = True
        if self.contact == "linear":
            t_ref = math.pi * math.sqrt(0.5 * self.mass.min() / self.k_n)
            name, default, warn, refuse = ("t_c = pi sqrt(m*/k_n) of the linear law",
                                           DT_LINEAR_DEFAULT, DT_LINEAR_DEFAULT,
                                           DT_LINEAR_REFUSE)
        else:
            t_ref = self.rayleigh_time()
            name, default, warn, refuse = ("the Rayleigh time t_R", DT_DEFAULT, DT_WARN,
                                           DT_REFUSE)
        if self.dt > refuse * t_ref * (1 + 1e-12):
            msg = (f"dt = {self.dt}: above {refuse:g} x {name} = {t_ref:.3g} s; use dt <= "
                   f"{default * t_ref:.3g} s or pass force_dt=True")
            if not self.force_dt:
                raise GsiInputError(msg)
            warnings.warn(msg)
        elif self.dt > warn * t_ref * (1 + 1e-12):
            warnings.warn(f"dt = {self.dt} s is above {warn:g} x {name} = {t_ref:.3g} s; "
                          f"dt <= {default * t_ref:.3g} s is safe")

    def heat_stability(self):
        """max_i dt sum_j H_ij/(m_i c_p,i): the explicit heat update is stable below 1."""
        if self.heat is None or self.n == 0:
            return 0.0
        self._ensure_lists()
        Hs = self.engine.heat_conductance_sum(*self._bundles(), self.table)
        return float((self.dt * Hs * self._p("mcp_inv")).max())

    def _check_heat(self):
        if self.heat is None:
            return
        ratio = self.heat_stability()
        if ratio > 1.0 and not self.force_dt:
            raise GsiRunError(
                f"heat: dt sum H/(m c_p) = {ratio:.3g} > 1 at step {self.step_count}: the explicit "
                "heat update is unstable; reduce dt, the conductivity, or pass force_dt=True")
        if ratio > 0.5 and not self._heat_warned:
            self._heat_warned = True
            warnings.warn(f"heat: dt sum H/(m c_p) = {ratio:.3g} (stable below 1)")

    # ------------------------------------------------------------------ neighbour lists
    def _ensure_lists(self):
        if self._need_rebuild or not self._built:
            self._rebuild()

    def _rebuild(self):
        n = self.n
        x = self._pa["x"][:n]
        r = self._pa["radius"][:n]
        rmax = float(r.max()) if n else 0.0
        dims, inv_cs = nbr.grid_for(self.lo, self.hi, 2 * rmax + self.skin, n)
        cell_of = np.empty(n, np.int64)
        nbr.cell_index(n, x, self.lo, inv_cs, dims, cell_of)
        cell_start, cell_list = nbr.bin_cells(n, cell_of, int(dims.prod()))
        # slabs along the axis where the particles spread over most cells
        spread = [np.ptp(np.floor((x[:, d] - self.lo[d]) * inv_cs[d])) if n else 0 for d in range(3)]
        axis = int(np.argmax(spread))
        small = n < self.parallel_min_n
        threads = 1 if small else numba.get_num_threads()
        s_lo, s_inv_w, nslab = nbr.slab_layout(
            x[:, axis], 2 * rmax + self.skin, threads,
            min_per_slab=nbr.MIN_SLAB_PARTICLES if small else 1)
        slab_of, slab_start, slab_list = nbr.slab_sort(n, x, cell_list, axis, s_lo, s_inv_w,
                                                       nslab)
        if self.sort_particles and n:
            # rows into visiting order: row m is the m-th particle the force pass visits
            perm = slab_list
            for store in (self._pa, self._wa):
                for arr in store.values():
                    arr[:n] = arr[:n][perm]
            new_of_old = np.empty(n, np.int64)
            new_of_old[perm] = np.arange(n)
            cell_of = cell_of[perm]
            slab_of = slab_of[perm]
            cell_list = new_of_old[cell_list].astype(cell_list.dtype)
            slab_list = np.arange(n, dtype=slab_list.dtype)
        counts = np.empty(n, np.int64)
        nbr.count_pairs(n, x, r, self.skin, cell_of, slab_of, cell_start, cell_list, dims, counts)
        nb_start = np.zeros(n + 1, np.int64)
        np.cumsum(counts, out=nb_start[1:])
        npair = int(nb_start[-1])
        nb_j = np.empty(npair, np.int32)
        nbr.fill_pairs(n, x, r, self.skin, cell_of, slab_of, cell_start, cell_list, dims,
                       nb_start, nb_j)
        hist = np.zeros((npair, 3))
        pact = np.zeros(npair, np.uint8)
        # new row -> old row through the ids at the last build
        ids = self._pa["id"][:n]
        old = self.pairs
        if self._built and len(self._ids_at_build):
            old_of_new = _rows_of(self._ids_at_build, ids)
            nbr.carry_pair_history(n, nb_start, nb_j, hist, pact, old_of_new, old.start,
                                   old.j, old.hist, old.active)
        else:
            old_of_new = np.full(n, -1, np.int64)
        # triangle candidates
        M = self.mesh_state
        mc_start = np.zeros(n + 1, np.int64)
        if len(M.tri):
            tstart, tlist = nbr.bin_triangles(M.x, M.tri, self.lo, inv_cs, dims, rmax + self.skin)
            dummy = np.zeros(0, np.int32)
            nbr.tri_candidates(n, x, r, self.skin, cell_of, tstart, tlist, M.x, M.tri,
                               mc_start, dummy, True)
            np.cumsum(mc_start[1:], out=mc_start[1:])
            mc_tri = np.empty(int(mc_start[-1]), np.int32)
            nbr.tri_candidates(n, x, r, self.skin, cell_of, tstart, tlist, M.x, M.tri,
                               mc_start, mc_tri, False)
            mc_hist = np.zeros((len(mc_tri), 3))
            if self._built:
                nbr.carry_tri_history(n, mc_start, mc_tri, mc_hist, old_of_new, old.tri_start,
                                      old.tri, old.tri_hist)
            M.x0[:] = M.x
        else:
            mc_tri = np.zeros(0, np.int32)
            mc_hist = np.zeros((0, 3))
        self.pairs = Pairs(slab_start, slab_list, nb_start, nb_j, hist, pact, mc_start, mc_tri,
                           mc_hist)
        pl = self.plane_state
        nbr.plane_candidates(x, r, self.skin, pl.point, pl.normal, self._wa["plane_cand"][:n])
        pl.point0[:] = pl.point
        self._built = True
        self._pa["x0"][:n] = x
        self._ids_at_build = ids.copy()
        self._need_rebuild = False
        self.n_rebuilds += 1

    # ------------------------------------------------------------------ stepping
    def _prepare(self):
        self._check_dt()
        if self._need_rebuild or not self._built:
            self._rebuild()
            self._check_heat()
        if not self._forces_valid:
            self.engine.compute_forces(self.g, *self._bundles(), self.table)
            self._forces_valid = True

    def step(self, n=1):
        """Advance ``n`` time steps (inserters run at their due steps)."""
        if n < 0:
            raise GsiInputError(f"step n = {n}: must be >= 0")
        threads = numba.get_num_threads()
        if self.n < self.parallel_min_n:
            numba.set_num_threads(1)
        try:
            self._step(n)
        finally:
            numba.set_num_threads(threads)

    def _step(self, n):
        remaining = int(n)
        half_skin2 = (0.5 * self.skin) ** 2
        vmax2 = self.v_max ** 2
        skip = False
        while remaining > 0:
            if not skip:
                for ins in self.inserters:
                    ins.maybe_insert()
            if self.n == 0 and not skip:
                chunk = min([remaining] + [ins.steps_to_next() for ins in self.inserters])
                self._advance_time(chunk)
                remaining -= chunk
                continue
            if skip:
                self._rebuild()
                self._check_heat()
            else:
                self._prepare()
            chunk = min([remaining] + [ins.steps_to_next() for ins in self.inserters])
            if self.radiation is not None:     # applied at T_n over its interval
                chunk = min(chunk, self.radiation.step_due())
            self._log.ctrl[clog.C_STEP] = self.step_count
            done, code, info = self.engine.advance(chunk, skip, self.dt, self.g, half_skin2,
                                                   vmax2, self.lo, self.hi, *self._bundles(),
                                                   self.table, self._log)
            self._advance_time(done)
            remaining -= done
            skip = False
            if code == 1:
                skip = True
            elif code == 4:                 # the log is full: grow it, take the sample
                self._grow_log()
                clog.sample(*self._bundles(), self._log)
            elif code == 2:
                out = ((self.x < self.lo) | (self.x > self.hi)).any(1)
                if self.lost == "error":
                    i = int(np.flatnonzero(out)[0])
                    raise GsiRunError(
                        f"particle id {int(self.ids[i])} left the domain at step {self.step_count} "
                        f"(x = {self.x[i].tolist()}); enlarge domain or add walls")
                n_out = int(out.sum())
                if n_out >= RUNAWAY_MIN and n_out > RUNAWAY_FRACTION * self.n:
                    speed = float(np.linalg.norm(self.v[out], axis=1).max())
                    raise GsiRunError(
                        f"runaway loss at step {self.step_count}: {n_out} of {self.n} particles "
                        f"left the domain in one step (fastest {speed:.3g} m/s); likely cause: "
                        f"dt = {self.dt} s too large for the stiffness (Rayleigh time "
                        f"{self.rayleigh_time():.3g} s), overlapping particles, or a missing "
                        f"wall")
                self.n_lost += n_out
                self._delete(out)
                skip = True
            elif code == 3:
                i = int(info)
                raise GsiRunError(
                    f"blow-up at step {self.step_count}: particle id {int(self.ids[i])} has "
                    f"velocity {self.v[i].tolist()} m/s (NaN or above v_max = {self.v_max}); "
                    f"likely cause: dt = {self.dt} s too large for the stiffness (Rayleigh time "
                    f"{self.rayleigh_time():.3g} s) or overlapping initial particles")
            if self._overflow[0]:
                self._overflow[0] = 0
                warnings.warn(f"more than {MAX_WALL_SLOTS} triangle contacts on one particle; extra ones ignored")

    # ------------------------------------------------------------------ contact log
    @property
    def contact_logging(self):
        """Whether a contact log is being recorded (:meth:`start_contact_log`)."""
        return self._log_t0 is not None

    def start_contact_log(self, *, every=1, dt_split=None, capacity=None):
        """Record every contact from now (t0) until :meth:`stop_contact_log` (t1); see
        :mod:`gsi.dem.contact_log`.

        Parameters
        ----------
        every : int
            Sampling factor n: the contacts are sampled every ``every`` steps (the first
            sample ``every`` steps from now).
        dt_split : float, optional
            Delta t_c^max (s): a contact longer than this is logged as several rows
            (Algorithm 2 of the seed); a multiple of every dt. Default: never split.
        capacity : int, optional
            Rows to reserve at first (default 32 per particle); the log grows as
            needed.

        The simulation switches to the logging variant of its engine (compiled once per
        law combination, then cached); trajectories are the same bit for bit.  The log
        is not part of :meth:`state` (a checkpoint taken while logging does not hold it).
        """
        if self.contact_logging:
            raise GsiInputError("start_contact_log: a contact log is already running; call "
                                "stop_contact_log() first")
        if not (isinstance(every, (int, np.integer)) and every >= 1):
            raise GsiInputError(f"contact_log.every = {every}: must be an integer >= 1 "
                                "(steps)")
        if self.n == 0:
            raise GsiInputError("start_contact_log: no particles to log")
        if int(self.ids.max()) >= 2 ** 31:
            raise GsiInputError("start_contact_log: particle ids above 2^31 cannot be logged")
        if self._npl > clog.TRI_BASE:
            raise GsiInputError(f"start_contact_log: at most {clog.TRI_BASE} planes")
        split = 0
        if dt_split is not None:
            per = every * self.dt
            split = int(round(dt_split / per))
            if not (dt_split > 0 and split >= 1 and abs(split * per - dt_split) <= 1e-9 * dt_split):
                raise GsiInputError(
                    f"contact_log.dt_split = {dt_split}: must be a positive multiple of "
                    f"every x dt = {per:g} s (e.g. {max(split, 1) * per:g} s)")
        n_cap = 8 * self.n + 64
        self._log = clog.empty_log_state(n_cap, int(capacity) if capacity else 4 * n_cap)
        c = self._log.ctrl
        c[clog.C_EVERY] = every
        c[clog.C_SPLIT] = split
        c[clog.C_NEXT] = self.step_count + every
        c[clog.C_START] = self.step_count
        if self.heat not in clog.SIZE_MODELS:
            raise GsiInputError(f"contact_log: heat = {self.heat!r} is not logged (the replay "
                                f"knows the contact sizes of 'area', 'radius' and 'constant')")
        c[clog.C_MODEL] = clog.SIZE_MODELS[self.heat]
        order = np.argsort(self.ids, kind="stable")
        self._log_t0 = dict(t0=self.time, ids=self.ids[order].copy(), x0=self.x[order].copy(),
                            T0=self.T[order].copy(),
                            heat_capacity=self.heat_capacity[order],
                            type_=self.type[order].astype(np.int32))
        self.engine = get_engine(self.contact, self.rolling, self.heat, log=True)

    def stop_contact_log(self):
        """End the log started by :meth:`start_contact_log` (now is t1).

        Returns
        -------
        gsi.dem.contact_log.ContactLog
        """
        if not self.contact_logging:
            raise GsiInputError("stop_contact_log: no contact log is running; call "
                                "start_contact_log() first")
        lg = self._log
        need = int(lg.ctrl[clog.C_NROWS] + lg.ctrl[clog.C_NOPEN])
        if need > lg.row_key.shape[0]:
            lg = clog.grown(lg, 0, need)
        clog.close_open(lg)
        a = self._log_t0
        self._log_t0 = None
        self._log = clog.empty_log_state()
        self.engine = get_engine(self.contact, self.rolling, self.heat)
        order = np.argsort(self.ids, kind="stable")
        ids = self.ids[order]
        if len(ids) != len(a["ids"]) or not (ids == a["ids"]).all():
            raise GsiRunError("stop_contact_log: particles were inserted or lost since "
                              "start_contact_log; the log needs the same particles at t0 and t1")
        from gsi.dem.materials import P_HC, P_KH
        pl, M = self.plane_state, self.mesh_state
        nw = len(M.wall_type)
        mesh_T = np.array([M.T[M.vertex_wall == w].mean() if (M.vertex_wall == w).any()
                           else 0.0 for w in range(nw)])
        tri_first = np.array([w._t0 for w in self.mesh_walls], np.int64)
        col = P_HC if self.heat == "constant" else P_KH
        return clog.ContactLog.from_rows(
            lg, ids=ids, x0=a["x0"], x1=self.x[order].copy(), T0=a["T0"],
            T1=self.T[order].copy(), heat_capacity=a["heat_capacity"], type_=a["type_"],
            coef=self.table[:, :, col].copy(),
            wall_type=np.concatenate([pl.type, M.wall_type]).astype(np.int32),
            wall_T=np.concatenate([pl.T, mesh_T]),
            wall_has_T=np.concatenate([pl.has_T, M.wall_has_T]).astype(bool),
            tri_wall=M.tri_wall.astype(np.int64), tri_first=tri_first, n_planes=self._npl,
            dt=self.dt, t0=a["t0"], t1=self.time, model=self.heat or "area")

    def _grow_log(self):
        """Room for the next sample: open contacts and rows at least doubled."""
        lg = self._log
        nc = int(clog.count_contacts(self.particles, self.pairs, self.wall_contacts))
        self._log = clog.grown(lg, max(2 * lg.cur_key.shape[0], 2 * nc),
                               max(2 * lg.row_key.shape[0],
                                   int(lg.ctrl[clog.C_NROWS] + lg.ctrl[clog.C_NOPEN]) + 4 * nc))

    def _advance_time(self, k):
        self.step_count += k
        self.time = self.step_count * self.dt      # not accumulated: no drift

    # ------------------------------------------------------------------ diagnostics
    def kinetic_energy(self, *, rotational=True):
        """Kinetic energy (J) of all particles: translation (+ rotation)."""
        e = 0.5 * float((self.mass * (self.v ** 2).sum(1)).sum())
        if rotational:
            e += 0.5 * float((self._p("inertia") * (self.omega ** 2).sum(1)).sum())
        return e

    def potential_energy(self):
        """Gravitational potential energy -sum m g.x (J) (zero at the origin)."""
        return -float((self.mass * (self.x @ self.g)).sum())

    def momentum(self):
        """Total linear momentum (3,) (kg m/s)."""
        return (self.mass[:, None] * self.v).sum(0)

    def contact_count(self):
        """Number of contacts at the last step (pairs once, plus wall contacts)."""
        if not self._built:
            return 0
        pairs = int(self.pairs.active.sum())
        return pairs + int(self.ncontact.sum()) - 2 * pairs

    def memory_bytes(self):
        """Bytes of all per-particle storage incl. neighbour lists and history."""
        b = sum(arr.nbytes for store in (self._pa, self._wa) for arr in store.values())
        return b + bundle_bytes(self.pairs)

    # ------------------------------------------------------------------ checkpoints
    def state(self):
        """The whole DEM state as plain arrays (for checkpoints; :meth:`set_state`).

        Returns a dict ``{key: numpy array}`` (copies) holding: every field of the five
        bundles (``p.<field>``, ``wc.<field>``, ``pairs.<field>``, ``planes.<field>``,
        ``mesh.<field>``: positions, velocities, the forces and torques of the last step,
        the tangential springs of pair, plane and triangle contacts, the neighbour lists
        they live on, the walls' positions, velocities, omega, centres and accumulators),
        the counters (``time`` s, ``step_count``, ``n_lost``, ``next_id``), the flags of
        the step loop (whether the forces of the last step are valid: forces are NOT
        recomputed on a resume, since recomputing them advances the tangential springs),
        the random generator's bit-generator state (``rng.*``) and each inserter's
        state (``ins<i>.*``). A simulation built the same way (same materials, walls and
        inserters) continues bit-identically after :meth:`set_state`.
        """
        n = self.n
        d = {f"p.{k}": self._pa[k][:n].copy() for k in PARTICLE_FIELDS}
        d.update({f"wc.{k}": self._wa[k][:n].copy() for k in WALL_CONTACT_FIELDS})
        d["wc.overflow"] = self._overflow.copy()
        for prefix, bundle in (("pairs", self.pairs), ("planes", self.plane_state),
                               ("mesh", self.mesh_state)):
            d.update({f"{prefix}.{k}": np.array(a) for k, a in zip(bundle._fields, bundle)})
        d["ids_at_build"] = np.array(getattr(self, "_ids_at_build", np.zeros(0, np.int64)))
        d["scalars"] = np.array([self.time, self.dt], np.float64)
        d["counters"] = np.array([n, self.step_count, self.n_lost, self._next_id,
                                  self.n_rebuilds, self._npl, self._S, len(self.inserters)],
                                 np.int64)
        d["flags"] = np.array([self._need_rebuild, self._forces_valid, self._dt_checked,
                               self._heat_warned, self._built], np.uint8)
        d.update({f"rng.{k}": v for k, v in _rng_state_arrays(self.rng.bit_generator.state).items()})
        for i, ins in enumerate(self.inserters):
            d.update({f"ins{i}.{k}": v for k, v in ins.state().items()})
        if self.radiation is not None:
            d.update(self.radiation.state())
        return d

    def set_state(self, d):
        """Restore :meth:`state` into a simulation built the same way (same materials,
        planes, mesh walls and inserters, in the same order). Nothing is recomputed:
        the next :meth:`step` continues exactly where the saved run stood."""
        if self.contact_logging:
            raise GsiInputError("set_state: a contact log is running; stop_contact_log() "
                                "first (the log is not part of the state)")
        n, step_count, n_lost, next_id, n_rebuilds, npl, S, n_ins = (
            int(v) for v in d["counters"])
        if (npl, S, n_ins, len(self.mesh_state.x), len(self.mesh_state.tri)) != (
                self._npl, self._S, len(self.inserters), len(d["mesh.x"]), len(d["mesh.tri"])):
            raise GsiInputError(
                f"restart: the checkpoint has {npl} planes, {len(d['mesh.tri'])} wall triangles "
                f"and {n_ins} inserters, this case {self._npl}, {len(self.mesh_state.tri)} and "
                f"{len(self.inserters)}; resume with the case that wrote it")
        if float(d["scalars"][1]) != self.dt:
            raise GsiInputError(f"restart: dt = {self.dt} s differs from the checkpoint's "
                                f"{float(d['scalars'][1])} s; resume with the case that wrote it")
        self.n = 0
        self._alloc(max(16, n))
        for k in PARTICLE_FIELDS:
            self._pa[k][:n] = d[f"p.{k}"]
        for k in WALL_CONTACT_FIELDS:
            self._wa[k][:n] = d[f"wc.{k}"]
        self._overflow[:] = d["wc.overflow"]
        self.n = n
        # copies: the run must not write into ``d`` (it may be restored again)
        self.pairs = Pairs(*[np.array(d[f"pairs.{k}"], order="C") for k in Pairs._fields])
        for prefix, bundle in (("planes", self.plane_state), ("mesh", self.mesh_state)):
            for k, a in zip(bundle._fields, bundle):
                a[...] = d[f"{prefix}.{k}"]
        self._ids_at_build = np.array(d["ids_at_build"], np.int64)
        self.time = float(d["scalars"][0])
        self.step_count, self.n_lost, self._next_id = step_count, n_lost, next_id
        self.n_rebuilds = n_rebuilds
        (self._need_rebuild, self._forces_valid, self._dt_checked, self._heat_warned,
         self._built) = (bool(v) for v in d["flags"])
        self.rng.bit_generator.state = _rng_state_from_arrays(
            {k[4:]: v for k, v in d.items() if k.startswith("rng.")})
        for i, ins in enumerate(self.inserters):
            ins.set_state({k[len(f"ins{i}."):]: v for k, v in d.items()
                           if k.startswith(f"ins{i}.")})
        if self.radiation is not None:
            self.radiation.set_state(d)


def _rng_state_arrays(state, prefix=""):
    """A bit generator's state dict as flat arrays: integers as little-endian uint64
    words (``<key>#int``, any size), strings as unicode scalars, arrays as they are."""
    out = {}
    for k, v in state.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_rng_state_arrays(v, key + "/"))
        elif isinstance(v, str):
            out[key] = np.array(v)
        elif isinstance(v, (int, np.integer)):
            v = int(v)
            words = [v & 0xFFFFFFFFFFFFFFFF]
            v >>= 64
            while v:
                words.append(v & 0xFFFFFFFFFFFFFFFF)
                v >>= 64
            out[key + "#int"] = np.array(words, np.uint64)
        else:
            out[key] = np.array(v)
    return out


def _rng_state_from_arrays(arrays):
    """Inverse of :func:`_rng_state_arrays`."""
    state = {}
    for key, v in arrays.items():
        if key.endswith("#int"):
            key = key[:-4]
            v = sum(int(w) << (64 * i) for i, w in enumerate(v))
        elif v.dtype.kind == "U":
            v = str(v)
        node = state
        *parents, leaf = key.split("/")
        for p in parents:
            node = node.setdefault(p, {})
        node[leaf] = v
    return state

def _rows_of(ids, wanted):
    """Rows of ``wanted`` ids in the id array ``ids`` (-1 where absent); ``ids`` are
    unique, sorted or not."""
    wanted = np.asarray(wanted, np.int64)
    if len(ids) == 0:
        return np.full(len(wanted), -1, np.int64)
    order = None if np.all(ids[1:] > ids[:-1]) else np.argsort(ids, kind="stable")
    srt = ids if order is None else ids[order]
    pos = np.minimum(np.searchsorted(srt, wanted), len(srt) - 1)
    rows = pos if order is None else order[pos]
    return np.where(srt[pos] == wanted, rows, -1).astype(np.int64)
