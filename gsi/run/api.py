"""Running a case: :func:`run_case` (the ``gsi run`` command's code path) and
:func:`demo_main` (the command line of a demo script)."""
from __future__ import annotations

import pathlib

from gsi.errors import GsiInputError, GsiRunError
from gsi.run.outdir import remove_temporaries
from gsi.run.result import RunInterrupted, RunResult, agreed
from gsi.run.runner import Runner

__all__ = ["run_case", "demo_main", "RunInterrupted", "RunResult"]


def run_case(case, *, out, quick: bool = False, pictures: bool | None = None,
             verbose: bool = True, overwrite: bool = False, resume: bool = False,
             checkpoint_every: float | None = None) -> RunResult:
    """Run a case (a :class:`gsi.case.Case` or a path to a case file) into ``out``.

    ``overwrite``: replace an earlier run's outputs in ``out`` (else such a directory is
    refused); ``resume``: continue from the newest checkpoint in ``out``;
    ``checkpoint_every``: simulated seconds between checkpoints (overrides the case). Input
    errors found before the run are the same on every MPI rank (marked so: rank 0 alone
    reports them). A failure to write (a full disk, a quota, a vanished directory) or to
    allocate stops the run with a one-line :class:`gsi.errors.GsiRunError`; the files
    written so far stay, half-written temporary files are removed."""
    if not hasattr(case, "run"):
        from gsi.case import load_case
        try:
            case = load_case(case)
        except GsiInputError as exc:
            raise agreed(exc)
    try:
        runner = Runner(case, out=out, quick=quick, pictures=pictures, verbose=verbose,
                        overwrite=overwrite, resume=resume, checkpoint_every=checkpoint_every)
    except GsiInputError as exc:
        raise agreed(exc)
    try:
        return runner.run()
    except OSError as exc:
        remove_temporaries(out)
        where = exc.filename or f"under {out}"
        raise GsiRunError(f"cannot write {where}: {exc.strerror or exc}; free space (or fix "
                          f"the directory) and run again with --overwrite") from None
    except MemoryError:
        raise GsiRunError("out of memory; fewer particles (particles[].count, rate) or a "
                          "coarser structure mesh (structures[].geometry.h)") from None


def demo_main(case, *, description: str = "", argv=None) -> RunResult | None:
    """The command line of a demo script: ``python demos/<name>.py [--quick] [--out DIR]
    [--no-pictures] [--overwrite | --resume] [--checkpoint-every S]``, the options of ``gsi
    run``; runs ``case`` and returns its result. Errors print one line: exit status 2 for
    bad input, 3 for a run that stopped, 130/143 after SIGINT/SIGTERM (checkpoint written)."""
    import argparse
    import sys
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--quick", action="store_true", help="the short form (< 2 minutes)")
    parser.add_argument("--out", default=None, help="output directory (default out/<name>)")
    parser.add_argument("--no-pictures", action="store_true", help="skip the PNG pictures")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace the outputs of an earlier run in --out")
    parser.add_argument("--resume", action="store_true",
                        help="continue from the newest checkpoint under OUT/checkpoints")
    parser.add_argument("--checkpoint-every", type=float, default=None, metavar="S",
                        help="checkpoint every S simulated seconds")
    args = parser.parse_args(argv)
    out = args.out if args.out is not None else pathlib.Path("out") / case.case.name
    try:
        return run_case(case, out=out, quick=args.quick,
                        pictures=False if args.no_pictures else None, overwrite=args.overwrite,
                        resume=args.resume, checkpoint_every=args.checkpoint_every)
    except GsiInputError as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        sys.exit(2)
    except GsiRunError as exc:
        print(f"run stopped: {' '.join(str(exc).split())}", file=sys.stderr)
        sys.exit(3)
    except RunInterrupted as exc:
        print(f"interrupted at t = {exc.time:.6g} s; checkpoint written; resume with "
              f"python {' '.join(sys.argv)} --resume", file=sys.stderr)
        sys.exit(exc.exit_code)
