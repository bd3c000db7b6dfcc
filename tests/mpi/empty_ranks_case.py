"""Structures with fewer cells than MPI ranks, through the runner, under ``mpirun -n N``
(tests/mpi/test_empty_ranks_mpi.py).

``python empty_ranks_case.py OUT.json CASE.toml WORKDIR``: runs the case (one-tetrahedron
``.msh`` structures: a P1 one coupled thermo-mechanically with a dynamic scheme and a P2
static one, a stream of hot particles onto them) with a checkpoint every 0.004 s, so that
some ranks own no cell; then rewinds the run to its older checkpoint and resumes it.
Rank 0 writes as JSON: the cells each rank owns, the final particle state, each
structure's interface displacement and summary, the monitor series, and whether the
resumed run ended bit-identical to the uninterrupted one on every rank (every
structure's state, the DEM state).
"""
import json
import pathlib
import sys

import numpy as np
from mpi4py import MPI

from gsi.case import load_case
from gsi.fem import compat
from gsi.run import Runner


def _final(runner):
    """This rank's final structure states and (rank 0) DEM state, as bytes per key."""
    d = {}
    for st in runner.structures:
        d.update({f"{st.name}.{k}": np.asarray(v).tobytes() for k, v in st.state().items()
                  if not k.endswith(("wall_dem", "wall_fe", "wall_transfer"))})
    if runner.sim is not None:
        d.update({f"dem.{k}": np.asarray(v).tobytes() for k, v in runner.sim.state().items()})
    return d


def main(out_json, case_path, work):
    comm = MPI.COMM_WORLD
    out = pathlib.Path(work) / f"run{comm.size}"
    case = load_case(case_path)
    first = Runner(case, out=out, verbose=False, pictures=False, checkpoint_every=0.004,
                   overwrite=True)
    res = first.run()
    cells = {st.name: comm.gather(compat.num_cells_local(st.mesh.mesh), root=0)
             for st in first.structures}
    u = {st.name: st.interface.displacement() for st in first.structures}
    a = _final(first)
    if comm.rank == 0:      # rewind: the resume starts from the older checkpoint
        newest = sorted((out / "checkpoints").glob("ckpt_*.json"))[-1]
        newest.unlink()
    comm.barrier()
    again = Runner(case, out=out, verbose=False, pictures=False, checkpoint_every=0.004,
                   resume=True)
    again.run()
    b = _final(again)
    same = a.keys() == b.keys() and all(a[k] == b[k] for k in a)
    same = comm.allgather(same)
    if comm.rank == 0:
        sim = first.sim
        result = dict(
            n_ranks=comm.size, cells=cells, resume_bitwise=same,
            x=np.asarray(sim.x).tolist(), v=np.asarray(sim.v).tolist(),
            T=np.asarray(sim.T).tolist(),
            u={k: v.tolist() for k, v in u.items()},
            summary={k: v for k, v in res.summary.items() if isinstance(v, (int, float))
                     and not k.endswith(("wall_dem", "wall_fe", "wall_transfer"))},
            monitors={name: {c: np.asarray(s).tolist() for c, s in series.items()}
                      for name, series in res.monitors.items()})
        with open(out_json, "w") as fh:
            json.dump(result, fh)


if __name__ == "__main__":
    main(*sys.argv[1:4])
