# # Hopper onto membrane: a granular stream loads a clamped rubber membrane
#
# The XDEM scenario of Fig. 15 (seed 000): 2,000 spheres with the softwood properties of
# its Table 3 (r = 10 mm, rho = 400 kg/m^3, E = 0.5 MPa, nu = 0.45, mu = 0.8, e = 0.5; plus
# a rolling resistance mu_r = 0.2 standing in for the angular shape of wood chips) rain
# into a closed conical hopper and settle on a slide gate under the outlet. The gate slides
# away at 0.6 s; the stream falls 0.285 m onto a clamped natural-rubber membrane (radius
# 0.3 m, 15 mm thick, E = 2 MPa), which deflects under the impacts while bending waves run
# through it; the particles roll toward the deepest point and heap.
#
# ## The physics
#
# The membrane is linear elastic (P2 tetrahedra; P1 locks in bending),
#
# $$ M\ddot u + C\dot u + K u = f, \qquad C = a_0 M, $$
#
# integrated by generalized-alpha with spectral radius rho_inf = 0.3 (numerical damping of
# the step-to-step oscillation that staggered coupling excites once the heap outweighs the
# membrane) and 5 % mass-proportional damping of its lowest mode, a_0 = 2 zeta omega_1.
#
# Staggered coupling (gsi.coupling.staggered): the membrane's top face is a DEM mesh wall.
# One FE step of dt_FE = n_sub dt_DEM, with n_sub from the lowest period T_1 (Rayleigh
# quotient of the static deflection, 20 FE steps per period). Over the sub-cycle the
# particles push on the wall; a contact at point p with barycentric weights w_k puts
# $-F w_k\,dt$ on node k (for P2 the six-node basis values of the face at p: the consistent
# nodal load). The FE takes the sub-cycle average $P_k = \sum -F w_k dt / dt_{FE}$, steps,
# and the wall moves to $x_0 + u$ with velocity $\dot u$. Every coupling step
# $\sum_k P_k = -\bar F_{wall}$ to round-off -- an invariant of the transfer, printed as
# ``balance_max``; the physics check is that the load tends to the weight of the heap.
#
# The same case is ``hopper_membrane.toml``; ``--quick`` runs 400 spheres for 1.5 s.

from gsi.case import (Case, CaseInfo, Dem, Material, Monitor, Motion, Output,
                      ParticleSource, Region, Run, Size, Structure, Wall)
from gsi.case.structure import Contact
from gsi.case.walls import MotionEvent
from gsi.run import demo_main

# ## Materials
#
# The particles (XDEM Table 3), the membrane as the DEM sees it (the FE material "rubber"
# has the same E and nu) and the steel of the hopper and its gate.

materials = {
    "softwood": Material(E=5.0e5, nu=0.45, rho=400.0, e=0.5, mu=0.8, mu_r=0.2),
    "rubber": Material(E=2.0e6, nu=0.45, rho=930.0, e=0.5, mu=0.8, mu_r=0.2),
    "steel": Material(E=2.1e11, nu=0.3, rho=7850.0, e=0.5, mu=0.4, mu_r=0.2),
}

# ## Particles
#
# They rain into the closed hopper from a cylinder above its rim.

wood = ParticleSource(name="wood", material="softwood", fill="random", count=2000,
                      size=Size(kind="single", radius=0.01),
                      region=Region(kind="cylinder", centre=(0.0, 0.0, 0.56), radius=0.19,
                                    length=0.4))

# ## Walls: the hopper and its slide gate
#
# A cone from the outlet (r = 7 cm, seven particle diameters: free flow) at z = 0.3 m up
# to r = 24 cm; under the outlet a square plate that slides away sideways at 2 m/s at
# 0.6 s and stops once it has cleared the outlet (0.2 m of travel): a schedule motion.

hopper = Wall(name="hopper", kind="cone", material="steel", centre=(0.0, 0.0, 0.3),
              outlet_radius=0.07, top_radius=0.24, length=0.3, facets=48)
gate = Wall(name="gate", kind="plate", material="steel", centre=(0.0, 0.0, 0.3),
            edge_u=(0.18, 0.0, 0.0), edge_v=(0.0, 0.18, 0.0),
            motion=Motion(kind="schedule", events=[
                MotionEvent(t=0.6, velocity=(2.0, 0.0, 0.0)), MotionEvent(t=0.7)]))

# ## The membrane
#
# A clamped disc from the shipped gmsh builder, P2, generalized-alpha; its "contact"
# surface touches the particles.

membrane = Structure(
    name="membrane", mesh="membrane",
    geometry={"shape": "circle", "radius": 0.3, "thickness": 0.015, "h": 0.06,
              "n_thickness": 1},
    material="rubber", degree=2, scheme="generalized_alpha", rho_inf=0.3,
    damping_ratio=0.05, supports=["support"],
    contact=Contact(tags=("contact",), mode="mechanical", wall_material="rubber",
                    steps_per_period=20.0))

# ## Monitors
#
# The discharged mass (spheres wholly below the outlet) and the membrane's deflection,
# stress and load.

monitors = [
    Monitor(name="discharged", kind="discharge", point=(0.0, 0.0, 0.29),
            normal=(0.0, 0.0, -1.0)),
    Monitor(name="membrane", kind="structure", target="membrane"),
]

# ## The case
#
# ``--quick``: 400 particles, the gate opens at 0.45 s, 1.5 s in all.

case = Case(
    case=CaseInfo(name="hopper_membrane", description="2,000 softwood spheres (r = 10 mm) "
                  "fall 0.3 m from a hopper onto a 0.6 m rubber membrane"),
    run=Run(duration=3.6, seed=11),
    dem=Dem(contact="hertz", rolling=True, heat="none", gravity=(0.0, 0.0, -9.81),
            domain_lo=(-0.45, -0.45, -0.3), domain_hi=(0.45, 0.45, 1.0)),
    materials=materials, particles=[wood], walls=[hopper, gate], structures=[membrane],
    monitors=monitors, output=Output(interval=0.1),
    quick={"run": {"duration": 1.5}, "particles": [{"count": 400}],
           "walls": [{}, {"motion": {"events": [{"t": 0.45, "velocity": [2.0, 0.0, 0.0]},
                                                {"t": 0.55}]}}]})

# ## Run
#
# ``python demos/hopper_membrane.py [--quick] [--out DIR]``; with MPI the membrane is
# distributed: ``mpirun -n 2 python demos/hopper_membrane.py --quick``. Output:
# ``particles/`` and ``walls/`` (ParaView series), ``membrane.xdmf`` (displacement, von
# Mises stress), ``membrane_coupling.csv`` (every coupling step: load, wall force,
# balance, work), ``monitors/*.csv``, ``monitors.png``, pictures and a GIF.

result = None

if __name__ == "__main__":
    result = demo_main(case, description="Hopper onto membrane (XDEM Fig. 15)")
