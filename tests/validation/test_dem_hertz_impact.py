"""Normal impact, sphere on wall and sphere on sphere (docs/design.md, "Validation cases", case 1).

References
----------
- Restitution: the Hertz–Mindlin damping of LIGGGHTS (beta from ln e) and the linear
  spring–dashpot give an outgoing/incoming normal speed ratio equal to e.
- Hertz (e = 1): contact duration t_c = 2.87 (m*^2/(R* E*^2 v))^(1/5), peak overlap
  d_max = (15 m* v^2/(16 E* sqrt(R*)))^(2/5) (Johnson, Contact Mechanics, 11.1).
- Linear: t_c = pi/(omega_n sqrt(1 - beta^2)), omega_n = sqrt(k_n/m*); for e = 1 the
  peak overlap is v/omega_n.
The time step is t_c/1000, so the step-counted duration resolves 0.1 %.
"""
import math

import pytest

from gsi.dem import Material, Simulation
from gsi.dem.materials import beta_of_e

D = "docs/design.md"  # where the references are written down

R = 1e-3
RHO = 2500.0
E, NU = 5e6, 0.3
K_N = 1e3
V0 = 1.0


def _effective(wall):
    m = RHO * 4 / 3 * math.pi * R ** 3
    E_eff = 1 / (2 * (1 - NU ** 2) / E)
    return (R, m, E_eff) if wall else (R / 2, m / 2, E_eff)


def _hertz_tc_dmax(wall):
    R_eff, m_eff, E_eff = _effective(wall)
    t_c = 2.87 * (m_eff ** 2 / (R_eff * E_eff ** 2 * V0)) ** 0.2
    d_max = (15 * m_eff * V0 ** 2 / (16 * E_eff * math.sqrt(R_eff))) ** 0.4
    return t_c, d_max


def _linear_tc(wall, e):
    m_eff = _effective(wall)[1]
    return math.pi / (math.sqrt(K_N / m_eff) * math.sqrt(1 - beta_of_e(e) ** 2))


def impact(e, *, law, wall, dt):
    """Run one head-on impact at V0; return (restitution, duration (s), peak overlap (m))."""
    mat = {"m": Material(E=E, nu=NU, rho=RHO, e=e, mu=0.5)}
    sim = Simulation(mat, contact=law, k_n=K_N, dt=dt, skin=2e-4,
                     domain=((0, 0, 0), (0.01, 0.01, 0.01)), gravity=(0, 0, 0))
    gap = 2e-6
    if wall:
        sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
        sim.add_particles([[0.005, 0.005, R + gap]], R, material="m", v=[[0, 0, -V0]])
    else:
        sim.add_particles([[0.004, 0.005, 0.005], [0.006 + gap, 0.005, 0.005]], R,
                          material="m", v=[[V0 / 2, 0, 0], [-V0 / 2, 0, 0]])
    steps_in, d_max, started = 0, 0.0, False
    for _ in range(100000):
        sim.step(1)
        d = R - sim.x[0, 2] if wall else 2 * R - (sim.x[1, 0] - sim.x[0, 0])
        if d > 0:
            started = True
            steps_in += 1
            d_max = max(d_max, d)
        elif started:
            break
    v_out = sim.v[0, 2] if wall else sim.v[1, 0] - sim.v[0, 0]
    return abs(v_out) / V0, steps_in * dt, d_max


@pytest.mark.parametrize("wall", [True, False], ids=["wall", "pair"])
@pytest.mark.parametrize("e", [0.3, 0.5, 0.8])
@pytest.mark.parametrize("law", ["hertz", "linear"])
def test_restitution_equals_e(law, wall, e, record_validation):
    t_c = _hertz_tc_dmax(wall)[0] if law == "hertz" else _linear_tc(wall, e)
    e_out, duration, _ = impact(e, law=law, wall=wall, dt=t_c / 1000)
    what = f"{law} impact, {'sphere on wall' if wall else 'sphere on sphere'}"
    record_validation(f"{what}: restitution (e = {e})", reference=e, measured=e_out,
                      tolerance=1e-2, source=f'{D}, "Validation cases" 1')
    if law == "linear":
        record_validation(f"{what}: contact duration (e = {e})", reference=t_c,
                          measured=duration, tolerance=1e-2, unit="s",
                          source="t_c = pi/(omega_n sqrt(1 - beta^2))")
    assert e_out == pytest.approx(e, rel=1e-2)
    if law == "linear":
        assert duration == pytest.approx(t_c, rel=1e-2)


@pytest.mark.parametrize("wall", [True, False], ids=["wall", "pair"])
def test_hertz_elastic_duration_and_peak_overlap(wall, record_validation):
    t_c, d_max = _hertz_tc_dmax(wall)
    e_out, duration, d_peak = impact(1.0, law="hertz", wall=wall, dt=t_c / 1000)
    what = f"Hertz impact (e = 1), {'sphere on wall' if wall else 'sphere on sphere'}"
    src = "Hertz theory (Johnson, Contact Mechanics, 11.1)"
    record_validation(f"{what}: restitution", reference=1.0, measured=e_out, tolerance=1e-6,
                      source=src)
    record_validation(f"{what}: contact duration t_c", reference=t_c, measured=duration,
                      tolerance=1e-2, unit="s", source=src)
    record_validation(f"{what}: peak overlap", reference=d_max, measured=d_peak,
                      tolerance=1e-2, unit="m", source=src)
    assert e_out == pytest.approx(1.0, rel=1e-6)
    assert duration == pytest.approx(t_c, rel=1e-2)
    assert d_peak == pytest.approx(d_max, rel=1e-2)


def test_linear_elastic_peak_overlap():
    m_eff = _effective(True)[1]
    t_c = _linear_tc(True, 1.0)
    e_out, duration, d_peak = impact(1.0, law="linear", wall=True, dt=t_c / 1000)
    assert d_peak == pytest.approx(V0 * math.sqrt(m_eff / K_N), rel=1e-3)
    assert duration == pytest.approx(t_c, rel=2e-3)
