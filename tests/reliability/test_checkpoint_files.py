"""Checkpoint files: wall-clock checkpoints, the last two kept, an incomplete checkpoint is
never the newest valid one, picture jobs survive a checkpoint."""
import pathlib

import numpy as np

from gsi import checkpoint as ck
from gsi.case import load_case
from gsi.run import Runner

CASE = pathlib.Path(__file__).resolve().parent / "data" / "coupled_small.toml"


def test_wall_clock_checkpoints_keep_the_last_two(tmp_path):
    case = load_case(CASE)
    case.run.duration = 0.012
    case.run.checkpoint_minutes = 1e-9          # due at the end of every chunk
    runner = Runner(case, out=tmp_path, verbose=False)
    runner.run()
    assert len(runner.checkpoint_seconds) >= 10     # one per chunk but the last
    names = sorted(p.name for p in (tmp_path / "checkpoints").iterdir())
    assert len(names) == 4 and all(".tmp" not in n for n in names)
    info = ck.newest(tmp_path / "checkpoints")
    assert info["step"] == int(names[-1][5:15]) and info["n_ranks"] == 1


def test_an_incomplete_checkpoint_is_not_the_newest_valid_one(tmp_path):
    d = tmp_path
    for step in (10, 20):
        size = ck.write_npz(ck.rank_file(d, step, 0), {"x": np.arange(step)})
        ck.write_manifest(d, step, dict(time=step * 0.1, n_ranks=1, sizes=[size]))
    ck.write_npz(ck.rank_file(d, 30, 0), {"x": np.arange(3)})      # no manifest: killed
    assert ck.newest(d)["step"] == 20
    ck.rank_file(d, 20, 0).write_bytes(b"truncated")                # size mismatch
    assert ck.newest(d)["step"] == 10
    ck.prune(d, keep=1)                  # keeps 20's manifest: it is the newest by name
    assert sorted(p.name for p in d.iterdir()) == [
        "ckpt_0000000020.json", "ckpt_0000000020.rank0.npz", "ckpt_0000000030.rank0.npz"]


def test_picture_jobs_round_trip_through_plain_arrays(tmp_path):
    job = dict(camera=None, path=tmp_path / "frame_0000.png", x=np.random.rand(5, 3),
               radius=np.full(5, 1e-3), color_by="speed", values=np.arange(5.0),
               surfaces=[dict(points=np.zeros((3, 3)), triangles=np.array([[0, 1, 2]]),
                              opacity=0.3, color="lightsteelblue")],
               title="t = 0.1 s", box=((0.0, 0.0, 0.0), (1.0, 1.0, 1.0)))
    arrays = {}
    skeleton = ck.pack([job], arrays, "frame.")
    ck.write_npz(tmp_path / "f.npz", dict(arrays, skeleton=np.array(str(skeleton))))
    loaded = ck.read_npz(tmp_path / "f.npz")
    back, = ck.unpack(skeleton, loaded)
    assert back["path"] == job["path"] and back["camera"] is None
    assert np.array_equal(back["x"], job["x"]) and back["surfaces"][0]["color"] == "lightsteelblue"
    assert back["box"] == [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]
