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
    from gsi.dem.wall_drivers import Oscillation, Servo, FreeWall   # walls that respond
    sim.drivers.add(Servo(floor, target=2e3, area=0.01, max_speed=0.05))  # 2 kPa on 0.01 m^2
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
build; ``sim.index(ids)`` maps ids to rows.  ``sort_particles`` re-orders the rows into
the order the force pass visits them (slab by slab, cell by cell): memory is then read
nearly in sequence (measured on the settle bed, 1 thread: +10 % at 20k particles, +20 %
at 200k, 3.9x against a random order); ``sim.ids`` is then not sorted.

Choices made here (time step, heat stability, radiation, lost particles, fixed
particles): see :mod:`gsi.dem.checks`.

State: five bundles (:mod:`gsi.dem.state`; see :mod:`gsi.dem.storage`); also
``sim.heat_capacity`` (J/K), ``sim.material_names``, ``sim.material_index(name)``.
The energy book (:mod:`gsi.dem.energy`) keeps three things here, both in checkpoints:
``sim.lost_energy`` (J, by :data:`gsi.dem.energy.LOST_PARTS`), what the particles removed
so far carried (``remove_particles`` books it, :func:`gsi.dem.energy.particle_energy`:
particles lost from the domain, ``lost=True``, counted in ``n_lost``, are removed
mid-step, in the step the loop stopped in, after its drift; those removed by the user
between steps as they are), ``sim.added_energy``, what the particles added so far brought in (``add_particles``), and
``sim.energy_book0`` (J), the start of the run's audit
(:meth:`gsi.dem.energy.EnergyAudit.of_run`; None until its first sample).

Collaborators (each with public methods; the simulation composes them):
:class:`gsi.dem.storage.ParticleStore` (the per-particle arrays; its views
:class:`~gsi.dem.storage.ParticleViews`),
:class:`gsi.dem.wall_registry.Walls` (planes, mesh walls and their bundles; its views
:class:`~gsi.dem.wall_registry.WallViews`),
:func:`gsi.dem.lists.build_lists` (the neighbour lists),
:mod:`gsi.dem.step_loop` (the step loop: compiled chunks and what happens between them),
:class:`gsi.dem.log_control.ContactLogControl` (the contact log),
:mod:`gsi.dem.checks` (the options, the time-step and heat-stability checks) and
:mod:`gsi.dem.checkpoint_state` (the whole state as arrays).
The engine (``sim.engine``, :func:`gsi.dem.engine.get_engine`) is called from
:mod:`gsi.dem.step_loop` only: ``advance`` (its codes named by
:class:`~gsi.dem.step_codes.StepCode`), ``compute_forces`` and ``heat_conductance_sum``.

