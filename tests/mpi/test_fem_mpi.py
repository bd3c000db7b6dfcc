"""docs/design.md, "Validation cases", case 10: the same structural analysis on 1 and 2 MPI ranks.

Runs tests/mpi/fem_mpi_case.py under ``mpirun -n 1`` and ``mpirun -n 2`` and compares:
displacement norms (static, dynamic) and temperature norm to 1e-8 relative (the direct
solver's round-off differs with the partition, nothing else does), the gathered surface
fields, and the nodal loads scattered from rank 0 to the owning ranks and gathered back.
"""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("gsi_tests_mpirun", HERE / "mpirun.py")
mpirun = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mpirun)

pytestmark = pytest.mark.mpi


def _run(n, tmp_path):
    return mpirun.run_json(HERE / "fem_mpi_case.py", n, tmp_path / f"result_{n}.json")


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("fem_mpi")
    return _run(1, tmp), _run(2, tmp)


def test_ran_on_one_and_two_ranks(results):
    r1, r2 = results
    assert (r1["n_ranks"], r2["n_ranks"]) == (1, 2)
    # the contact surface is split between the two ranks: the scatter is exercised
    assert len(r2["owned_surface_vertices"]) == 2 and min(r2["owned_surface_vertices"]) > 0
    assert sum(r2["owned_surface_vertices"]) == r1["owned_surface_vertices"][0]


@pytest.mark.parametrize("key", ["static_norm", "dynamic_norm", "heat_norm"])
def test_same_norms_on_1_and_2_ranks(results, key):
    r1, r2 = results
    assert r2[key] == pytest.approx(r1[key], rel=1e-8)
    assert r1[key] > 0


def test_same_surface_fields_and_loads(results):
    r1, r2 = results
    assert r1["global_ids"] == r2["global_ids"]
    u1, u2 = np.array(r1["surface_u"]), np.array(r2["surface_u"])
    assert np.abs(u2 - u1).max() <= 1e-8 * np.abs(u1).max()
    T1, T2 = np.array(r1["surface_T"]), np.array(r2["surface_T"])
    assert np.abs(T2 - T1).max() <= 1e-8 * np.abs(T1).max()
    # loads given on rank 0 arrive once at every vertex, on 1 and on 2 ranks
    for r in (r1, r2):
        assert np.array(r["loads_back"]) == pytest.approx(np.array(r["loads_in"]), abs=1e-14)
    assert r2["load_sum"] == pytest.approx(r1["load_sum"], rel=1e-12)
    assert r1["dynamic_n_factorizations"] == r2["dynamic_n_factorizations"] == 1
