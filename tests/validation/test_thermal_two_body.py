"""Particle-wall conduction through the FE coupling against exact two-body references.

docs/design.md, "Validation cases", case 9 ("hot particles on a cold wall") in its smallest form: ONE fixed particle
touches ONE triangle of the contact face of a small FE block.

* Lumped two-body limit: with a very high wall conductivity the block is isothermal, so
  particle (capacity C_p) and block (capacity C_w = rho c V) form the lumped two-body
  problem C_p dT_p/dt = H (T_w - T_p) = -C_w dT_w/dt, whose exact solution is
  T_p - T_w = (T_p0 - T_w0) exp(-t/tau), tau = 1/(H (1/C_p + 1/C_w)), both tending to
  T_eq = (C_p T_p0 + C_w T_w0)/(C_p + C_w). The staggered scheme has its own exact
  discrete solution (explicit Euler sub-cycle at a held wall temperature, then the wall
  gains exactly the heat the particle lost); the coupled run must follow that to the
  isothermality error and the continuous one to the time-step error O(dt_FE/tau).
* Neumann reference: on a real steel plate, the coupled FE temperature field must equal
  a separate FE heat run driven directly by the point heat load Q = H (T_p - T_w(p))
  split over the triangle's vertices with barycentric weights, with H from the contact
  geometry (Hertz contact radius a^2 = 2 R d - d^2) and both conductivities, computed
  here independently of the DEM code.
"""
import math

import numpy as np
import pytest

from gsi import meshes
from gsi.coupling.thermal import ThermalCoupling
from gsi.dem import Material, Simulation
from gsi.fem.heat import Heat

D = "docs/design.md"  # where the references are written down

R, D = 2.0e-3, 5.0e-5          # particle radius, overlap with the wall (m)
DT, N_SUB = 2.0e-5, 10         # DEM step (s), DEM steps per coupling step
K_P, CP_P, RHO_P = 1.0, 10.0, 2500.0


def _coupled(structure, wall_mat, *, T_p, T_w, tag, weights, tri_index=None):
    heat = Heat(structure, wall_mat, dt=N_SUB * DT, T_initial=T_w)
    sim = Simulation({"p": Material(E=1e7, nu=0.3, rho=RHO_P, k=K_P, cp=CP_P),
                      "w": Material(E=1e9, nu=0.3, rho=wall_mat["rho"], k=wall_mat["k"])},
                     heat="area", gravity=(0, 0, 0), dt=DT, skin=5e-4,
                     domain=((-0.05, -0.05, -0.05), (0.05, 0.05, 0.05)))
    cp = ThermalCoupling(sim, heat, wall_material="w", n_sub=N_SUB, tag=tag, T_ref=T_w)
    s = cp.surface
    t = 0 if tri_index is None else tri_index(s)
    p = (np.asarray(weights)[:, None] * s.x0[s.triangles[t]]).sum(0)
    normal = s.normals()[t]
    ids = sim.add_particles([p + (R - D) * normal], R, material="p", T=T_p)
    sim.fix(ids)
    return cp, t


def _conductance(k_w):
    a2 = 2 * R * D - D * D
    return 4 * K_P * k_w / (K_P + k_w) * math.sqrt(math.pi * a2)


