"""The drum's set-up before t0 (gsi.studies.drum.prepare) spread over several runs: saved every
``chunk`` steps, resumed after an interruption, and bit-identical to one uninterrupted
set-up; a state file of another set-up is refused with a one-line error, and one of
fewer spin-up turns is extended."""
import numpy as np
import pytest

from gsi.studies.drum import drum_geometry, prepare
from gsi.errors import GsiInputError

SETUP = dict(settle=0.05, spin_up=0.05)


class Stop(Exception):
    pass


def test_interrupted_setup_resumes_bit_identically(tmp_path):
    g = drum_geometry(200)
    ref, hot_ref, _ = prepare(g, **SETUP)
    path = tmp_path / "setup.npz"
    said = []

    def say(msg):
        said.append(msg)
        if len(said) == 3:          # killed after the third save (still settling)
            raise Stop

    with pytest.raises(Stop):
        prepare(g, **SETUP, state=path, chunk=150, say=say)
    assert path.exists() and "step 450 of" in said[-1]
    timing = {}
    sim, hot, _ = prepare(g, **SETUP, state=path, chunk=150, say=said.append, timing=timing)
    assert any("resumed the set-up at step 450" in m for m in said)
    assert sim.time == ref.time and sim.step_count == ref.step_count
    for name in ("x", "v", "omega", "T"):
        assert np.array_equal(getattr(sim, name), getattr(ref, name)), name
    assert np.array_equal(hot, hot_ref)
    # the turning drum's steps are counted once, over both runs
    assert timing["spin_steps"] == int(round(0.05 * g.steps_per_turn))
    assert timing["spin_seconds"] > 0.0
    # a finished set-up is read back, nothing stepped
    again, _, _ = prepare(g, **SETUP, state=path, chunk=150)
    assert np.array_equal(again.x, ref.x) and again.step_count == ref.step_count


def test_state_of_another_setup_refused(tmp_path):
    g = drum_geometry(200)
    path = tmp_path / "setup.npz"
    prepare(g, settle=0.02, spin_up=0.02, state=path, chunk=1000)
    with pytest.raises(GsiInputError, match="another drum set-up"):
        prepare(g, settle=0.03, spin_up=0.02, state=path)
    # a file that went past this set-up's t0 is not its prefix
    with pytest.raises(GsiInputError, match="another drum set-up"):
        prepare(g, settle=0.02, spin_up=0.01, state=path)


def test_shorter_spin_up_is_extended_bit_identically(tmp_path):
    g = drum_geometry(200)
    ref, hot_ref, _ = prepare(g, settle=0.02, spin_up=0.04)
    path = tmp_path / "setup.npz"
    prepare(g, settle=0.02, spin_up=0.02, state=path, chunk=100)
    said = []
    sim, hot, _ = prepare(g, settle=0.02, spin_up=0.04, state=path, chunk=100,
                          say=said.append)
    assert "resumed the set-up at step" in said[0]
    assert sim.step_count == ref.step_count and sim.step_count > 0
    for name in ("x", "v", "omega", "T"):
        assert np.array_equal(getattr(sim, name), getattr(ref, name)), name
    assert np.array_equal(hot, hot_ref)
