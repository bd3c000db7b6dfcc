"""Ensembles for the chaotic validation cases (issue 32).

A granular flow is chaotic: a change in the last bit of one position (another CPU's
floating-point summation order, another thread count) grows to a different trajectory
within a fraction of a second. A test that asserts on one trajectory then passes or fails
on round-off. The chaotic cases are therefore judged by an *ensemble*: ``M`` realisations
of the same case that differ only in their start positions, member ``k`` having every
particle moved by ``k`` x 0.5 nm times a uniform random number in [-1, 1] per coordinate
(:func:`gsi.studies.ensemble.perturb`: generator ``k``; member 0 is the case as it is;
quasi-2D cases move in their plane only), far below any physical scale (particle radii
are millimetres) yet far above round-off, so the members are independent samples of the
flow. The members run side by side, one per core (:func:`gsi.studies.ensemble.
run_ensemble`: spawned workers, one numba thread each; a member's result is bitwise the
one it gives in-process), so a member function and what it returns must be picklable: a
module-level function returning plain arrays.

A claim "q <= bound" holds when the ensemble mean plus three standard errors is below
the bound, mean + 3 SE <= bound (and "q >= bound" when mean - 3 SE >= bound), with
SE = max(sd, sd_floor)/sqrt(M), sd the members' sample standard deviation. With three to
five members the sample sd is itself uncertain (with M = 3 it falls below a third of the
true spread about one time in ten), so each test gives a floor ``sd_floor``: the spread of
that quantity measured once on a larger ensemble (the members of the test plus those of
the same test run with dt x (1 + 1e-12)), written beside the test with the date.

``GSI_TEST_DT_SCALE`` (environment; default 1): every ensemble case runs with its time
step multiplied by it. ``GSI_TEST_DT_SCALE=1.000000000001`` changes nothing but the
floating-point round-off of every step (summation order and last bits), so each member
takes another trajectory; the ensemble tests must pass either way (the check that they
do not hang on one trajectory; docs/design.md, "Chaotic cases: ensembles").
"""
from __future__ import annotations

import dataclasses
import math
import os
import types
from dataclasses import dataclass

import numpy as np
import pytest

from gsi.run import Runner
from gsi.studies.ensemble import SHIFT, perturb, run_ensemble

#: time-step factor of the ensemble cases (see the module docstring)
DT_SCALE = float(os.environ.get("GSI_TEST_DT_SCALE", "1"))


@dataclass(frozen=True)
class Stat:
    """Ensemble statistics of one quantity (or an array of them, per entry)."""

    mean: np.ndarray
    sd: np.ndarray
    se: np.ndarray
    members: int

    def upper(self, z: float = 3.0):
        return self.mean + z * self.se

    def lower(self, z: float = 3.0):
        return self.mean - z * self.se

    def text(self, fmt: str = ".3g") -> str:
        m, s = np.atleast_1d(self.mean), np.atleast_1d(self.se)
        return ", ".join(f"{a:{fmt}} +- {b:{fmt}}" for a, b in zip(m, s)) + \
            f" (M = {self.members}, mean +- SE)"


def ensemble_stat(values, sd_floor=0.0) -> Stat:
    """Mean, sample sd and standard error over the members (axis 0) of ``values``; the
    sd used for the SE is at least ``sd_floor`` (see the module docstring)."""
    v = np.asarray(values, float)
    M = v.shape[0]
    sd = v.std(axis=0, ddof=1) if M > 1 else np.zeros(v.shape[1:])
    se = np.maximum(sd, sd_floor) / math.sqrt(M)
    return Stat(mean=v.mean(axis=0), sd=sd, se=se, members=M)


def with_dt_scale(case):
    """``case`` (a validated :class:`gsi.case.Case`) with its time step times
    :data:`DT_SCALE` (unchanged for 1)."""
    if DT_SCALE == 1.0:
        return case
    dt = case.check()
    case.run = dataclasses.replace(case.run, dt=dt * DT_SCALE)
    return case


class PerturbedRunner(Runner):
    """The runner of member ``k``: the case's start positions moved by :func:`perturb`
    after the set-up (a test-side hook; the library is unchanged)."""

    def __init__(self, case, *, member: int, plane: str = "xyz", **kw):
        super().__init__(case, **kw)
        self.case = with_dt_scale(self.case)        # after the quick variant
        self.member = member
        self.plane = plane

    def setup(self) -> None:
        super().setup()
        if self.sim is not None:
            perturb(self.sim.x, self.member, self.plane)


def _case_member(i, specs, out, plane, extract, keep, kw):
    """Run ``specs[i]`` = (case, member k, directory) by a :class:`PerturbedRunner` in
    ``out``/directory: the runner itself if ``i`` is in ``keep`` (run in the test's own
    process), else ``extract(runner)`` (what the test needs, picklable)."""
    case, k, name = specs[i]
    r = PerturbedRunner(case, member=k, plane=plane, out=out / name, pictures=False,
                        verbose=False, **kw)
    r.result = r.run()
    return r if i in keep else extract(r)


def run_cases(specs, out, *, plane="xyz", extract=None, keep=(), workers=None, **kw) -> list:
    """Run the members ``specs`` = [(case, k, directory), ...] (member ``k``'s start
    perturbation) side by side (:func:`gsi.studies.ensemble.run_ensemble`), several
    ensembles in one pool if the specs hold several cases. Entry ``i`` returns
    ``extract(runner)`` (a module-level function of the test module; picklable output),
    or for ``i`` in ``keep`` its run :class:`PerturbedRunner` (``.result``), run in this
    process; without ``extract`` every member runs here, one after the other."""
    specs = list(specs)
    if extract is None:
        keep, workers = tuple(range(len(specs))), 1
    return run_ensemble(_case_member, len(specs), args=(specs, out, plane, extract,
                                                        tuple(keep), kw),
                        here=tuple(keep), workers=workers)


def run_members(case_factory, out, members: int, **kw) -> list:
    """:func:`run_cases` of ``members`` realisations of ``case_factory()`` (a fresh case
    per member) in ``out``/m<k>."""
    return run_cases([(case_factory(), k, f"m{k}") for k in range(members)], out, **kw)


@pytest.fixture(scope="session")
def ens():
    """The helpers of this module for the test modules (which cannot import a conftest
    under ``--import-mode=importlib``): ``ens.stat``, ``ens.perturb``, ``ens.run_members``,
    ``ens.run_cases``, ``ens.run_ensemble``,
    ``ens.with_dt_scale``, ``ens.DT_SCALE``, ``ens.SHIFT``."""
    return types.SimpleNamespace(stat=ensemble_stat, perturb=perturb, run_members=run_members,
                                 run_cases=run_cases,
                                 run_ensemble=run_ensemble, with_dt_scale=with_dt_scale,
                                 DT_SCALE=DT_SCALE, SHIFT=SHIFT)
