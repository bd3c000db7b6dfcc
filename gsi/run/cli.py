"""The ``gsi`` command: ``--version``, ``info``, ``check CASE.toml``, ``run CASE.toml``.

Input errors print one line ``error: <key> = <value>: <what is allowed>`` and exit with
status 2, never a traceback; a run that blows up (or cannot write its files) prints its
diagnosis and exits with 3. Warnings print as one line ``warning: ...``. ``gsi run`` refuses
an ``--out`` holding an earlier run's outputs unless ``--overwrite`` (start again) or
``--resume`` (continue from its newest checkpoint; a case changed since then is refused
with the changed keys unless ``--allow-changes``). ``gsi check`` prints the case's size
estimate (:mod:`gsi.case.sizes`).
SIGINT/SIGTERM during ``gsi run`` write a checkpoint and print one line
``interrupted at t = ...; checkpoint written; resume with gsi run ... --resume``, exit
status 130/143. Under MPI, rank 0 alone prints an error every rank shares; an error on
one rank only (e.g. in the FE part) is printed by that rank in one line and aborts every
rank (``MPI_Abort``), so no rank waits for ever.
"""
from __future__ import annotations

import argparse
import importlib
import os
import pathlib
import sys

import gsi
from gsi.errors import GsiInputError, GsiRunError

EXIT_INPUT, EXIT_RUN = 2, 3


def _version_of(module: str, attr: str = "__version__") -> str:
    try:
        mod = importlib.import_module(module)
    except Exception as exc:  # an optional package that is missing or broken
        return f"not available ({type(exc).__name__})"
    return str(getattr(mod, attr, "?"))


def info() -> str:
    """Versions of gsi and the stack, the MPI library and numba's thread count."""
    lines = [f"gsi        {gsi.__version__}"]
    for name in ("dolfinx", "numba", "numpy", "petsc4py", "mpi4py", "gmsh", "meshio", "pyvista"):
        lines.append(f"{name:<10} {_version_of(name)}")
    try:
        from mpi4py import MPI
        lines.append(f"MPI        {MPI.Get_library_version().splitlines()[0].strip()}")
    except Exception as exc:
        lines.append(f"MPI        not available ({type(exc).__name__})")
    try:
        import numba
        lines.append(f"threads    {numba.config.NUMBA_NUM_THREADS} (numba)")
    except Exception:
        pass
    return "\n".join(lines)


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="gsi", description="granular-structure interaction toolkit")
    p.add_argument("--version", action="version", version=f"gsi {gsi.__version__}")
    p.add_argument("-v", "--verbose", action="count", default=0,
                   help="show the libraries' log lines (FFCx's JIT builds, ...); -vv: debug")
    sub = p.add_subparsers(dest="command")
    sub.add_parser("info", help="versions of gsi and its stack")
    c = sub.add_parser("check", help="validate a case file without running it")
    c.add_argument("case", nargs="?", help="CASE.toml")
    c.add_argument("--keys", action="store_true", help="list every key with unit and default")
    r = sub.add_parser("run", help="run a case file")
    r.add_argument("case", help="CASE.toml")
    r.add_argument("-v", "--verbose", action="count", default=0, dest="verbose_run",
                   help="show the libraries' log lines (FFCx's JIT builds, ...); -vv: debug")
    r.add_argument("--out", default=None, help="output directory (default out/<case name>)")
    r.add_argument("--quick", action="store_true", help="the case's [quick] form (short)")
    r.add_argument("--no-pictures", action="store_true", help="skip PNG pictures")
    r.add_argument("--overwrite", action="store_true",
                   help="replace the outputs of an earlier run in --out (else refused)")
    r.add_argument("--checkpoint-every", type=float, default=None, metavar="S",
                   help="checkpoint every S simulated seconds (overrides "
                        "run.checkpoint_interval; 0 = none)")
    r.add_argument("--resume", action="store_true",
                   help="continue from the newest checkpoint under OUT/checkpoints")
    r.add_argument("--allow-changes", action="store_true",
                   help="with --resume: continue although the case changed since the "
                        "checkpoint (the changed keys are printed)")
    return p


def _one_line(exc) -> str:
    """The message of ``exc`` on one line (some libraries' messages span several)."""
    return " ".join(str(exc).split())


