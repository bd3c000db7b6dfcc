"""The particle store (gsi.dem.storage.ParticleStore): the fields only frictional heating
uses (gsi.dem.state.FRICTION_FIELDS) have no rows when it is off, so they cost neither
memory nor copying; adding, sorting, deleting and restoring particles work either way,
and a checkpoint made with it off restores into a store with it on as zeros."""
import numpy as np
import pytest

from gsi.dem.state import FRICTION_FIELDS, PARTICLE_FIELDS
from gsi.dem.storage import ParticleStore


def _store(unused):
    s = ParticleStore(4, unused=unused)
    x = np.arange(30, dtype=float).reshape(10, 3)
    s.add_spheres(x, np.full(10, 0.5), mtype=0, rho=1000.0, cp=1000.0, first_id=0)
    return s


def test_unused_fields_have_no_rows_and_cost_no_bytes():
    from gsi.dem.state import empty_pairs
    off, on = _store(FRICTION_FIELDS), _store(())
    for k in FRICTION_FIELDS:
        assert len(off.particle[k]) == 0 and len(off.view(k)) == 0
        assert len(on.view(k)) == 10
    per_row = sum(np.dtype(PARTICLE_FIELDS[k][1]).itemsize * int(np.prod(PARTICLE_FIELDS[k][0]))
                  for k in FRICTION_FIELDS)
    assert per_row == 56                       # heat_friction, fd (3), td (3)
    assert on.nbytes(empty_pairs(0)) - off.nbytes(empty_pairs(0)) == per_row * on.capacity


@pytest.mark.parametrize("unused", [FRICTION_FIELDS, ()], ids=["off", "on"])
def test_add_permute_delete_and_restore(unused):
    s = _store(unused)
    s.view("heat_friction")[:] = np.arange(len(s.view("heat_friction")))
    s.permute(np.arange(10)[::-1])
    assert s.view("id").tolist() == list(range(9, -1, -1))
    s.delete(s.view("id") % 2 == 0)
    assert s.view("id").tolist() == [9, 7, 5, 3, 1] and s.n == 5
    if not unused:
        assert s.view("heat_friction").tolist() == [9.0, 7.0, 5.0, 3.0, 1.0]
    d = s.state()
    t = ParticleStore(4, unused=unused)
    t.set_state(d, s.n)
    for k in PARTICLE_FIELDS:
        np.testing.assert_array_equal(t.view(k), s.view(k))


def test_a_checkpoint_without_friction_restores_into_a_store_with_it_as_zeros():
    off = _store(FRICTION_FIELDS)
    on = ParticleStore(4)
    on.set_state(off.state(), off.n)
    np.testing.assert_array_equal(on.view("x"), off.view("x"))
    for k in FRICTION_FIELDS:
        assert on.view(k).shape[0] == off.n and not on.view(k).any()


def test_an_unknown_unused_field_is_refused():
    with pytest.raises(ValueError, match="unknown fields"):
        ParticleStore(4, unused=("nope",))
