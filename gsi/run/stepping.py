"""The DEM's steps of one chunk in blocks of about :data:`TARGET_SECONDS` of wall time.

A chunk (the steps between two events: outputs, samples, coupling ends, ...) can be hours
of wall time when the output interval is long and dt small. The runner hands the DEM
(rank 0) one block of steps at a time and, between blocks, every rank learns in one
small allreduce whether a signal came (then the run checkpoints at that step and
stops, see :class:`gsi.run.checkpoints.Checkpointer`), whether the wall-clock
checkpoint is due, whether the DEM failed, and the step reached. So SIGINT/SIGTERM are
honoured within about one block plus the checkpoint write, whatever the output
interval.

The split does not change the results: each ``Simulation.step(n)`` call ends on a
complete step (forces of the current positions, no drifted step pending; the engine's
fused "end of step s, start of step s + 1" is bitwise the same arithmetic as ending a
call and starting the next one), so ``step(a); step(b)`` is bit-identical to
``step(a + b)`` -- tested in tests/reliability/test_stop.py.

Block size: the measured wall time per step of the last block sets the next one
(``TARGET_SECONDS`` / (s per step)); it grows at most fourfold per block (a first
block that compiled the engine or a step without particles says little) and starts
at one step.
"""
from __future__ import annotations

import math
import time

TARGET_SECONDS = 0.25      # wall time per block (s): the stop latency is about this
GROWTH = 4                 # a block is at most this many times the last one


class StepBlocks:
    """Sizes of the DEM's step calls (rank 0; see the module docstring)."""

    def __init__(self, target: float = TARGET_SECONDS):
        self.target = float(target)
        self.n = 1
        self.blocks = 0            # step calls made

    def next(self, remaining: int) -> int:
        """Steps of the next block (at most ``remaining``)."""
        return max(1, min(int(remaining), self.n))

    def measured(self, n: int, seconds: float) -> None:
        """A block of ``n`` steps took ``seconds`` of wall time."""
        self.blocks += 1
        per = seconds / max(n, 1)
        ideal = self.target / per if per > 0 else math.inf
        self.n = int(max(1, min(ideal, GROWTH * max(self.n, n), 1e12)))

    def step(self, sim, remaining: int) -> int:
        """Run one block of at most ``remaining`` steps of ``sim``; returns its size."""
        n = self.next(remaining)
        t0 = time.perf_counter()
        sim.step(n)
        self.measured(n, time.perf_counter() - t0)
        return n
