# # Thermal silo: hot clinker heats and stresses a steel bin
#
# 450 clinker particles at 800 K are charged into a small steel bin (radius 5 cm, 8 cm high,
# 3 mm wall) whose outer surface is cooled by air. The particles conduct heat among
# themselves and into the wall; the wall conducts, loses heat by convection, expands, and
# carries the bed. A thermo-mechanical wall-load study in miniature.
#
# ## The physics
#
# Particles (uniform temperature each, low Biot number), explicit every DEM step:
#
# $$ m_i c_{p,i} \frac{dT_i}{dt} = \sum_j H_{ij}(T_j - T_i), \qquad
#    H_{ij} = \frac{4 k_i k_j}{k_i + k_j}\sqrt{\pi a_{ij}^2} \quad (\text{the ``area'' model}), $$
#
# with a the Hertz contact radius; a particle-wall contact uses the wall's conductivity and
# the FE temperature interpolated at the contact point. The wall (P1 tetrahedra):
#
# $$ \rho c \,\partial_t T = \nabla\cdot(k\nabla T), \qquad -k\nabla T\cdot n = h(T - T_\infty)
#    \text{ on the outer surface}, $$
#
# backward Euler, loaded by the particles' heat as nodal Neumann terms (the heat they gave
# up, split by the barycentric weights of each contact), and quasi-static thermo-elasticity
# $\sigma = C:(\varepsilon(u) - \alpha (T - T_{ref}) I)$ under the thermal strain and the
# bed's weight.
#
# Every coupling step the heat the particles lose into the wall equals the heat the wall
# receives (an invariant of the transfer, ``heat_balance_max``), and the total energy
# $\sum m c_p (T - T_{ref}) + \int \rho c (T - T_{ref}) + \text{convection losses}$ is
# conserved to round-off (``drift_max``).
#
# Heat-capacity time scaling: heating a bin takes minutes, DEM steps are 30 us. The run
# divides particle c_p and steel c by s = 200 (``run.heat_time_scale``): every thermal time
# constant shrinks by s, so 0.3 s of simulated time shows 60 s of heating, with physical
# temperatures and heat flows. The mechanics is not scaled.
#
# The same case is ``thermal_silo.toml``.

from gsi.case import (Case, CaseInfo, Dem, Material, Monitor, Output, ParticleSource, Region,
                      Run, Size, Structure)
from gsi.case.structure import Contact, Convection, StructureThermal
from gsi.run import demo_main

# ## Materials
#
# Cement clinker: rho = 3150 kg/m^3 (true density of Portland clinker, Taylor, Cement
# Chemistry, 2nd ed., 1997), k = 1.6 W/(m K), c_p = 1000 J/(kg K) (within the ranges of kiln
# and cooler models at 500-800 K, e.g. Mujumdar & Ranade, Ind. Eng. Chem. Res. 45 (2006)
# 2315); E is the usual soft DEM modulus (it sets the contact radius and so H). The steel
# as the DEM sees it must have the structure's conductivity, 53.3 W/(m K) (EN 1993-1-2).

materials = {
    "clinker": Material(E=5.0e7, nu=0.25, rho=3150.0, e=0.3, mu=0.6, k=1.6, cp=1000.0),
    "steel": Material(E=210.0e9, nu=0.3, rho=7850.0, e=0.3, mu=0.6, k=53.3, cp=440.0),
}

# ## Particles
#
# 450 hot particles (r = 3.5-4.5 mm) placed at random in the bin.

clinker = ParticleSource(name="clinker", material="clinker", fill="random", count=450,
                         temperature=800.0, size=Size(kind="uniform", min=0.0035, max=0.0045),
                         region=Region(kind="cylinder", centre=(0.0, 0.0, 0.002), radius=0.045,
                                       length=0.1))

# ## The bin
#
# The shipped silo builder (flat bottom), steel from the library (E 210 GPa, nu 0.3,
# alpha 12e-6 1/K, k 53.3, c 440), quasi-static, clamped at its support; the contact is
# mechanical and thermal; the outer surface loses heat to air at 25 W/(m^2 K).

bin_ = Structure(
    name="bin", mesh="silo",
    geometry={"radius": 0.05, "height": 0.08, "thickness": 0.003, "bottom": "flat",
              "h": 0.008},
    material="steel", degree=1, scheme="static", supports=["support"],
    contact=Contact(tags=("contact",), mode="both", wall_material="steel", n_sub=50),
    thermal=StructureThermal(T_ref=293.15, T_initial=293.15, theta=1.0,
                             convection=[Convection(tag="outer", h=25.0, T_ambient=293.15)]))

# ## Monitors

monitors = [Monitor(name="clinker_T", kind="temperature", group="clinker"),
            Monitor(name="bin", kind="structure", target="bin")]

# ## The case

case = Case(
    case=CaseInfo(name="thermal_silo", description="450 clinker particles at 800 K settle in "
                  "a 10 cm steel bin cooled outside"),
    run=Run(duration=3.0, dt=3.0e-5, seed=3, heat_time_scale=200.0),
    dem=Dem(contact="hertz", heat="area", gravity=(0.0, 0.0, -9.81),
            domain_lo=(-0.07, -0.07, -0.02), domain_hi=(0.07, 0.07, 0.14)),
    materials=materials, particles=[clinker], structures=[bin_], monitors=monitors,
    output=Output(interval=0.05, color_by="temperature", picture_every=2),
    quick={"run": {"duration": 0.3}})

# ## Run
#
# Output: ``bin.xdmf`` (temperature, displacement, von Mises stress), ``bin_energy.csv``
# (the energy books of every coupling step), ``bin_coupling.csv``, ``monitors/*.csv``,
# particles coloured by temperature, pictures.

result = None

if __name__ == "__main__":
    result = demo_main(case, description="Thermal silo: hot clinker in a cooled steel bin")
