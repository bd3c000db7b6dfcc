"""The hopper-onto-membrane demo (XDEM Fig. 15) in its quick form, run by the one runner.

400 softwood spheres (XDEM Table 3, plus rolling resistance) settle in a closed conical
hopper, the gate slides away at 0.45 s, the stream falls 0.285 m onto a clamped P2 rubber
membrane (two-way staggered coupling), 1.5 s in all. Checks of the physics in the result:

* the hopper empties: at least 95 % of the mass is below the outlet at the end, and the
  membrane catches it (fewer than 5 % of the particles lost over its rim);
* invariant of the transfer: the nodal loads balance the wall force on the particles at
  every coupling step (1e-12);
* impacts: the peak membrane load exceeds the weight of the whole charge (the falling
  stream delivers momentum faster than gravity alone), yet the impulse delivered to the
  membrane, integrated over the run, cannot exceed weight x time plus the momentum the
  stream brings (m sqrt(2 g H) per particle) -- a momentum bound;
* at the end the load averaged over the membrane's lowest period T_1 (which averages out
  its main vibration) carries the weight of the particles on the membrane within 10 %;
* the membrane deflects downward, its lowest point under the heap.
"""
import math
import pathlib

import numpy as np
import pytest

from gsi.case import load_case
from gsi.run import run_case

ROOT = pathlib.Path(__file__).resolve().parents[2]
N, R, RHO = 400, 0.01, 400.0


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("hopper_membrane")
    case = load_case(ROOT / "demos" / "hopper_membrane.toml")
    r = run_case(case, out=out, quick=True, verbose=False, pictures=False)
    rec = np.genfromtxt(out / "membrane_coupling.csv", delimiter=",", names=True)
    return case, out, r, rec


def test_hopper_discharges_onto_the_membrane(demo):
    case, out, r, rec = demo
    mass0 = N * RHO * 4.0 / 3.0 * math.pi * R ** 3
    assert r.n_particles + r.n_lost == N
    dis = r.monitors["discharged"]
    assert dis["mass_kg"][-1] >= 0.95 * mass0
    assert r.n_lost < 0.05 * N
    m = dis["mass_kg"] + (mass0 / N) * dis["lost"]       # below the outlet or lost beyond
    assert np.all(np.diff(m) >= -1e-12)                  # nothing climbs back


def test_load_balance_every_step_is_an_invariant_of_the_transfer(demo):
    case, out, r, rec = demo
    assert r.structures["membrane"]["balance_max"] < 1e-12
    assert np.abs(rec["load_z"] - rec["wall_force_z"]).max() < 1e-12 * np.abs(rec["load_z"]).max()


def test_impacts_and_momentum_bound(demo):
    case, out, r, rec = demo
    g = 9.81
    mass0 = N * RHO * 4.0 / 3.0 * math.pi * R ** 3
    W = mass0 * g
    assert -rec["load_z"].min() > W
    dt_fe = r.structures["membrane"]["dt"]
    impulse = -rec["load_z"].sum() * dt_fe
    t_first = rec["t"][np.flatnonzero(rec["load_z"] != 0)[0]]
    H = 0.3 + 0.3 - 0.025                    # top of the hopper to the membrane top (m)
    bound = W * (rec["t"][-1] - t_first) + mass0 * math.sqrt(2 * g * H)
    assert 0 < impulse < bound


def test_final_load_carries_the_heap(demo):
    case, out, r, rec = demo
    T_1 = r.structures["membrane"]["T_1"]
    last = rec["t"] > rec["t"][-1] - T_1
    weight_on = r.monitors["discharged"]["mass_kg"][-1] * 9.81
    assert -rec["load_z"][last].mean() == pytest.approx(weight_on, rel=0.1)


def test_membrane_deflects_downward(demo):
    case, out, r, rec = demo
    assert rec["min_uz"].min() < 0
    assert -rec["min_uz"].min() == pytest.approx(rec["max_deflection"].max(), rel=0.05)
    assert rec["max_deflection"].max() > 1e-3          # millimetres under a 0.67 kg stream
    for name in ("membrane_coupling.csv", "membrane.xdmf", "particles/particles.pvd",
                 "monitors/discharged.csv", "monitors/membrane.csv", "monitors.png",
                 "summary.txt"):
        assert (out / name).is_file(), name
