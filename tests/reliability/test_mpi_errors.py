"""An error on any MPI rank reaches every rank: one message, a non-zero exit, no hang.

* A DEM blow-up (two stiff particles overlapping, a forced step far above their Rayleigh
  time) on rank 0 while rank 1 waits in the coupled FE part: every rank stops with the
  same error; rank 0 alone prints ``run stopped: blow-up ...``; exit status 3.
* An error raised in the FE step of rank 1 only (injected by the test driver): rank 1
  prints one line and aborts every rank (MPI_Abort); exit status 3.
Both under ``mpirun -n 2`` with a timeout: a hang fails the test.
"""
import importlib.util
import pathlib
import subprocess
import sys

_spec = importlib.util.spec_from_file_location(
    "gsi_tests_reliability_util", pathlib.Path(__file__).resolve().parent / "_util.py")
_util = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_util)


def _ours(stderr):
    """Our lines (not Open MPI's banners, not Python warnings)."""
    return [line for line in stderr.splitlines()
            if line.startswith(("run stopped", "error:", "RuntimeError", "Traceback"))]


def test_a_dem_blow_up_under_mpirun_stops_every_rank_with_one_message(tmp_path):
    cmd = _util.mpirun(2) + [sys.executable, "-m", "gsi.cli", "run",
                             str(_util.HERE / "data" / "blow_up.toml"), "--out",
                             str(tmp_path), "--no-pictures"]
    proc = subprocess.run(cmd, env=_util.env(), capture_output=True, text=True, timeout=240)
    assert proc.returncode == 3, proc.stderr[-3000:]
    ours = _ours(proc.stderr)
    assert len(ours) == 1 and ours[0].startswith("run stopped: blow-up at step "), proc.stderr
    assert "overlapping initial particles" in ours[0]
    assert (tmp_path / "plate.xdmf").is_file() and (tmp_path / "plate.csv").is_file()


def test_an_fe_error_on_rank_1_aborts_every_rank(tmp_path):
    proc = _util.driver(tmp_path / "out", "--fail-fe-on-rank", "1", ranks=2, timeout=240,
                        check=False)
    assert proc.returncode == 3, proc.stderr[-3000:]
    ours = _ours(proc.stderr)
    assert ours == ["RuntimeError: injected FE failure at step 3 (rank 1 of 2; stopping "
                    "every rank)"], proc.stderr
