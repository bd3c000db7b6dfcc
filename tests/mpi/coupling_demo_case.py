"""The quick hopper_membrane demo (no pictures), run under ``mpirun -n N`` by
tests/mpi/test_coupling_mpi.py; writes its CSV files next to argv[1] and their columns
as JSON to argv[1] ({"coupling": {...}, "history": {...}})."""
import json
import pathlib
import sys

import numpy as np
from mpi4py import MPI

from gsi.case import load_case
from gsi.run import run_case

ROOT = pathlib.Path(__file__).resolve().parents[2]

if __name__ == "__main__":
    out = pathlib.Path(sys.argv[1])
    case = load_case(ROOT / "demos" / "hopper_membrane.toml")
    run_case(case, out=out.with_suffix(""), quick=True, verbose=False, pictures=False)
    if MPI.COMM_WORLD.rank == 0:
        res = {}
        for name, path in (("coupling", "membrane_coupling.csv"),
                           ("history", "monitors/discharged.csv")):
            a = np.genfromtxt(out.with_suffix("") / path, delimiter=",", names=True)
            res[name] = {c: a[c].tolist() for c in a.dtype.names}
        out.write_text(json.dumps(res))
