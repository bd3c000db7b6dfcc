"""Helpers of the reliability tests: run the CLI or the driver in a subprocess, compare runs."""
import csv
import os
import pathlib
import shutil
import subprocess
import sys
import time

import numpy as np
import pytest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
CASE = HERE / "data" / "coupled_small.toml"
EVERY = "0.006"            # s between checkpoints of the tests (steps 300, 600, 900)
TIMING = ("wall_dem", "wall_fe", "wall_transfer")    # wall-clock columns of the records


def env(threads=1):
    return dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                OMPI_MCA_rmaps_base_oversubscribe="1", NUMBA_NUM_THREADS=str(threads),
                PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))


def mpirun(n):
    exe = shutil.which("mpirun")
    if exe is None:
        pytest.skip("mpirun not found")
    return [exe, "-n", str(n)]


def driver(out, *extra, threads=1, ranks=None, timeout=600, check=True, case=None):
    cmd = [sys.executable, str(HERE / "driver.py"), str(case or CASE), str(out), *extra]
    if ranks:
        cmd = mpirun(ranks) + cmd
    proc = subprocess.run(cmd, env=env(threads), capture_output=True, text=True,
                          timeout=timeout)
    if check:
        assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return proc


def cli(out, *extra, ranks=None, case=None, **popen):
    cmd = [sys.executable, "-m", "gsi.cli", "run", str(case or CASE), "--out", str(out),
           "--no-pictures", *extra]
    if ranks:
        cmd = mpirun(ranks) + cmd
    return subprocess.Popen(cmd, env=env(1), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, **popen)


def longer_case(directory, duration):
    """A copy of the test case (in ``directory``) that runs ``duration`` s instead."""
    text = CASE.read_text()
    assert "duration = 0.024\n" in text
    path = pathlib.Path(directory) / CASE.name
    path.write_text(text.replace("duration = 0.024\n", f"duration = {duration!r}\n"))
    return path


def wait_for(path_glob, directory, *, timeout=300, proc=None):
    """Wait until a file matching ``path_glob`` exists under ``directory``."""
    t0 = time.time()
    while time.time() - t0 < timeout:
        if list(pathlib.Path(directory).glob(path_glob)):
            return
        if proc is not None and proc.poll() is not None:
            raise AssertionError(f"the run ended before {path_glob} appeared: "
                                 + proc.stderr.read()[-3000:])
        time.sleep(0.05)
    raise AssertionError(f"{path_glob} did not appear under {directory}")


def rewind(src, dst):
    """A copy of a finished run's directory whose newest checkpoint is dropped: resuming it
    starts from the older one, with the later outputs of the finished run still there."""
    shutil.copytree(src, dst)
    manifests = sorted((dst / "checkpoints").glob("ckpt_*.json"))
    manifests[-1].unlink()
    return int(manifests[-2].name[5:15])


def dumps(prefix):
    out = {}
    for path in sorted(prefix.parent.glob(prefix.name + ".rank*.npz")):
        with np.load(path, allow_pickle=False) as z:
            out[path.name.rsplit(".", 2)[1]] = {k: z[k] for k in z.files}
    return out


def assert_same_files(a, b):
    """Every output file of run ``a`` exists in ``b`` with the same bytes -- except: the
    wall-clock columns of the coupling CSV, summary.txt's wall times, the HDF5 files'
    object time stamps (same size required), the checkpoints (they hold the records'
    wall-clock columns) and monitors.png."""
    files = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file()
                   and "checkpoints" not in p.parts and p.name != "monitors.png")
    assert sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file()
                  and "checkpoints" not in p.parts and p.name != "monitors.png") == files
    for rel in files:
        fa, fb = a / rel, b / rel
        if rel.suffix == ".h5":
            assert fa.stat().st_size == fb.stat().st_size, rel
        elif rel.name.endswith("_coupling.csv"):
            ra, rb = (list(csv.DictReader(f.open())) for f in (fa, fb))
            assert len(ra) == len(rb) > 0
            for x, y in zip(ra, rb):
                assert {k: v for k, v in x.items() if k not in TIMING} == \
                       {k: v for k, v in y.items() if k not in TIMING}, rel
        elif rel.name == "summary.txt":
            assert fa.read_text().splitlines()[1] == fb.read_text().splitlines()[1]
        else:
            assert fa.read_bytes() == fb.read_bytes(), rel


def assert_files_open(out):
    """Every output file opens: PVD + VTU (meshio), CSV (numpy), XDMF (pyvista, in a
    subprocess: a broken file must not take the test down)."""
    import xml.etree.ElementTree as ET

    import meshio
    for pvd in out.rglob("*.pvd"):
        for ds in ET.parse(pvd).getroot().iter("DataSet"):
            vtu = pvd.parent / ds.get("file")
            piece = ET.parse(vtu).getroot().find("UnstructuredGrid/Piece")
            if int(piece.get("NumberOfPoints")) > 0:   # meshio cannot read an empty grid
                meshio.read(vtu)
    for path in out.rglob("*.csv"):
        if "checkpoints" in path.parts:
            continue
        with path.open() as fh:
            header = fh.readline().strip().split(",")
        data = np.genfromtxt(path, delimiter=",", skip_header=1, ndmin=2)
        assert data.shape[1] == len(header) if data.size else True, path
    for xdmf in out.glob("*.xdmf"):
        code = ("import sys, pyvista as pv; r = pv.get_reader(sys.argv[1]); "
                "[r.set_active_time_value(t) or r.read() for t in r.time_values]; "
                "print(len(r.time_values))")
        proc = subprocess.run([sys.executable, "-c", code, str(xdmf)], env=env(),
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr[-2000:]


def _state_arrays(a, b):
    """(rank, key, x, y) of two final-state dumps (all ranks), wall-clock columns aside;
    the keys, dtypes and shapes must agree."""
    assert a.keys() == b.keys() and a
    for rank in a:
        x, y = a[rank], b[rank]
        assert x.keys() == y.keys()
        for k in x:
            if not k.endswith(TIMING):
                assert (x[k].dtype, x[k].shape) == (y[k].dtype, y[k].shape), (rank, k)
                yield rank, k, x[k], y[k]


def assert_same_state(a, b):
    """Bitwise equality of two final-state dumps (all ranks), wall-clock columns aside."""
    for rank, k, x, y in _state_arrays(a, b):
        assert x.tobytes() == y.tobytes(), (rank, k)


def assert_close_state(a, b, *, rtol=1e-7):
    """Two final-state dumps agree as two repeats of one run under MPI do: integers exactly,
    floats to ``rtol`` of each array's largest magnitude (the round-off balances
    ``balance_*`` are round-off themselves and only compared in size)."""
    for rank, k, x, y in _state_arrays(a, b):
        if x.dtype.kind != "f":
            assert x.tobytes() == y.tobytes(), (rank, k)
        elif "balance_" in k:
            assert np.nanmax(np.abs(y), initial=0.0) < 1e-11, (rank, k)
        else:
            scale = np.nanmax(np.abs(x), initial=0.0)
            assert np.allclose(x, y, rtol=0.0, atol=rtol * scale, equal_nan=True), \
                (rank, k, np.nanmax(np.abs(x - y)), scale)
