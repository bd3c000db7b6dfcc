"""The hopper-onto-membrane demo (XDEM Fig. 15) in its quick form, run from its TOML.

400 softwood spheres (XDEM Table 3, plus rolling resistance) settle in a closed conical
hopper, the gate slides away at 0.45 s, the stream falls 0.285 m onto a clamped P2
rubber membrane (two-way staggered coupling), 1.5 s in all. Checks of the physics in the result:

* the hopper empties: at least 95 % of the mass is below the outlet at the end, and the
  membrane catches it (fewer than 5 % of the particles lost over its rim; measured 1);
* the nodal loads balance the wall force on the particles at every step (1e-12);
* impacts: the peak membrane load exceeds the weight of the whole charge (the falling
  stream delivers momentum faster than gravity alone), yet the impulse delivered to the
  membrane, integrated over the run, cannot exceed weight x time plus the momentum the
  stream brings (m sqrt(2 g H) per particle) -- a momentum bound;
* at the end the load averaged over the membrane's lowest period T_1 (which averages out
  its main vibration) carries the weight of the particles on the membrane within 10 %
  (measured 0.9 %);
* the membrane deflects downward, its lowest point under the heap.
"""
import math
import pathlib

import numpy as np
import pytest

from gsi.config.case import load_case
from gsi.drivers.hopper_membrane import run

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("hopper_membrane")
    case = load_case(ROOT / "demos" / "hopper_membrane.toml")
    return case, out, run(case, out=out, quick=True, verbose=False, pictures=False)


def test_hopper_discharges_onto_the_membrane(demo):
    case, out, r = demo
    assert r.n_particles + r.n_lost == 400
    assert r.discharged_mass >= 0.95 * r.particle_mass
    assert r.n_lost < 0.05 * 400
    m = r.history["discharged_mass"]
    assert np.all(np.diff(m[: np.argmax(m) + 1]) >= 0)   # monotone until lost particles leave


def test_load_balance_every_step(demo):
    case, out, r = demo
    assert r.balance_max < 1e-12
    rec = np.genfromtxt(out / "coupling.csv", delimiter=",", names=True)
    assert np.abs(rec["load_z"] - rec["wall_force_z"]).max() < 1e-12 * np.abs(rec["load_z"]).max()


def test_impacts_and_momentum_bound(demo):
    case, out, r = demo
    g = 9.81
    W = r.particle_mass * g
    assert -r.load_z_min > W
    rec = np.genfromtxt(out / "coupling.csv", delimiter=",", names=True)
    impulse = -rec["load_z"].sum() * r.dt_fe
    t_first = rec["t"][np.flatnonzero(rec["load_z"] != 0)[0]]
    H = case.hopper.outlet_z + case.hopper.height - 0.025        # highest drop to the membrane top
    bound = W * (r.time - t_first) + r.particle_mass * math.sqrt(2 * g * H)
    assert 0 < impulse < bound


def test_final_load_carries_the_heap(demo):
    case, out, r = demo
    rec = np.genfromtxt(out / "coupling.csv", delimiter=",", names=True)
    last = rec["t"] > rec["t"][-1] - r.T_1
    assert -rec["load_z"][last].mean() == pytest.approx(r.weight_on_membrane, rel=0.1)


def test_membrane_deflects_downward(demo):
    case, out, r = demo
    rec = np.genfromtxt(out / "coupling.csv", delimiter=",", names=True)
    assert rec["min_uz"].min() < 0
    assert -rec["min_uz"].min() == pytest.approx(r.max_deflection, rel=0.05)
    assert r.max_deflection > 1e-3          # millimetres under a 0.67 kg stream
    for name in ("history.csv", "coupling.csv", "structure.xdmf", "particles.pvd",
                 "history.png"):
        assert (out / name).is_file(), name
