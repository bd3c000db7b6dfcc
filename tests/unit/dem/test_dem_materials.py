"""Pair tables and time-step references of gsi.dem.materials."""
import math

import pytest

from gsi.dem.materials import (Material, pair_table, beta_of_e, rayleigh_time,
                               P_E, P_G, P_BETA, P_MU, P_KH, P_E_REST)
from gsi.errors import GsiInputError

GLASS = Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.4, k=1.0)
STEEL = Material(E=200e9, nu=0.29, rho=7800, e=0.8, mu=0.0, k=40.0)


def test_pair_table_values():
    t = pair_table([GLASS, STEEL], k_n=1e3)
    assert t.shape[:2] == (2, 2)
    assert t[0, 0, P_E] == pytest.approx(GLASS.E / (2 * (1 - 0.09)))
    inv = (1 - 0.09) / 5e6 + (1 - 0.29 ** 2) / 200e9
    assert t[0, 1, P_E] == pytest.approx(1 / inv) == t[1, 0, P_E]
    invG = 2 * (2 - 0.3) * 1.3 / 5e6 + 2 * (2 - 0.29) * 1.29 / 200e9
    assert t[0, 1, P_G] == pytest.approx(1 / invG)
    assert t[0, 1, P_E_REST] == pytest.approx(math.sqrt(0.4))
    assert t[0, 1, P_MU] == 0.0                       # frictionless steel wall
    assert t[0, 1, P_KH] == pytest.approx(4 * 40 / 41)
    assert t[0, 0, P_BETA] == pytest.approx(beta_of_e(0.5))


def test_overrides_are_symmetric():
    t = pair_table([GLASS, STEEL], pair_overrides={(0, 1): {"e": 0.9, "mu": 0.7}})
    assert t[1, 0, P_E_REST] == t[0, 1, P_E_REST] == 0.9
    assert t[1, 0, P_MU] == 0.7


def test_beta_limits():
    assert beta_of_e(1.0) == 0.0
    assert beta_of_e(0.0) == -1.0
    le = math.log(0.5)
    assert beta_of_e(0.5) == pytest.approx(le / math.sqrt(le ** 2 + math.pi ** 2))


def test_rayleigh_time():
    G = 5e6 / 2.6
    assert rayleigh_time(1e-3, GLASS) == pytest.approx(
        math.pi * 1e-3 * math.sqrt(2500 / G) / (0.1631 * 0.3 + 0.8766))


@pytest.mark.parametrize("kw,key", [({"E": -1}, "E"), ({"nu": 0.5}, "nu"), ({"e": 1.2}, "e"),
                                    ({"mu": -0.1}, "mu"), ({"cp": 0}, "cp")])
def test_validation_names_key(kw, key):
    args = dict(E=1e6, nu=0.3, rho=1000)
    args.update(kw)
    with pytest.raises(GsiInputError, match=rf"materials\.glass\.{key} = "):
        Material(**args).validate("glass")
