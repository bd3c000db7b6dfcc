"""The step loop of a DEM simulation (:meth:`gsi.dem.Simulation.step`): ``n`` steps as
compiled chunks of the engine's ``advance``, stopping between chunks only to insert
particles, to apply radiation, to rebuild the neighbour lists, to delete lost particles
or to grow the contact log (the engine's stop codes: :class:`gsi.dem.step_codes.StepCode`).

It drives a simulation through its public methods and state (``sim.engine``,
``sim.bundles()``, ``sim.flags``, ``sim.rebuild_lists()``, ``sim.advance_idle()``, ...);
the time-step and heat-stability checks (:mod:`gsi.dem.checks`) run here, when the
particles or the lists change.

A mesh wall moved between steps (``MeshWall.set_vertices``, e.g. by a coupled
structure) is seen by the next step; the loop rebuilds the candidate lists first if a
vertex moved more than half the skin (``sim.wall_moved()``). The forces of the last step
are NOT evaluated again: a force evaluation advances every tangential spring by its
increment, so a second one at the same time level would count that increment twice (and
a coupled structure's interval boundary would perturb every contact in the DEM). The
moved wall enters the next step's force pass: a lag of one DEM step, the staggered
scheme's own.
"""
import warnings

import numba

from gsi.errors import GsiInputError
from gsi.dem import checks
from gsi.dem import contact_log as clog
from gsi.dem.state import MAX_WALL_SLOTS
from gsi.dem.step_codes import StepCode, blow_up, lost_particles
from gsi.dem.wall_drivers import bed_of


def run(sim, n):
    """Advance ``sim`` by ``n`` steps, on one thread below ``sim.parallel_min_n``
    particles."""
    if n < 0:
        raise GsiInputError(f"step n = {n}: must be >= 0")
    sim.wall_moved()                  # mesh walls set between the calls
    threads = numba.get_num_threads()
    if sim.n < sim.parallel_min_n:
        numba.set_num_threads(1)
    try:
        _chunks(sim, int(n))
    finally:
        numba.set_num_threads(threads)


def run_inserters(sim):
    """Add the particles every inserter of ``sim`` has due by now (the inserter places,
    the simulation adds; :class:`gsi.dem.insertion.Inserter`); returns how many."""
    added = 0
    for ins in sim.inserters:
        x, r = ins.place(sim.time, sim.rng, sim.x, sim.radius)
        ids = (sim.add_particles(x, r, material=ins.material, v=ins.velocity, T=ins.T)
               if len(r) else ())
        ins.inserted(ids)
        added += len(ids)
    return added


def _chunks(sim, remaining):
    vmax2 = sim.v_max ** 2
    skip = False
    while remaining > 0:
        if not skip:
            run_inserters(sim)
        if sim.n == 0 and not skip:
            chunk = min([remaining] + [i.steps_to_next(sim.time, sim.dt) for i in sim.inserters])
            sim.advance_idle(chunk)
            remaining -= chunk
            continue
        if skip:
            sim.rebuild_lists()
            check_heat(sim)
        else:
            prepare(sim)
        chunk = min([remaining] + [i.steps_to_next(sim.time, sim.dt) for i in sim.inserters])
        if sim.radiation is not None:     # applied at T_n over its interval
            chunk = min(chunk, sim.radiation.step_due(sim.step_count, sim.dt,
                                                      force_dt=sim.force_dt))
        if sim.drivers:                   # walls that respond: up to their next update
            due = (sim.drivers.steps_due(sim.step_count) if skip   # (a resumed step has
                   else sim.drivers.drive(sim.step_count, sim.time, sim.dt, bed_of(sim)))
            chunk = min(chunk, due)                                  # moved its walls)
        sim.log.state.ctrl[clog.C_STEP] = sim.step_count
        half_skin2 = (0.5 * sim.list_skin) ** 2
        done, code, info = sim.engine.advance(chunk, skip, sim.dt, sim.g, half_skin2, vmax2,
                                              sim.lo, sim.hi, *sim.bundles(), sim.table,
                                              sim.log.state)
        sim.advance_idle(done)
        remaining -= done
        skip = after_chunk(sim, StepCode(code), info)
        if sim.store.overflow[0]:
            sim.store.overflow[0] = 0
            warnings.warn(f"more than {MAX_WALL_SLOTS} triangle contacts on one particle; "
                          "extra ones ignored")


def prepare(sim):
    """Before a chunk: check the time step (new particles), rebuild the lists if due
    (and check the heat stability), evaluate the forces if the state changed."""
    if sim.n and not (sim.flags.dt_checked or sim.dt_rule_applied):
        sim.flags.dt_checked = True
        checks.check_dt(sim)
    if sim.flags.need_rebuild or not sim.flags.built:
        sim.rebuild_lists()
        check_heat(sim)
    if not sim.flags.forces_valid:
        sim.engine.compute_forces(sim.g, *sim.bundles(), sim.table)
        sim.flags.forces_valid = True


def heat_stability(sim):
    """max_i dt sum_j H_ij/(m_i c_p,i) of ``sim`` (the lists built first if due): the
    explicit heat update is stable below 1."""
    if sim.heat is None or sim.n == 0:
        return 0.0
    sim.wall_moved()
    if sim.flags.need_rebuild or not sim.flags.built:
        sim.rebuild_lists()
    Hs = sim.engine.heat_conductance_sum(*sim.bundles(), sim.table)
    return float((sim.dt * Hs * sim.particles.mcp_inv).max())


def check_heat(sim):
    """The explicit heat update's stability check (:func:`gsi.dem.checks.check_heat`)."""
    if sim.heat is None:
        return
    sim.flags.heat_warned = checks.check_heat(sim.heat_stability(), sim.step_count,
                                              force=sim.force_dt, warned=sim.flags.heat_warned)


def after_chunk(sim, code, info):
    """Act on the engine's stop ``code``; returns whether the next chunk resumes the
    drifted step (``skip_first_drift``)."""
    if code == StepCode.REBUILD:
        return True
    if code == StepCode.LOG_FULL:          # grow the log, take the sample
        sim.log.grow(sim.particles, sim.pairs, sim.wall_contacts)
        clog.sample(*sim.bundles(), sim.log.state)
    elif code == StepCode.LOST:
        sim.remove_particles(lost_particles(sim), lost=True)
        return True
    elif code == StepCode.BLOW_UP:
        raise blow_up(sim, int(info))
    return False
