"""``--resume`` with the iterative structure solvers of issue 33: the restart case
(data/coupled_small.toml, see test_restart.py) with its plate solved by CG + BDDC
(``solver = "iterative"``, ``petsc = { pc_type = "bddc" }``: one subdomain per rank, so
under ``mpirun -n 2``), and by CG + the block low-rank Cholesky preset.

What is compared, and how strictly: **bitwise**, state and files, as the direct solver's
restart test. BDDC's pieces are each deterministic on a fixed partition (the mesh
partition is reproducible, :func:`gsi.fem.compat._deterministic_partitioning`; every
subdomain's MUMPS factorization runs on one rank, the coarse problem is PETSc's own LU,
CG's dot products are reductions over the same 2 ranks in the same order), and CG starts
every step from the last solution, which the checkpoint holds bitwise. A resumed run
builds BDDC again from the same matrix, so it must take the same iterates: a tolerance
here would hide a preconditioner rebuilt differently after the restart (e.g. from a
different matrix or ordering), which the bitwise test catches.

The block low-rank Cholesky preset (``petsc = { pc_type = "cholesky" }``: CG + MUMPS's
compressed factor, gsi.fem.options) is resumed **serially**, also bitwise: on one rank
MUMPS's factorization is deterministic. On several ranks it is not (MUMPS sums the
contribution blocks in the order they arrive, see
:class:`gsi.fem.solvers.FactorOnceSolver`): a resumed run there agrees with the
uninterrupted one to round-off and CG's 1e-10, not bit for bit, as ``out_of_core``.
"""
import importlib.util
import pathlib

import pytest

_spec = importlib.util.spec_from_file_location(
    "gsi_tests_reliability_util", pathlib.Path(__file__).resolve().parent / "_util.py")
_util = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_util)
CASE, EVERY, driver, dumps, rewind = (_util.CASE, _util.EVERY, _util.driver, _util.dumps,
                                      _util.rewind)
assert_same_files, assert_same_state = _util.assert_same_files, _util.assert_same_state

#: the structure's solver lines of each variant (added after its ``supports``) and the
#: MPI ranks it runs on (None: serially)
SOLVERS = {
    "bddc": ('solver = "iterative"\npetsc = { pc_type = "bddc" }\n', 2),
    "blr": ('solver = "iterative"\npetsc = { pc_type = "cholesky" }\n', None),
}


def case_with(directory, lines: str) -> pathlib.Path:
    """A copy of the restart case (in ``directory``) whose structure has ``lines``."""
    text = CASE.read_text()
    anchor = 'supports = ["z0"]\n'
    assert text.count(anchor) == 1
    path = pathlib.Path(directory) / CASE.name
    path.write_text(text.replace(anchor, anchor + lines))
    return path


@pytest.mark.parametrize("variant", [pytest.param("bddc", marks=pytest.mark.mpi), "blr"])
def test_resume_with_an_iterative_solver_is_bitwise(tmp_path, variant):
    lines, ranks = SOLVERS[variant]
    case = case_with(tmp_path, lines)
    ref = tmp_path / "ref"
    proc = driver(ref / "out", "--checkpoint-every", EVERY, "--dump", str(ref / "final"),
                  ranks=ranks, case=case)
    assert "Traceback" not in proc.stderr
    step = rewind(ref / "out", tmp_path / "out")
    assert step == 800
    proc = driver(tmp_path / "out", "--resume", "--checkpoint-every", EVERY, "--dump",
                  str(tmp_path / "final"), ranks=ranks, case=case)
    assert "resumed at t = 0.012 s (step 800)" in proc.stdout
    assert_same_state(dumps(ref / "final"), dumps(tmp_path / "final"))
    assert_same_files(ref / "out", tmp_path / "out")


def test_the_bddc_case_is_refused_on_one_rank(tmp_path):
    """The variant above really runs BDDC: on one rank the same case stops with BDDC's
    one-line error (a subdomain per rank), so the 2-rank runs did not fall back to
    another preconditioner."""
    case = case_with(tmp_path, SOLVERS["bddc"][0])
    proc = driver(tmp_path / "out", case=case, check=False)
    assert proc.returncode == 2, proc.stderr[-2000:]
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith("error: structures[0].petsc.pc_type = 'bddc': needs 2 or more MPI "
                           "ranks"), last
