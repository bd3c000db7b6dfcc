"""Contact conductance models (docs/design.md, "Heat in particles") evaluated directly."""
import math

import pytest

from gsi.dem.contact import conductance as heat
from gsi.dem.materials import Material, pair_table

A = Material(E=1e9, nu=0.3, rho=2000, k=2.0)
B = Material(E=1e9, nu=0.3, rho=2000, k=8.0)


@pytest.mark.parametrize("name,expected", [
    ("area", lambda a2: 4 * 2 * 8 / 10 * math.sqrt(math.pi * a2)),
    ("radius", lambda a2: 4 * 2 * 8 / 10 * math.sqrt(a2)),
    ("constant", lambda a2: 0.3),
    # Feng's pipe network: row 1 is (A, B): k_i = 2, k_j = 8; radii 1 mm and 2 mm
    ("pipe", lambda a2: 0.004 / (_feng(math.sqrt(a2), 1e-3, 2.0)
                                 + _feng(math.sqrt(a2), 2e-3, 8.0) + 0.01)),
])
def test_models(name, expected):
    tab = pair_table([A, B], h_c=0.3, pipe_length=0.004, pipe_resistance=0.01).reshape(4, -1)
    fn = getattr(heat, name)
    for a2 in (1e-8, 2.5e-7):
        assert fn(a2, 1e-3, 2e-3, tab, 1) == pytest.approx(expected(a2), rel=1e-14)
    if name != "constant":
        assert fn(0.0, 1e-3, 2e-3, tab, 1) == 0.0 and fn(-1e-9, 1e-3, 2e-3, tab, 1) == 0.0


def _feng(a, r, k):
    alpha = math.asin(a / r)
    return (-math.log(alpha) + 1.5 + alpha ** 2 / 36) / (math.pi * k)


def test_pipe_model_on_a_wall_has_no_wall_resistance():
    tab = pair_table([A, B], pipe_length=0.004, pipe_resistance=0.01).reshape(4, -1)
    a2 = 2.5e-7
    H = heat.pipe(a2, 1e-3, math.inf, tab, 1)
    assert H == pytest.approx(0.004 / (_feng(math.sqrt(a2), 1e-3, 2.0) + 0.01), rel=1e-14)
