"""Lacey's mixing index (gsi.post.mixing) and the 'mixing' monitor's input checks."""
import math

import numpy as np
import pytest

from gsi.case.case import case_from_table
from gsi.post.mixing import lacey_index
from gsi.errors import GsiInputError

BOX = ([0.0, 0.0, 0.0], [1.0, 1.0, 1.0])


def test_segregated_halves_give_zero_and_a_random_mixture_gives_one():
    rng = np.random.default_rng(3)
    x = rng.uniform(0.0, 1.0, (40000, 3))
    M, kept, mean = lacey_index(x, x[:, 0] < 0.5, *BOX, (8, 1, 8))
    assert M == pytest.approx(0.0, abs=1e-12) and kept == 64 and mean == 625.0
    M, _, _ = lacey_index(x, rng.uniform(size=len(x)) < 0.3, *BOX, (8, 1, 8))
    # a random mixture: s^2 scatters about sr^2 with relative spread sqrt(2/64)
    assert abs(M - 1.0) < 0.01


def test_the_index_by_hand_on_two_cells():
    # cell 0: 3 A of 4; cell 1: 1 A of 4; p = 1/2, s^2 = (4/16 + 4/16)/8 = 1/16,
    # s0^2 = 1/4, sr^2 = 1/16 (n = 4): M = (1/4 - 1/16)/(1/4 - 1/16) = 1
    x = np.array([[0.1, 0.5, 0.5]] * 4 + [[0.6, 0.5, 0.5]] * 4)
    a = np.array([1, 1, 1, 0, 1, 0, 0, 0], bool)
    assert lacey_index(x, a, *BOX, (2, 1, 1)) == (pytest.approx(1.0), 2, 4.0)
    # all A in cell 0: s^2 = s0^2, M = 0
    a = np.array([1, 1, 1, 1, 0, 0, 0, 0], bool)
    assert lacey_index(x, a, *BOX, (2, 1, 1))[0] == pytest.approx(0.0)


def test_sparse_cells_and_particles_outside_are_left_out_and_one_species_is_nan():
    x = np.array([[0.1, 0.5, 0.5]] * 4 + [[0.6, 0.5, 0.5]] * 2 + [[2.0, 0.5, 0.5]] * 5)
    a = np.array([1, 0, 1, 0, 1, 1] + [1] * 5, bool)
    M, kept, mean = lacey_index(x, a, *BOX, (2, 1, 1), min_count=3)
    # one cell kept, p = 1/2 in it: s^2 = 0, M = s0^2/(s0^2 - s0^2/4) = 4/3 (more even
    # than random)
    assert kept == 1 and mean == 4.0 and M == pytest.approx(4.0 / 3.0)
    assert math.isnan(lacey_index(x, np.ones(len(x), bool), *BOX, (2, 1, 1))[0])
    assert math.isnan(lacey_index(x, a, *BOX, (2, 1, 1), min_count=10)[0])


def _case(monitor):
    return {"case": {"name": "m"}, "run": {"duration": 0.1},
            "dem": {"domain_lo": [0, 0, 0], "domain_hi": [1, 1, 1]},
            "materials": {"g": {"E": 1e7, "nu": 0.3, "rho": 2500.0}},
            "particles": [{"name": "a", "material": "g", "count": 10,
                           "region": {"kind": "box", "lo": [0, 0, 0], "hi": [1, 1, 1]},
                           "size": {"kind": "single", "radius": 0.01}}],
            "monitors": [dict({"name": "mix", "kind": "mixing"}, **monitor)]}


@pytest.mark.parametrize("monitor, says", [
    ({"group": "a", "region": {"kind": "box", "lo": [0, 0, 0], "hi": [1, 1, 1]}},
     "monitors[0].cells: missing"),
    ({"group": "a", "cells": [2, 1, 2],
      "region": {"kind": "sphere", "centre": [0.5, 0.5, 0.5], "radius": 0.4}},
     "monitors[0].region.kind = 'sphere': a 'mixing' monitor samples a box"),
    ({"group": "a", "cells": [2, 0, 2],
      "region": {"kind": "box", "lo": [0, 0, 0], "hi": [1, 1, 1]}},
     "monitors[0].cells = [2, 0, 2]"),
])
def test_bad_mixing_monitors_get_one_line_errors(monitor, says):
    with pytest.raises(GsiInputError) as err:
        case_from_table(_case(monitor))
    assert str(err.value).startswith(says) and "\n" not in str(err.value)
