"""docs/design.md, "Validation cases", case 9: hot particles fall onto a cold thermo-elastic plate.

Nine particles at 600 K drop onto a clamped steel plate (P1 or P2 elasticity) at 300 K whose underside is cooled
by convection; they bounce, conduct heat to the plate and among themselves, and push it.
Per coupling step the heat given to the structure through the nodal loads equals the heat
the particles lost to it (round-off: an invariant of the transfer, true by construction);
the physics checks are that the total energy (particles + plate + convective
loss) is conserved to round-off, the nodal loads carry the particles' weight once they
rest, and the plate, heated on top, warms and deforms, and its thermal deformation reaches
the DEM wall.
"""
import numpy as np
import pytest

from gsi import meshes
from gsi.coupling.staggered import StaggeredCoupling
from gsi.coupling.thermal import ThermalCoupling
from gsi.dem import Material, Simulation
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat

D = "docs/design.md"  # where the references are written down

L, LZ = 0.03, 0.003
R = 2.0e-3
DT, N_SUB = 2.0e-5, 20
T_HOT, T_COLD = 600.0, 300.0
STEEL = dict(E=210e9, nu=0.3, rho=7850.0, c=440.0, k=53.3, alpha=12e-6)


@pytest.fixture(scope="module", params=[1, 2], ids=["P1", "P2"])
def run(request):
    """P1 and P2 elasticity (P2: the DEM wall is the contact face split at the edge
    midpoints, whose temperatures and heat the coupling maps to the P1 heat vertices)."""
    plate = meshes.build("box", length_x=L, length_y=L, length_z=LZ, n=(6, 6, 1))
    heat = Heat(plate, STEEL, dt=N_SUB * DT, T_initial=T_COLD)
    heat.set_convection("z0", 200.0, T_COLD)
    el = Elasticity(plate, STEEL, degree=request.param, T_ref=T_COLD)
    el.clamp("z0")
    sim = Simulation({"ore": Material(E=5e7, nu=0.25, rho=3000.0, e=0.3, mu=0.5, k=2.0,
                                      cp=10.0),
                      "steel": Material(E=210e9, nu=0.3, rho=7850.0, k=53.3, cp=440.0)},
                     heat="area", gravity=(0, 0, -9.81), dt=DT, skin=5e-4,
                     domain=((-0.01, -0.01, -0.01), (L + 0.01, L + 0.01, 0.05)))
    for point, normal in (((0, 0, 0), (1, 0, 0)), ((L, 0, 0), (-1, 0, 0)),
                          ((0, 0, 0), (0, 1, 0)), ((0, L, 0), (0, -1, 0))):
        sim.add_plane(point, normal, material="steel")          # adiabatic side walls
    mech = StaggeredCoupling(sim, el, wall_material="steel", n_sub=N_SUB, tag="z1")
    cp = ThermalCoupling(sim, heat, mechanics=mech, tag="z1", T_ref=T_COLD)
    g = np.linspace(0.25 * L, 0.75 * L, 3)
    x = np.array([(a, b, LZ + 1.5 * R + 0.3 * R * k) for k, (a, b) in
                  enumerate((a, b) for a in g for b in g)])
    sim.add_particles(x, R, material="ore", T=T_HOT)
    cp.run(300)                                                  # 0.12 s
    return cp


def test_heat_lost_by_particles_is_gained_by_the_plate_invariant_of_the_transfer(run, record_validation):
    h = run.history()
    assert np.count_nonzero(h["Q_particles"] > 0) > 100          # heat flowed on most steps
    record_validation("hot particles on a cold plate: |heat lost - heat gained| / largest step heat",
                      reference=0.0,
                      measured=float(np.abs(h["balance_error"]).max() / np.abs(h["Q_particles"]).max()),
                      tolerance=1e-12, kind="abs", source=f'{D}, "Validation cases" 9')
    assert np.abs(h["balance_error"]).max() <= 1e-12 * np.abs(h["Q_particles"]).max()
    # the convective exchange at the underside is in the balance (early on it is tiny and
    # of either sign: consistent-capacity P1 undershoots below T_ambient near a point load)
    assert np.abs(h["Q_boundary_loss"]).sum() > 1e6 * np.abs(h["drift"]).max()


def test_total_energy_is_conserved(run):
    h = run.history()
    # the stored energies are differences of int rho c T dx (~2800 J here) and of the
    # particle sum: round-off is relative to those totals
    E_total = STEEL["rho"] * STEEL["c"] * L * L * LZ * T_COLD + abs(h["E_particles"][0])
    assert np.abs(h["drift"]).max() <= 1e-12 * E_total
    assert h["n_particles"][-1] == 9


def test_plate_warms_and_carries_the_particles(run):
    h = run.history()
    assert h["T_wall_max"][-1] > T_COLD + 0.1
    assert h["E_structure"][-1] > 0.5 * h["Q_particles"].sum()
    assert h["T_particles_mean"][-1] < T_HOT - 10.0
    weight = 9 * 3000.0 * 4 / 3 * np.pi * R**3 * 9.81
    # time-averaged force on the structure over the last steps ~ the weight (at rest)
    assert np.mean(h["wall_force_z"][-20:]) == pytest.approx(-weight, rel=0.05)
    assert np.isfinite(h["max_von_mises"]).all() and h["max_von_mises"][-1] > 0


def test_deformed_plate_is_the_dem_wall(run):
    s = run.mechanics.interface
    assert np.abs(run.wall.vertices - s.positions()).max() <= 1e-15
    assert np.abs(s.displacement()).max() > 0
    # the mechanical balance of the same steps (the StaggeredCoupling record)
    m = run.mechanics.history()
    assert np.nanmax(m["balance_rel"]) <= 1e-12


def test_wall_temperature_is_the_linear_fe_field(run):
    """The DEM wall's vertex temperatures: the FE values at the surface vertices (as set
    for the last step) and, on a P2 wall, the mean of the two ends at each midpoint, so the
    barycentric interpolation on a refined triangle is the P1 field of the FE triangle."""
    T_wall = run.wall.vertex_temperature
    nv = run.surface.n_vertices
    T_vert = T_wall[:nv]
    assert T_vert.max() > T_COLD
    if run.mechanics.interface.n_midpoints:
        ends = run.mechanics.interface.midpoint_edges
        assert np.array_equal(T_wall[nv:], 0.5 * T_vert[ends].sum(axis=1))
        # the midpoints are where the interface puts them
        x0 = run.mechanics.interface.x0
        assert np.abs(x0[nv:] - 0.5 * x0[ends].sum(axis=1)).max() <= 1e-15
    else:
        assert len(T_wall) == nv
