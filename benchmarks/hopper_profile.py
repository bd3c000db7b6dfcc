"""Where the hopper-onto-membrane demo's DEM step goes (a small system: <= 2,000 spheres).

    python benchmarks/hopper_profile.py [--duration 1.2] [--quick]

Runs demos/hopper_membrane.toml through the runner (no pictures; ``--duration`` s of it,
default the whole case) with timers around the engine's compiled step loop
(``gsi.dem.engine.fast_advance``, the call of :func:`gsi.dem.engine.advance`) and the
neighbour-list build (:func:`gsi.dem.lists.build_lists`, split into the pair search,
the triangle candidates and the rest), and reads the coupling's own DEM, FE and
transfer wall times from the structure's summary. The DEM's "Python" row is the DEM
wall time minus the engine and the list builds: the chunking between coupling
intervals, insertion, checks, the call of the compiled step loop.

Timers wrap module functions, so they add two clock reads per call (microseconds
against milliseconds). Wall-clock figures: run it on an idle machine.

The last line: ``particles= steps= dem_ms_per_step= particle_steps_per_s= engine_ms=
lists_ms= python_ms= rebuild_every= fe_share=`` (per-step figures in ms).
"""
import argparse
import collections
import dataclasses
import functools
import pathlib
import shutil
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))


def _timed(mod, name, seconds, calls, extra=None):
    f = getattr(mod, name)

    @functools.wraps(f)
    def wrapper(*args, **kwargs):
        t = time.perf_counter()
        out = f(*args, **kwargs)
        seconds[name] += time.perf_counter() - t
        calls[name] += 1
        if extra is not None:
            extra(args, out)
        return out
    setattr(mod, name, wrapper)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=None, help="s of the case (default: all)")
    ap.add_argument("--quick", action="store_true", help="the --quick case (400 spheres)")
    args = ap.parse_args(argv)
    from gsi.case import load_case
    from gsi.dem import engine, lists, neighbour, simulation
    from gsi.run.runner import Runner
    seconds, calls = collections.defaultdict(float), collections.Counter()
    steps = collections.Counter()

    def count(args_, out):            # particle-steps of each engine call
        done = int(out[0])
        if args_[0] > 0:              # not a forces-only pass
            steps["steps"] += done
            steps["particle_steps"] += done * args_[8].x.shape[0]
    _timed(engine, "fast_advance", seconds, calls, count)
    _timed(simulation, "build_lists", seconds, calls)
    _timed(lists, "_triangle_candidates", seconds, calls)
    for name in ("find_pairs", "find_pairs_serial"):
        _timed(neighbour, name, seconds, calls)
    case = load_case(HERE.parent / "demos" / "hopper_membrane.toml")
    if args.quick:
        case = dataclasses.replace(case.quick_variant(), quick={})
    if args.duration:
        case = dataclasses.replace(case, run=dataclasses.replace(case.run, duration=args.duration),
                                   quick={})
    out = pathlib.Path(tempfile.mkdtemp(prefix="gsi_hopper_profile_"))
    try:
        runner = Runner(case, out=out, pictures=False, verbose=False,
                        overwrite=True)
        t0 = time.perf_counter()
        result = runner.run()
        wall = time.perf_counter() - t0
        n_end = runner.sim.n
    finally:
        shutil.rmtree(out, ignore_errors=True)
    s = result.structures["membrane"]
    n = max(steps["steps"], 1)
    dem = s["wall_dem"]
    pairs = seconds["find_pairs"] + seconds["find_pairs_serial"]
    tri = seconds["_triangle_candidates"]
    build = seconds["build_lists"]
    python = dem - seconds["fast_advance"] - build
    ms = 1e3 / n
    print(f"hopper_membrane{' --quick' if args.quick else ''}: {steps['steps']} steps, "
          f"{n_end} particles at the end, run {wall:.1f} s")
    print(f"  DEM {dem:.2f} s = {dem * ms:.3f} ms/step "
          f"({steps['particle_steps'] / dem:.3g} particle-steps/s)")
    print(f"    engine (advance, {calls['fast_advance']} calls) "
          f"{seconds['fast_advance'] * ms:.3f} ms/step")
    print(f"    lists ({calls['build_lists']} builds, one per "
          f"{n / max(calls['build_lists'], 1):.1f} steps) {build * ms:.3f} ms/step: pair "
          f"search {pairs * ms:.3f}, triangle candidates {tri * ms:.3f}, rest "
          f"{(build - pairs - tri) * ms:.3f}; {1e3 * build / max(calls['build_lists'], 1):.2f} "
          f"ms per build")
    print(f"    Python between the calls {python * ms:.3f} ms/step")
    total = dem + s["wall_fe"] + s["wall_transfer"]
    print(f"  FE {s['wall_fe']:.2f} s, transfer {s['wall_transfer']:.2f} s "
          f"({(s['wall_fe'] + s['wall_transfer']) / total:.1%} of the coupling loop)")
    print(f"particles={n_end} steps={steps['steps']} dem_ms_per_step={dem * ms:.4g} "
          f"particle_steps_per_s={steps['particle_steps'] / dem:.4g} "
          f"engine_ms={seconds['fast_advance'] * ms:.4g} lists_ms={build * ms:.4g} "
          f"python_ms={python * ms:.4g} "
          f"rebuild_every={n / max(calls['build_lists'], 1):.3g} "
          f"fe_share={s['wall_fe'] / total:.3f}")


if __name__ == "__main__":
    main()