def test_lumped_two_body_limit(record_validation):
    L, Lz = 0.02, 0.005
    block = meshes.build("box", length_x=L, length_y=L, length_z=Lz, n=(2, 2, 1))
    wall = dict(E=1e9, nu=0.3, rho=1.0, c=420.0, k=1e6)   # near-isothermal block
    T_p0, T_w0 = 400.0, 300.0
    cp, _ = _coupled(block, wall, T_p=T_p0, T_w=T_w0, tag="z1", weights=(1 / 3, 1 / 3, 1 / 3))
    n_steps = 2500                                      # 0.5 s
    cp.run(n_steps)
    h = cp.history()
    C_p = RHO_P * 4 / 3 * math.pi * R**3 * CP_P
    C_w = wall["rho"] * wall["c"] * L * L * Lz
    H = _conductance(wall["k"])
    # exact discrete solution of the staggered scheme (lumped wall)
    r = DT * H / C_p
    Tp, Tw = T_p0, T_w0
    Tp_d, Tw_d = [], []
    for _ in range(n_steps):
        Tp_new = Tw + (Tp - Tw) * (1 - r) ** N_SUB
        Tw += C_p * (Tp - Tp_new) / C_w
        Tp = Tp_new
        Tp_d.append(Tp)
        Tw_d.append(Tw)
    Tp_d, Tw_d = np.array(Tp_d), np.array(Tw_d)
    dT0 = T_p0 - T_w0
    # isothermality error of the block: ~ H dT0/(k L) = 6e-7 dT0
    record_validation("two-body limit (particles on a block): particles vs exact discrete "
                      "staggered solution, max error / dT0", reference=0.0,
                      measured=float(np.abs(h["T_particles_mean"] - Tp_d).max() / dT0),
                      tolerance=1e-6, kind="abs", source=f'{D}, "Validation cases" 9')
    assert np.abs(h["T_particles_mean"] - Tp_d).max() <= 1e-6 * dT0
    assert np.abs(h["T_wall_mean"] - Tw_d).max() <= 1e-6 * dT0
    # continuous lumped two-body solution
    tau = 1.0 / (H * (1 / C_p + 1 / C_w))
    T_eq = (C_p * T_p0 + C_w * T_w0) / (C_p + C_w)
    t = h["t"]
    diff = dT0 * np.exp(-t / tau)
    Tp_exact = T_eq + diff * C_w / (C_p + C_w)
    Tw_exact = T_eq - diff * C_p / (C_p + C_w)
    dt_fe = N_SUB * DT
    assert t[-1] > 3 * tau                              # well on the way to T_eq
    assert np.abs(h["T_particles_mean"] - Tp_exact).max() <= 2 * dt_fe / tau * dT0
    assert np.abs(h["T_wall_mean"] - Tw_exact).max() <= 2 * dt_fe / tau * dT0
    assert abs(h["T_particles_mean"][-1] - T_eq) < 0.05 * dT0
    # energy: per step to round-off, total drift to round-off
    assert np.abs(h["balance_error"]).max() <= 1e-12 * np.abs(h["Q_particles"]).max()
    # the drift is the direct solver's round-off: the near-isothermal block's conduction
    # matrix is ~1e8 x its capacity matrix C/dt, so it is amplified (3.7e-9 measured)
    assert np.abs(h["drift"]).max() <= 1e-7 * C_p * dT0


def test_wall_heating_equals_fe_run_with_the_equivalent_point_flux():
    L, Lz = 0.02, 0.002
    plate = meshes.build("box", length_x=L, length_y=L, length_z=Lz, n=(4, 4, 1))
    steel = dict(E=210e9, nu=0.3, rho=7850.0, c=440.0, k=53.3)
    T_p0, T_w0 = 800.0, 300.0
    w = np.array([0.45, 0.35, 0.20])

    def middle_triangle(s):
        centre = s.x0[s.triangles].mean(1)
        return int(np.argmin(np.linalg.norm(centre[:, :2] - L / 2, axis=1)))

    cp, t = _coupled(plate, steel, T_p=T_p0, T_w=T_w0, tag="z1", weights=w,
                     tri_index=middle_triangle)
    n_steps = 200
    cp.run(n_steps)
    s = cp.surface
    gids = s.global_ids[s.triangles[t]]
    # reference: the same FE heat problem driven by the point flux computed here
    ref = Heat(plate, steel, dt=N_SUB * DT, T_initial=T_w0)
    C_p = RHO_P * 4 / 3 * math.pi * R**3 * CP_P
    H = _conductance(steel["k"])
    r = DT * H / C_p
    Tp = T_p0
    surf_T = np.full(s.n_vertices, T_w0)
    idx = s.triangles[t]
    rows, dofs = ref.vmap.lookup_owned(s.global_ids)   # serial: every vertex is owned
    assert len(rows) == s.n_vertices
    for _ in range(n_steps):
        T_w = float(w @ surf_T[idx])                    # wall temperature at the contact point
        Tp_new = T_w + (Tp - T_w) * (1 - r) ** N_SUB
        Q = C_p * (Tp - Tp_new)                         # J given to the wall over the step
        Tp = Tp_new
        ref.clear_nodal_heat()
        ref.add_nodal_heat(gids, Q / ref.dt * w)
        ref.step()
        surf_T = ref.T.x.array[dofs]
    rise = cp.heat.T.x.array.max() - T_w0
    assert rise > 0.1                                   # the plate warmed measurably
    assert np.abs(cp.heat.T.x.array - ref.T.x.array).max() <= 1e-9 * rise
    assert cp.records[-1].T_particles_mean == pytest.approx(Tp, rel=1e-12)
    h = cp.history()
    assert np.abs(h["balance_error"]).max() <= 1e-12 * np.abs(h["Q_particles"]).max()
    assert np.abs(h["drift"]).max() <= 1e-10 * C_p * (T_p0 - T_w0)
    # the contact sees the non-uniform field: hotter than the plate mean
    assert cp.records[-1].T_contact_max > cp.records[-1].T_wall_mean

