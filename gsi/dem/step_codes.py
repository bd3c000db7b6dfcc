"""The step loop's vocabulary: :class:`StepCode` (why the engine's ``advance`` stopped),
:class:`StepFlags` (the loop's state flags), and the verdicts on lost and blown-up
particles."""
import enum

import numpy as np

from gsi.errors import GsiRunError

#: a step in which more than this fraction of the particles (and at least RUNAWAY_MIN)
#: leave the domain stops the run: that is a blow-up, not an outflow
RUNAWAY_FRACTION = 0.5
RUNAWAY_MIN = 10


class StepCode(enum.IntEnum):
    """What the engine's ``advance`` stopped for (its bare return codes, named)."""

    DONE = 0            # all steps done
    REBUILD = 1         # the lists need a rebuild (the last step drifted: resume skipping it)
    LOST = 2            # particles left the domain (same resume)
    BLOW_UP = 3         # a particle's speed is NaN or above v_max
    LOG_FULL = 4        # the contact log has no room for this step's sample


class StepFlags:
    """The step loop's flags (part of the checkpoint state, in this order)."""

    NAMES = ("need_rebuild", "forces_valid", "dt_checked", "heat_warned", "built")

    def __init__(self):
        self.need_rebuild = True      # the neighbour lists are out of date
        self.forces_valid = False     # the forces of the last step are those of the state
        self.dt_checked = False       # the time-step rule has seen every particle
        self.heat_warned = False      # the heat-stability warning was given
        self.built = False            # the neighbour lists have been built once

    def changed(self):
        """Particles or walls were added: the lists and the forces are out of date."""
        self.need_rebuild = True
        self.forces_valid = False

    def values(self):
        return [getattr(self, k) for k in self.NAMES]

    def set_values(self, values):
        for k, v in zip(self.NAMES, values):
            setattr(self, k, bool(v))


def lost_particles(sim):
    """The mask of the particles outside the domain (a GsiRunError with ``lost="error"``
    or on a runaway loss)."""
    out = ((sim.x < sim.lo) | (sim.x > sim.hi)).any(1)
    if sim.lost == "error":
        i = int(np.flatnonzero(out)[0])
        raise GsiRunError(
            f"particle id {int(sim.ids[i])} left the domain at step {sim.step_count} "
            f"(x = {sim.x[i].tolist()}); enlarge domain or add walls")
    n_out = int(out.sum())
    if n_out >= RUNAWAY_MIN and n_out > RUNAWAY_FRACTION * sim.n:
        speed = float(np.linalg.norm(sim.v[out], axis=1).max())
        raise GsiRunError(
            f"runaway loss at step {sim.step_count}: {n_out} of {sim.n} particles "
            f"left the domain in one step (fastest {speed:.3g} m/s); likely cause: "
            f"dt = {sim.dt} s too large for the stiffness (Rayleigh time "
            f"{sim.rayleigh_time():.3g} s), overlapping particles, or a missing "
            f"wall")
    return out


def blow_up(sim, i):
    """The error of particle row ``i``'s blow-up."""
    return GsiRunError(
        f"blow-up at step {sim.step_count}: particle id {int(sim.ids[i])} has "
        f"velocity {sim.v[i].tolist()} m/s (NaN or above v_max = {sim.v_max}); "
        f"likely cause: dt = {sim.dt} s too large for the stiffness (Rayleigh time "
        f"{sim.rayleigh_time():.3g} s) or overlapping initial particles")
