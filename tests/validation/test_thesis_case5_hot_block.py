"""Seed 001 (thesis), chapter III, case 5: a packed hot block falls on a cold bed while
heat diffuses through the particle contacts.

The case is ``demos/graded/case5_hot_block.toml``, run by the runner as a user would
(``gsi.run.Runner``; monitors as arrays). 25 copper particles at 373.15 K fall 7 mm
onto 24 at 273.15 K resting on the floor; ``radius`` model; adiabatic walls (the thesis:
heat only between particles).

References:

* heat is conserved: the heat-capacity weighted mean stays (24 x 273.15 + 25 x
  373.15)/49 = 324.1704 K (to round-off);
* the spread max T - min T never grows: the explicit update T_i += dt sum_j H_ij (T_j -
  T_i)/C_i makes each new temperature a convex combination of old ones while dt sum_j
  H_ij/C_i <= 1 (the DEM checks it), so max T cannot rise nor min T fall;
* heat does diffuse: the block's mean falls and the bed's rises, monotonically.

The fall and the bounces are chaotic: which block particle ends where, and so how much
the hottest and coldest particles conduct by 0.4 s, changes with the last bit of a
position. The claims that depend on the trajectory are therefore asserted on an ensemble
of M = 5 realisations (start positions moved by up to k x 0.5 nm in the slab's plane,
tests/validation/conftest.py; run two at a time), mean -+ 3 standard errors: the spread
drops (the extreme particles do conduct: its drop is > 0), the gap of the group means
closes below 90 K, and the resting contacts' Biot number stays below 0.1. Measured (M = 5,
at dt and at dt (1 + 1e-12)): drop 0.43 +- 0.05 and 0.52 +- 0.08 K, gap 84.5 +- 0.3 K,
Bi 0.024 +- 0.001 (mean +- SE). The max principle, the conservation and the monotone gap
hold on every trajectory and are asserted on every member.

Why the drop's bound is > 0 and not 0.3 K. The drop spread(0) - spread(0.4 s) = (373.15
K - max T) + (min T - 273.15 K) is an extreme value: 85-95 % of it is the coldest bed
particle's warming, which depends on whether that corner particle has a warmed neighbour
by 0.4 s. On 37 members it is 0.391 +- 0.027 K, sd 0.167 K (sd/mean 0.42; averaged over
the last quarter or half of the run the same). Asserting mean - 3 SE >= 0.3 K with a
margin of two more SE needs SE <= (0.391 - 0.3)/5 = 0.018 K, i.e. M ~ 85 (3.3 s CPU
each, about 140 s on two cores); M = 36 would run in about 60 s but pass only about
three times in five (mean - 3 SE is then 0.31 K on the mean, with an SE of the mean of
0.03 K). The seed gives no number for case 5 (its Fig. III.11 shows the "gradual thermal
diffusion"): the 0.3 K is the old single-run test's own bound, shown as the goal; the
bound asserted is the seed's qualitative claim, mean - 3 SE > 0, with the sd floor from
the 37 members.
"""
import pathlib
import types

import numpy as np
import pytest

from gsi.case import load_case
from gsi.case.biot_check import check_biot

CASE = pathlib.Path(__file__).resolve().parents[2] / "demos" / "graded" / "case5_hot_block.toml"
M = 5
#: sd floors (conftest), below the spreads of two 5-member ensembles (at dt and at
#: dt (1 + 1e-12), 2026-12-04: sd 0.12-0.18 K, 0.56-0.72 K, 0.002); the drop's from 37
#: members (2026-12-05: sd 0.147 K of 20 at dt, 0.191 K of 17 at dt (1 + 1e-12); it was
#: 0.08 K, below the spread the larger ensemble shows)
SD_DROP, SD_GAP, SD_BIOT = 0.15, 0.3, 0.002


def _member(runner):
    """What the tests need of a member (picklable): counts, monitors, the resting
    contacts' Biot number (thesis eq. II.4)."""
    res = runner.result
    rep = check_biot(runner.case, runner.sim, warn=False)
    return types.SimpleNamespace(n_particles=res.n_particles, n_lost=res.n_lost,
                                 monitors=res.monitors, biot_contacts=rep.n_contacts,
                                 biot=rep.max)


@pytest.fixture(scope="module")
def members(ens, tmp_path_factory):
    return ens.run_members(lambda: load_case(CASE), tmp_path_factory.mktemp("case5"), M,
                           plane="xz", extract=_member)


def test_every_member_conserves_heat_and_never_widens_the_spread(members):
    mean0 = (24 * 273.15 + 25 * 373.15) / 49
    for res in members:
        assert res.n_particles == 49 and res.n_lost == 0
        mon = res.monitors
        T_all, block, bed = mon["all_T"], mon["block_T"], mon["bed_T"]
        assert np.all(T_all["count"] == 49)
        # heat conserved (adiabatic walls): round-off only (measured 1.8e-12 K)
        assert np.abs(T_all["T_mean_K"] - mean0).max() < 1e-9
        # the spread never grows (max principle of the explicit contact conduction)
        spread = T_all["T_max_K"] - T_all["T_min_K"]
        assert spread[0] == pytest.approx(100.0, abs=1e-9)
        assert np.diff(T_all["T_max_K"]).max() <= 1e-12
        assert np.diff(T_all["T_min_K"]).min() >= -1e-12
        assert np.diff(spread).max() <= 1e-12
        # heat flows from the block to the bed: the gap of the group means closes
        gap = block["T_mean_K"] - bed["T_mean_K"]
        assert np.diff(gap).max() <= 1e-12
        # the block landed and the bed came to rest: the fall's kinetic energy is
        # dissipated to below 0.1 % (one member at dt (1 + 1e-12) was still rocking at
        # 1.2e-7 J, the others below 1e-8 J)
        KE = mon["particles"]["kinetic_energy_J"]
        assert KE[-1] < 1e-3 * KE.max()


def test_hot_block_on_cold_bed_ensemble(members, ens, record_validation):
    drop, gap, biot = [], [], []
    for r in members:
        T_all = r.monitors["all_T"]
        spread = T_all["T_max_K"] - T_all["T_min_K"]
        drop.append(spread[0] - spread[-1])
        g = r.monitors["block_T"]["T_mean_K"] - r.monitors["bed_T"]["T_mean_K"]
        gap.append(g[-1])
        # the Biot number of the resting contacts (thesis eq. II.4): small here
        assert r.biot_contacts > 40
        biot.append(r.biot)
    s_drop, s_gap, s_bi = (ens.stat(drop, SD_DROP), ens.stat(gap, SD_GAP),
                           ens.stat(biot, SD_BIOT))
    print(f"case 5 at 0.4 s: spread drop {s_drop.text()} K; block - bed gap {s_gap.text()} K;"
          f" Biot {s_bi.text()}")
    record_validation("seed 001 case 5 (M = 5): spread drop at 0.4 s, mean - 3 SE",
                      reference=0.0, measured=float(s_drop.lower()), tolerance=0.0,
                      kind="bound", unit="K", note="mean - 3 SE > 0 (the extremes conduct)",
                      source="max principle of the explicit update; seed 001 Fig. III.11 "
                             "(gradual diffusion, no number)",
                      goal="0.3 K (the old single-run bound): 37 members give 0.391 +- "
                           "0.027 K, sd 0.167 K; mean - 3 SE >= 0.3 K with margin needs "
                           "M ~ 85")
    assert s_drop.lower() > 0.0
    assert s_gap.upper() < 90.0                          # measured 86.2 K (one member)
    assert s_bi.upper() < 0.1
