"""The bed-on-membrane coupled case (gsi/studies/bed_on_membrane.py), run under ``mpirun -n N``
by tests/mpi/test_coupling_mpi.py; writes its key numbers and records as JSON to argv[1]."""
import json
import pathlib
import sys

from mpi4py import MPI

from gsi.studies.bed_on_membrane import bed_on_membrane

if __name__ == "__main__":
    res = bed_on_membrane(h=0.05, duration=0.3)
    if MPI.COMM_WORLD.rank == 0:
        res["records"] = {k: v.tolist() for k, v in res["records"].items()}
        res["reaction"] = list(res["reaction"])
        res["load"] = list(res["load"])
        pathlib.Path(sys.argv[1]).write_text(json.dumps(res))