How it runs (engines, the chunked step loop, threads): see :mod:`gsi.dem.lists`.
"""
import numpy as np

from gsi.dem.material_set import MaterialSet
from gsi.dem.engine import get_engine
from gsi.dem import checks, step_loop
from gsi.dem.checkpoint_state import capture, restore
from gsi.dem.energy import new_flows, particle_energy
from gsi.dem.insertion import Inserter
from gsi.dem.lists import adaptive_skin, build_lists
from gsi.dem.log_control import ContactLogControl
from gsi.dem.radiation import Radiation, emissivity_by_type
from gsi.dem.state import FRICTION_FIELDS, empty_pairs
from gsi.dem.step_codes import StepFlags
from gsi.dem.storage import ParticleStore, ParticleViews
from gsi.dem.wall_drivers import WallDrivers
from gsi.dem.wall_registry import Walls, WallViews
from gsi.dem.walls import MeshWall, vec3


class Simulation(ParticleViews, WallViews):
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
        Contact conduction model (:mod:`gsi.dem.contact.conductance`); None: no heat.
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
        pass visits them (module docstring): rows then change at every build.
    skin_max : float, optional
        Largest skin (m) of the adaptive skin (:func:`gsi.dem.lists.adaptive_skin`);
        default: the skin is fixed at ``skin``.
    frictional_heating : bool, default False
        Dissipated contact energy heats both bodies (:mod:`gsi.dem.contact.dissipation`).
    """

    def __init__(self, materials, *, contact="hertz", rolling=False, heat=None, h_c=None,
                 pipe_length=None, pipe_resistance=0.0, k_n=None, gravity=(0.0, 0.0, -9.81),
                 dt, skin, domain, force_dt=False, v_max=100.0, lost="delete",
                 pair_overrides=None, seed=None, parallel_min_n=2000, sort_particles=False,
                 dt_checked=False, skin_max=None, frictional_heating=False):
        lo, hi = checks.check_options(materials, dt, skin, contact, k_n, heat, h_c, pipe_length,
                                      pipe_resistance, lost, domain)
        self.material_set = MaterialSet(materials, k_n=k_n, h_c=h_c, pipe_length=pipe_length,
                                        pipe_resistance=pipe_resistance,
                                        pair_overrides=pair_overrides)
        self.materials, self.table = self.material_set.materials, self.material_set.table
        self.frictional_heating = fh = bool(frictional_heating)   # engines: :attr:`engine`
        self._engines = tuple(get_engine(contact, rolling, heat, lg, fh) for lg in (False, True))
        self.contact, self.rolling, self.heat = contact, rolling, heat
        self.k_n, self.h_c = k_n, h_c
        self.g = vec3(gravity, "gravity")
        self.dt, self.skin = float(dt), float(skin)
        # skin of the current lists, in [skin, skin_max] (None: fixed): lists.adaptive_skin
        self.skin_max = self.skin if skin_max is None else max(float(skin_max), self.skin)
        self.list_skin = self.skin
        self.lo, self.hi = lo, hi
        self.force_dt, self.v_max, self.lost = force_dt, float(v_max), lost
        self.rng = np.random.default_rng(seed)
        self.parallel_min_n = int(parallel_min_n)
        self.sort_particles = bool(sort_particles)
        self.time = 0.0
        self.step_count = 0
        self.n_lost = 0
        self.lost_energy, self.added_energy, self.energy_book0 = new_flows()
        self.next_id = 0                # the id the next particle gets
        self.store = ParticleStore(16, unused=() if fh else FRICTION_FIELDS)
        self.walls = Walls(self.store)
        self.drivers = WallDrivers()      # walls that respond: sim.drivers.add(driver)
        self.pairs = empty_pairs(0)
        self.inserters = []
        self.n_rebuilds = 0
        self.radiation = None
        self.log = ContactLogControl()
        self.ids_at_build = np.zeros(0, np.int64)     # particle ids at the last list build
        self.flags = StepFlags()
        self.dt_rule_applied = bool(dt_checked)     # the caller applied the time-step rule

    @property
    def engine(self):
        """The compiled engine of this simulation's laws (:func:`gsi.dem.engine.get_engine`),
        its logging variant while a contact log runs."""
        return self._engines[self.log.running]

    # ------------------------------------------------------------------ state bundles
    def bundles(self):
        """The engine's state arguments ``(P, pairs, pl, M, wc)``."""
        return (self.particles, self.pairs, self.plane_state, self.mesh_state,
                self.wall_contacts)

    @property
    def material_names(self):
        """Material names in index order (the particle ``type`` and pair-table rows)."""
        return list(self.material_set.names)

    def material_index(self, name, key="material"):
        """Index of material ``name`` (its value in ``sim.type``); an unknown name is a
        one-line error naming ``key``."""
        return self.material_set.index(name, key)

    # ------------------------------------------------------------------ particles
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
        x, r = checks.check_particles(x, radius, self.lo, self.hi)
        t = self.material_index(material, "particles.material")
        mat = self.materials[material]
        ids = self.store.add_spheres(x, r, mtype=t, rho=mat.rho, cp=mat.cp, v=v, T=T,
                                     omega=omega, first_id=self.next_id)
        self.next_id += len(x)
        self.added_energy += particle_energy(self, self.ids >= self.next_id - len(x))
        self.flags.changed()
        self.flags.dt_checked = False
        return ids

    def fix(self, ids, fixed=True):
        """Hold particles in place (they still feel forces and exchange heat)."""
        self.store.particle["fixed"][self.index(ids)] = 1 if fixed else 0

    def remove_particles(self, mask, *, lost=False):
        """Remove the particles where ``mask`` (n,) is true (``lost``: module docstring)."""
        mask = np.asarray(mask, bool)
        self.lost_energy += particle_energy(self, mask, mid_step=lost)
        self.n_lost += int(mask.sum()) if lost else 0
        self.store.delete(mask)
        self.flags.need_rebuild = True

    # ------------------------------------------------------------------ walls
    def add_plane(self, point, normal, *, material, temperature=None, velocity=(0.0, 0.0, 0.0)):
        """Add an infinite plane through ``point`` (m) with unit ``normal`` into the domain.

        Returns
        -------
        PlaneWall
        """
        t = self.material_index(material, "plane.material")
        wall = self.walls.add_plane(point, normal, mtype=t, material=material,
                                    temperature=temperature, velocity=velocity)
        self.flags.changed()                  # the plane candidates of the particles
        return wall

    def add_mesh_wall(self, vertices, triangles=None, *, material=None, vertex_temperature=None):
        """Add a triangle-mesh wall (arrays, or a :class:`MeshWall`).

        Returns
        -------
        MeshWall
        """
        wall = vertices if isinstance(vertices, MeshWall) else MeshWall(
            vertices, triangles, material=material, vertex_temperature=vertex_temperature)
        t = self.material_index(wall.material, "mesh_wall.material")
        self.walls.add_mesh_wall(wall, mtype=t)
        self.flags.changed()
        return wall

    def add_mesh_wall_file(self, path, *, material, scale=1.0, vertex_temperature=None):
        """Add a mesh wall read from a file with meshio (see :meth:`MeshWall.from_file`)."""
        return self.add_mesh_wall(MeshWall.from_file(path, material=material, scale=scale,
                                                     vertex_temperature=vertex_temperature))

    def wall_moved(self):
        """Rebuild the candidate lists before the next step if a mesh-wall vertex moved
        more than half the skin since the last build (``set_vertices`` between steps; the
        step loop asks at every :meth:`step`, see :mod:`gsi.dem.step_loop`)."""
        if self.walls.moved_beyond(0.5 * self.list_skin):
            self.flags.need_rebuild = True

    # ------------------------------------------------------------------ inserters
    def add_inserter(self, region, rate, *, radius, material, velocity=(0.0, 0.0, 0.0),
                     max_count=None, T=None, start=None):
        """Continuous insertion (see :class:`gsi.dem.insertion.Inserter`)."""
        self.material_index(material, "inserter.material")
        self.inserters.append(Inserter(region, rate, radius=radius, material=material,
                                       velocity=velocity, max_count=max_count, T=T,
                                       start=self.time if start is None else start))
        return self.inserters[-1]

    def set_radiation(self, emissivity, *, cutoff=None, every=1, T_enclosure=None):
        """Turn on particle radiation (:class:`gsi.dem.radiation.Radiation`: emissivity by
        material name, cut-off c (-, default 1.5), an evaluation every ``every`` steps,
        an optional enclosure temperature T_enclosure (K)). Returns the model."""
        self.radiation = Radiation(self.store, self.walls, domain=(self.lo, self.hi),
                                   eps_type=emissivity_by_type(emissivity, self.material_names),
                                   cutoff=cutoff, every=every, T_enclosure=T_enclosure)
        return self.radiation

    # ------------------------------------------------------------------ checks
    def rayleigh_time(self):
        """min over particles of the Rayleigh time t_R (s) (inf without particles)."""
        return self.material_set.rayleigh_time(self.radius, self.type)

    def heat_stability(self):
        """max_i dt sum_j H_ij/(m_i c_p,i): the explicit heat update is stable below 1."""
        return step_loop.heat_stability(self)

    # ------------------------------------------------------------------ neighbour lists
    def rebuild_lists(self):
        """Build the neighbour lists now (the step loop does it when a particle or a wall
        vertex moved more than half the skin); the tangential springs carry over."""
        self.list_skin = adaptive_skin(self.skin, self.skin_max, self.dt, self.v,
                                       self.plane_state.velocity, self.mesh_state.v)
        self.pairs, self.ids_at_build = build_lists(
            self.store, self.walls, self.pairs, self.ids_at_build if self.flags.built else None,
            lo=self.lo, hi=self.hi, skin=self.list_skin, parallel_min_n=self.parallel_min_n,
            sort_particles=self.sort_particles)
        self.flags.built = True
        self.flags.need_rebuild = False
        self.n_rebuilds += 1

    # ------------------------------------------------------------------ stepping
    def step(self, n=1):
        """Advance ``n`` time steps (inserters run at their due steps; the loop:
        :mod:`gsi.dem.step_loop`)."""
        step_loop.run(self, n)

    def advance_idle(self, k):
        """Count ``k`` steps as done (the clock only; the engine has run them, or there
        was nothing to move)."""
        self.step_count += k
        self.time = self.step_count * self.dt      # not accumulated: no drift

    # ------------------------------------------------------------------ contact log
    @property
    def contact_logging(self):
        """Whether a contact log is being recorded (:meth:`start_contact_log`)."""
        return self.log.running

    def start_contact_log(self, *, every=1, dt_split=None, capacity=None):
        """Record every contact from now (t0) until :meth:`stop_contact_log` (t1): every
        ``every`` steps, contacts longer than ``dt_split`` (s) split, ``capacity`` rows
        reserved (see :meth:`gsi.dem.log_control.ContactLogControl.start`)."""
        self.log.start(self.particles, time=self.time, step_count=self.step_count, dt=self.dt,
                       heat=self.heat, n_planes=self.n_planes, every=every,
                       dt_split=dt_split, capacity=capacity)

    def stop_contact_log(self):
        """End the log started by :meth:`start_contact_log` (now is t1); returns the
        :class:`gsi.dem.contact_log.ContactLog`."""
        return self.log.stop(self.particles, self.walls, time=self.time, dt=self.dt,
                             heat=self.heat, table=self.table)

    # ------------------------------------------------------------------ diagnostics
    def contact_count(self):
        """Number of contacts at the last step (pairs once, plus wall contacts)."""
        if not self.flags.built:
            return 0
        pairs = int(self.pairs.active.sum())
        return pairs + int(self.ncontact.sum()) - 2 * pairs

    def memory_bytes(self):
        """Bytes of all per-particle storage incl. neighbour lists and history."""
        return self.store.nbytes(self.pairs)

    # ------------------------------------------------------------------ checkpoints
    def state(self):
        """The whole DEM state as plain arrays (for checkpoints; :meth:`set_state`); see
        :func:`gsi.dem.checkpoint_state.capture`."""
        return capture(self)

    def set_state(self, d):
        """Restore :meth:`state` into a simulation built the same way (same materials,
        planes, mesh walls and inserters, in the same order). Nothing is recomputed:
        the next :meth:`step` continues exactly where the saved run stood."""
        restore(self, d)
