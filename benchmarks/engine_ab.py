"""A/B timing of engine variants: the force pass of each on the settled ``settle`` bed.

    python benchmarks/settle.py --save-state settled.npz         # once: the settled bed
    python benchmarks/engine_ab.py settled.npz base=gsi/dem/engine.py try=/tmp/engine_try.py

Each ``NAME=TEMPLATE`` is a copy of the engine template ``gsi/dem/engine.py`` (edited to
try an idea); it is made into a Hertz engine (no rolling, no heat, as the benchmark) under
``$GSI_ENGINE_DIR/ab`` and imported as a module of its own, so all variants run in one
process on the same state. The calls are interleaved (round after round, each a batch of
20 force passes from the same restored state), which keeps the comparison fair on a
shared machine; the best and the median batch are printed. Environment: ``MODE`` of
:func:`contact_forces` (0 the forces only, default; 2 with the fused integration),
``THREADS`` (default 1; CPU time on one thread, wall time on more), ``ROUNDS`` (15),
``SORT`` (1: rows sorted at rebuilds as in the benchmark; 0 id order).
Last line: ``<name>_best_ms=... <name>_median_ms=...`` per variant.
"""
import importlib.util
import os
import pathlib
import sys
import time

import numba
import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

from gsi.dem import engine_factory  # noqa: E402

HEADER = ("# <<ENGINE-LAWS (engine_ab)\n"
          "from gsi.dem.contact.hertz import hertz as LAW\n"
          "from gsi.dem.contact.rolling import no_rolling as ROLL\n"
          "from gsi.dem.heat import none as COND\n"
          "ROLL_ON = False\nHEAT_ON = False\nLOG_ON = False\n# ENGINE-LAWS>>")


def load_variant(name, template):
    """The engine module of one template file."""
    out = pathlib.Path(engine_factory.engine_dir()) / "ab"
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"gsi_engine_ab_{name}.py"
    source = engine_factory._BLOCK.sub(lambda m: HEADER, pathlib.Path(template).read_text(),
                                       count=1)
    if not path.exists() or path.read_text() != source:
        path.write_text(source)
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[path.stem] = module
    spec.loader.exec_module(module)
    return module


def main(argv):
    os.environ.setdefault("SORT", "1")     # rows in force-pass order, as benchmarks/settle.py
    from settle_profile import make, repeater
    threads = int(os.environ.get("THREADS", "1"))
    mode = int(os.environ.get("MODE", "0"))
    rounds = int(os.environ.get("ROUNDS", "15"))
    numba.set_num_threads(threads)
    sim = make(argv[0])
    sim.step(200)
    variants = dict(a.split("=", 1) for a in argv[1:])
    reps = {k: repeater(load_variant(k, v)) for k, v in variants.items()}
    P, pairs, pl, M, wc = sim._bundles()
    nslab = len(pairs.slab_start) - 1
    acc = np.zeros((nslab, len(pl.point), 7))
    so = np.zeros((nslab, 3))
    arrays = [sim.x, sim.v, sim.omega, sim.force, sim.torque, pairs.hist]
    saved = [a.copy() for a in arrays]

    def run(rep, n):
        for a, b in zip(arrays, saved):
            a[:] = b
        clock = time.perf_counter if threads > 1 else time.process_time
        t0 = clock()
        rep(n, mode, sim.dt, P, pairs, pl, M, wc, sim.table, acc, sim.g, sim.lo, sim.hi, so)
        return (clock() - t0) / n * 1e3

    for rep in reps.values():
        run(rep, 1)                        # compile / load
    times = {k: [] for k in reps}
    for _ in range(rounds):
        for k, rep in reps.items():
            times[k].append(run(rep, 20))
    for a, b in zip(arrays, saved):
        a[:] = b
    line = []
    for k, v in times.items():
        print(f"{k}: best {min(v):.3f} ms, median {np.median(v):.3f} ms per force pass "
              f"({sim.n} particles, {len(pairs.j)} pairs, mode {mode}, {threads} thread(s))")
        line += [f"{k}_best_ms={min(v):.4g}", f"{k}_median_ms={np.median(v):.4g}"]
    print(" ".join(line))


if __name__ == "__main__":
    main(sys.argv[1:])
