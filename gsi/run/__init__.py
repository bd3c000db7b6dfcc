"""Running a case: the time loop and its collaborators.

* :mod:`gsi.run.runner`: :class:`Runner`, the event loop (DEM chunks between events,
  structures' coupling intervals, wall motions, monitors, outputs, checkpoints);
* :func:`build_simulation` (from :mod:`gsi.case.build_dem`): the DEM of a case;
* :mod:`gsi.run.outputs`, :mod:`gsi.run.pictures`, :mod:`gsi.run.outdir`: output series,
  pictures, the output directory; :mod:`gsi.run.lock`: the directory's lock (one run
  at a time);
* :mod:`gsi.run.checkpoints`: :class:`Checkpointer`, checkpoint and restart;
  :mod:`gsi.run.stepping`: the DEM's steps in blocks (a signal is honoured within one);
* :mod:`gsi.run.result`: :class:`RunResult`, the summary, :class:`RunInterrupted`;
* :mod:`gsi.run.api`: :func:`run_case`, :func:`demo_main`; :mod:`gsi.run.cli`: the
  ``gsi`` command.
"""
from gsi.run.api import demo_main, run_case
from gsi.case.build_dem import build_simulation
from gsi.run.result import RunInterrupted, RunResult
from gsi.run.runner import Runner

__all__ = ["Runner", "RunResult", "RunInterrupted", "run_case", "demo_main",
           "build_simulation"]