def _library_logs(verbose: int) -> None:
    """Library log lines on stderr only with ``-v`` (INFO) or ``-vv`` (DEBUG).

    FFCx calls ``logging.basicConfig()`` at import and its JIT (cffi, distutils) lowers
    the root logger to INFO, which printed one ``INFO:root:building 'libffcx_...'`` line
    per compiled form; the level is set on the handler, which they do not touch."""
    import logging
    level = logging.DEBUG if verbose > 1 else logging.INFO if verbose else logging.WARNING
    root = logging.getLogger()
    plain = [h for h in root.handlers if type(h) is logging.StreamHandler]
    if not root.handlers:
        handler = logging.StreamHandler()
        handler.setFormatter(logging.Formatter(logging.BASIC_FORMAT))
        root.addHandler(handler)
        plain = [handler]
    for h in plain:
        h.setLevel(level)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings as one line ``warning: ...`` on stderr (no source line)."""
    print(f"warning: {_one_line(message)}", file=sys.stderr if file is None else file)


def main(argv: list[str] | None = None) -> int:
    import warnings
    args = parser().parse_args(argv)
    _library_logs(args.verbose + getattr(args, "verbose_run", 0))
    with warnings.catch_warnings():      # restores the caller's filters and showwarning
        warnings.simplefilter("ignore", DeprecationWarning)   # libraries' notes to developers
        warnings.showwarning = _show_warning
        return _main(args, argv)


def _main(args, argv=None) -> int:
    try:
        if args.command == "info":
            print(info())
            return 0
        if args.command == "check":
            return _check(args)
        if args.command == "run":
            return _run(args, argv)
        parser().print_help()
        return 0
    except GsiInputError as exc:
        return _report(exc, f"error: {_one_line(exc)}", EXIT_INPUT)
    except GsiRunError as exc:
        return _report(exc, f"run stopped: {_one_line(exc)}", EXIT_RUN)
    except KeyboardInterrupt:
        if _mpi_size() == 1 or sys.modules["mpi4py.MPI"].COMM_WORLD.rank == 0:
            print("interrupted: the files written so far are complete", file=sys.stderr)
        return 130
    except Exception as exc:
        if _mpi_size() > 1:      # one rank failed alone: the others must not wait
            return _report(exc, f"{type(exc).__name__}: {exc}", EXIT_RUN)
        raise


def _mpi_size() -> int:
    mpi = sys.modules.get("mpi4py.MPI")
    return mpi.COMM_WORLD.size if mpi is not None else 1


def _report(exc, line: str, code: int) -> int:
    """Print ``line`` once: serially, or on rank 0 for an error every rank shares;
    an error of one rank alone is printed by it and aborts all ranks."""
    size = _mpi_size()
    if size == 1:
        print(line, file=sys.stderr)
        return code
    from mpi4py import MPI
    comm = MPI.COMM_WORLD
    if getattr(exc, "agreed", False):
        if comm.rank == 0:
            print(line, file=sys.stderr, flush=True)
        return code
    print(f"{line} (rank {comm.rank} of {size}; stopping every rank)", file=sys.stderr,
          flush=True)
    comm.Abort(code)
    return code


def _check(args) -> int:
    from gsi.case import Case, load_case
    from gsi.config.schema import describe
    if args.keys:
        print("\n".join(describe(Case)))
        return 0
    if not args.case:
        raise GsiInputError("check: give a case file (gsi check CASE.toml) or --keys")
    from gsi.case.sizes import estimate, summary
    case = load_case(args.case)
    dt = case.check()
    est = summary(estimate(case, dt))
    from gsi.case.biot_check import check_biot_at_start
    check_biot_at_start(case, dt)          # a warning when Bi is not << 1
    print(f"{args.case}: ok (case '{case.case.name}': {len(case.particles)} particle "
          f"source(s), {len(case.walls)} wall(s), {len(case.structures)} structure(s), "
          f"{len(case.monitors)} monitor(s); dt = {dt:.3g} s)")
    print(f"  {est}")
    return 0


def _run(args, argv=None) -> int:
    import shlex
    from gsi.case import load_case
    from gsi.run.api import RunInterrupted, run_case
    try:       # the same inputs on every rank: the same error (reported once)
        case = load_case(args.case)
    except GsiInputError as exc:
        exc.agreed = True
        raise
    out = args.out if args.out is not None else pathlib.Path("out") / case.case.name
    if args.resume:
        from gsi.case.fingerprint import check_resume
        check_resume(case, out, quick=args.quick, allow=args.allow_changes)
    elif args.allow_changes:
        raise GsiInputError("--allow-changes: only with --resume")
    try:
        run_case(case, out=out, quick=args.quick, pictures=False if args.no_pictures else None,
                 overwrite=args.overwrite, resume=args.resume,
                 checkpoint_every=args.checkpoint_every)
    except RunInterrupted as exc:
        words = list(sys.argv[1:] if argv is None else argv)
        if "--out" not in words and not any(w.startswith("--out=") for w in words):
            words += ["--out", str(out)]
        prefix = ["mpirun", "-n", str(_mpi_size())] if _mpi_size() > 1 else []
        command = shlex.join(prefix + ["gsi"] + [w for w in words
                                                 if w not in ("--resume", "--overwrite")]
                             + ["--resume"])
        if _mpi_size() == 1 or sys.modules["mpi4py.MPI"].COMM_WORLD.rank == 0:
            print(f"interrupted at t = {exc.time:.6g} s; checkpoint written; resume with "
                  f"{command}", file=sys.stderr, flush=True)
        if _mpi_size() > 1:
            # Ctrl-C of mpirun: Open MPI sends the ranks SIGTERM and SIGKILL one second
            # later (odls_base_sigkill_timeout); the checkpoint is complete and every file
            # closed, so leave now rather than spend that second in the interpreter's,
            # PETSc's and MPI's teardown (measured: the rank then often missed the line)
            sys.stdout.flush()
            os._exit(exc.exit_code)
        return exc.exit_code
    return 0


if __name__ == "__main__":
    sys.exit(main())
