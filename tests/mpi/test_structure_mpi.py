"""A Structure from a user-style .geo (meshes/belt.geo), coupled thermo-mechanically, on 1
and 2 MPI ranks (tests/mpi/structure_mpi_case.py): the same records (mechanical loads,
deflection, heat into the belt, energies; not the round-off balances) to 1e-9 of their
scale, the same interface
displacement and particle temperatures; a missing group is the same one-line error on
every rank."""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("gsi_tests_mpirun", HERE / "mpirun.py")
mpirun = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mpirun)

pytestmark = pytest.mark.mpi


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("structure_mpi")
    return [mpirun.run_json(HERE / "structure_mpi_case.py", n, tmp / f"r{n}.json")
            for n in (1, 2)]


def test_missing_group_is_one_error_on_every_rank(results):
    for r in results:
        assert len(r["errors"]) == r["n_ranks"]
        assert len(set(r["errors"])) == 1
        assert r["errors"][0].startswith("structures[1].tags.support = 'clamped': no physical "
                                         "surface group of that name in belt.geo")


def test_same_coupled_run_on_1_and_2_ranks(results):
    r1, r2 = results
    assert (r1["n_ranks"], r2["n_ranks"]) == (1, 2)
    for group in ("mech", "heat"):
        for key, x in r1[group].items():
            if key in ("balance_rel", "balance_error", "drift"):
                continue                                 # round-off themselves
            x, y = np.asarray(x, float), np.asarray(r2[group][key], float)
            scale = np.nanmax(np.abs(x)) if np.any(np.isfinite(x)) else 0.0
            assert np.allclose(x, y, rtol=0, atol=1e-9 * max(scale, 1e-300), equal_nan=True), key
    h = r1["heat"]
    assert sum(h["Q_particles"]) > 0 and max(map(abs, h["balance_error"])) <= \
        1e-12 * max(map(abs, h["Q_particles"]))
    assert max(r1["mech"]["balance_rel"]) <= 1e-12
    u1, u2 = np.array(r1["u"]), np.array(r2["u"])
    assert np.abs(u1).max() > 0 and np.abs(u2 - u1).max() <= 1e-9 * np.abs(u1).max()
    assert np.array(r2["T_particles"]) == pytest.approx(r1["T_particles"], rel=1e-12)
