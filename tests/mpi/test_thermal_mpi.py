"""The thermo-mechanical DEM <-> FE coupling on 1 and 2 MPI ranks gives the same answer.

Runs tests/mpi/thermal_mpi_case.py under ``mpirun -n 1`` and ``-n 2`` (the DEM on rank 0,
the FE distributed) and compares the temperature and displacement of the contact surface,
the particle temperatures and the per-step energy records: equal up to the direct
solver's round-off (1e-9 relative). On both, the heat given to the structure equals the
heat the particles lost every step (the loads broadcast from rank 0 land once).
"""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("mpirun", HERE / "mpirun.py")
mpirun = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mpirun)

pytestmark = pytest.mark.mpi


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("thermal_mpi")
    return tuple(mpirun.run_json(HERE / "thermal_mpi_case.py", n, tmp / f"thermal_{n}.json")
                 for n in (1, 2))


def _close(a, b, rel):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.abs(a - b).max() <= rel * np.abs(a).max()


def test_ran_on_one_and_two_ranks(results):
    assert (results[0]["n_ranks"], results[1]["n_ranks"]) == (1, 2)


@pytest.mark.parametrize("key", ["T_surf", "u_surf", "wall_x", "T_particles"])
def test_same_fields(results, key):
    r1, r2 = results
    assert _close(r1[key], r2[key], 1e-9)


def test_wall_warmed_and_moved(results):
    r1, _ = results
    assert max(r1["T_surf"]) > 300.5
    assert np.abs(r1["u_surf"]).max() > 0


@pytest.mark.parametrize("key", ["Q_particles", "Q_structure", "E_structure",
                                 "Q_boundary_loss", "T_wall_max", "max_von_mises"])
def test_same_energy_record(results, key):
    r1, r2 = results
    assert _close(r1[key], r2[key], 1e-9)


def test_balance_on_both(results):
    for r in results:
        q = np.abs(r["Q_particles"]).max()
        assert q > 0
        assert np.abs(r["balance_error"]).max() <= 1e-12 * q
