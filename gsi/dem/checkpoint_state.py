"""The whole state of a DEM simulation as plain arrays, for checkpoints (:func:`capture`,
:func:`restore`), with the random generator's state as flat arrays."""
import numpy as np

from gsi.errors import GsiInputError
from gsi.dem.state import Pairs


def rng_state_arrays(state, prefix=""):
    """A bit generator's state dict as flat arrays: integers as little-endian uint64
    words (``<key>#int``, any size), strings as unicode scalars, arrays as they are."""
    out = {}
    for k, v in state.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(rng_state_arrays(v, key + "/"))
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


def rng_state_from_arrays(arrays):
    """Inverse of :func:`rng_state_arrays`."""
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


def capture(sim):
    """The whole DEM state of ``sim`` as plain arrays (for checkpoints; :func:`restore`).

    Returns a dict ``{key: numpy array}`` (copies) holding: every field of the five
    bundles (``p.<field>``, ``wc.<field>``, ``pairs.<field>``, ``planes.<field>``,
    ``mesh.<field>``: positions, velocities, the forces and torques of the last step,
    the tangential springs of pair, plane and triangle contacts, the neighbour lists
    they live on, the walls' positions, velocities, omega, centres and accumulators),
    the counters (``time`` s, ``step_count``, ``n_lost``, ``next_id``), the energy
    book's own accumulators (``energy``: whether the run's audit has started, its
    baseline ``sim.energy_book0`` and the walls' reset heat; ``energy.lost``:
    ``sim.lost_energy``; ``energy.added``: ``sim.added_energy``), the flags of the step
    loop (whether the forces of the last step are valid: forces are NOT
    recomputed on a resume, since recomputing them advances the tangential springs),
    the random generator's bit-generator state (``rng.*``) and each inserter's
    state (``ins<i>.*``), each wall driver's state (``drv<i>``: next update, velocity,
    a free wall's half-step velocity, a servo's gain). A simulation built the same way (same materials, walls and
    inserters) continues bit-identically after :func:`restore`.
    """
    d = sim.store.state()
    for prefix, bundle in (("pairs", sim.pairs), ("planes", sim.plane_state),
                           ("mesh", sim.mesh_state)):
        d.update({f"{prefix}.{k}": np.array(a) for k, a in zip(bundle._fields, bundle)})
    d["ids_at_build"] = np.array(sim.ids_at_build)
    d["scalars"] = np.array([sim.time, sim.dt], np.float64)
    d["list_skin"] = np.array([sim.list_skin], np.float64)
    d["counters"] = np.array([sim.n, sim.step_count, sim.n_lost, sim.next_id,
                              sim.n_rebuilds, sim.n_planes, sim.store.slots,
                              len(sim.inserters)], np.int64)
    d["flags"] = np.array(sim.flags.values(), np.uint8)
    b0 = sim.energy_book0
    d["energy"] = np.array([b0 is not None, b0 or 0.0, sim.walls.heat_reset], np.float64)
    d["energy.lost"] = np.array(sim.lost_energy, np.float64)
    d["energy.added"] = np.array(sim.added_energy, np.float64)
    d.update({f"rng.{k}": v for k, v in rng_state_arrays(sim.rng.bit_generator.state).items()})
    for i, ins in enumerate(sim.inserters):
        d.update({f"ins{i}.{k}": v for k, v in ins.state().items()})
    if sim.radiation is not None:
        d.update(sim.radiation.state())
    for i, drv in enumerate(sim.drivers.items):       # walls that respond
        d[f"drv{i}"] = drv.state()
    return d


def restore(sim, d):
    """Restore :func:`capture` into a simulation built the same way (same materials,
    planes, mesh walls and inserters, in the same order)."""
    if sim.contact_logging:
        raise GsiInputError("set_state: a contact log is running; stop_contact_log() "
                            "first (the log is not part of the state)")
    n, step_count, n_lost, next_id, n_rebuilds, npl, S, n_ins = (
        int(v) for v in d["counters"])
    if (npl, S, n_ins, len(sim.mesh_state.x), len(sim.mesh_state.tri)) != (
            sim.n_planes, sim.store.slots, len(sim.inserters), len(d["mesh.x"]),
            len(d["mesh.tri"])):
        raise GsiInputError(
            f"restart: the checkpoint has {npl} planes, {len(d['mesh.tri'])} wall triangles "
            f"and {n_ins} inserters, this case {sim.n_planes}, {len(sim.mesh_state.tri)} "
            f"and {len(sim.inserters)}; resume with the case that wrote it")
    if float(d["scalars"][1]) != sim.dt:
        raise GsiInputError(f"restart: dt = {sim.dt} s differs from the checkpoint's "
                            f"{float(d['scalars'][1])} s; resume with the case that wrote it")
    sim.store.set_state(d, n)
    # copies: the run must not write into ``d`` (it may be restored again)
    sim.pairs = Pairs(*[np.array(d[f"pairs.{k}"], order="C") for k in Pairs._fields])
    for prefix, bundle in (("planes", sim.plane_state), ("mesh", sim.mesh_state)):
        for k, a in zip(bundle._fields, bundle):
            # accumulators added later (frictional heat, wall work) start at 0
            a[...] = d.get(f"{prefix}.{k}", 0.0)
    sim.ids_at_build = np.array(d["ids_at_build"], np.int64)
    sim.time = float(d["scalars"][0])
    # the skin of the restored lists (checkpoints before the adaptive skin: the fixed one)
    sim.list_skin = float(d["list_skin"][0]) if "list_skin" in d else sim.skin
    sim.step_count, sim.n_lost, sim.next_id = step_count, n_lost, next_id
    sim.n_rebuilds = n_rebuilds
    sim.flags.set_values(bool(v) for v in d["flags"])
    # the energy book (checkpoints before it: a new baseline at the first audit)
    has_b0, b0, sim.walls.heat_reset = (float(v) for v in d.get("energy", (0, 0, 0)))
    sim.energy_book0 = b0 if has_b0 else None
    sim.lost_energy[:] = d.get("energy.lost", 0.0)
    sim.added_energy[:] = d.get("energy.added", 0.0)
    sim.rng.bit_generator.state = rng_state_from_arrays(
        {k[4:]: v for k, v in d.items() if k.startswith("rng.")})
    for i, ins in enumerate(sim.inserters):
        ins.set_state({k[len(f"ins{i}."):]: v for k, v in d.items()
                       if k.startswith(f"ins{i}.")})
    if sim.radiation is not None:
        sim.radiation.set_state(d)
    for i, drv in enumerate(sim.drivers.items):
        if f"drv{i}" in d:
            drv.set_state(d[f"drv{i}"])
