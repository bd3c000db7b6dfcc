# # Pour: glass beads settle into a box
#
# The smallest complete gsi study, composed from parts: 2,000 glass beads (radius
# 1.8-2.2 mm, the soft glass of the LIGGGHTS ``settle`` benchmark) are placed at random
# above a 6 x 6 cm open box and fall under gravity until they rest as a bed.
#
# ## The physics
#
# Every pair of spheres in contact with overlap $\delta > 0$ pushes apart with the
# Hertz-Mindlin law (the LIGGGHTS ``hertz`` model), normal part
#
# $$ F_n = k_n \delta - \gamma_n v_n, \qquad k_n = \tfrac43 E^* \sqrt{R^* \delta}, \qquad
#    \gamma_n = -2\sqrt{5/6}\,\beta\sqrt{S_n m^*}, \quad S_n = 2E^*\sqrt{R^*\delta}, $$
#
# with $\beta = \ln e/\sqrt{\ln^2 e + \pi^2}$ from the restitution $e$, and a tangential
# spring $k_t = 8 G^* \sqrt{R^*\delta}$ capped by Coulomb friction $\mu |F_n|$. A wall is
# a sphere of infinite radius and mass. Velocity Verlet advances the beads with a step of
# 0.2 Rayleigh times, $t_R = \pi R \sqrt{\rho/G}/(0.1631\nu + 0.8766)$.
#
# Once the bed is at rest, the walls carry its weight: $\sum_w \mathbf F_w = -\sum_i m_i
# \mathbf g$. That balance is what the summary prints ("walls and structures carry ...
# % of the particles' weight") and what ``tests/demos/test_demos.py`` checks.
#
# The same case is ``pour.toml`` beside this script: ``gsi run demos/pour.toml`` gives
# the same numbers.

from gsi.case import (Case, CaseInfo, Dem, Material, Monitor, Output, ParticleSource,
                      Region, Run, Size, Wall)
from gsi.run import demo_main

# ## The material
#
# One material serves the beads and the box walls (a pair of equal materials keeps their
# e and mu).

glass = Material(E=5.0e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5, k=1.0, cp=840.0)

# ## The particles
#
# A random fill of 2,000 beads in a box region above the container, falling at 0.5 m/s.

beads = ParticleSource(name="beads", material="glass", fill="random", count=2000,
                       velocity=(0.0, 0.0, -0.5),
                       size=Size(kind="uniform", min=0.0018, max=0.0022),
                       region=Region(kind="box", lo=(0.0, 0.0, 0.05), hi=(0.06, 0.06, 0.15)))

# ## The walls
#
# An open box: five planes (a floor and four sides).

box = Wall(name="box", kind="box", material="glass", lo=(0.0, 0.0, 0.0), hi=(0.06, 0.06, 0.2))

# ## What to record
#
# The force of the beads on the box (it tends to their weight) and the state of the bed
# (count, kinetic energy, contacts, height).

monitors = [Monitor(name="box_load", kind="wall", target="box"),
            Monitor(name="bed", kind="particles")]

# ## The case
#
# The parts compose into one case; ``[quick]`` keeps the first 0.25 s (what the tests run).

case = Case(
    case=CaseInfo(name="pour", description="2,000 glass beads (r = 2 mm) fall 5 cm into a "
                  "6 x 6 cm box and settle"),
    run=Run(duration=0.6, seed=7),
    dem=Dem(contact="hertz", rolling=False, heat="none", gravity=(0.0, 0.0, -9.81),
            domain_lo=(-0.01, -0.01, -0.01), domain_hi=(0.07, 0.07, 0.2)),
    materials={"glass": glass}, particles=[beads], walls=[box], monitors=monitors,
    output=Output(interval=0.02, picture_every=5),
    quick={"run": {"duration": 0.25}})

# ## Run
#
# ``python demos/pour.py [--quick] [--out DIR]``: the runner writes ``particles/``
# (ParaView series), ``walls/``, ``monitors/*.csv``, ``monitors.png`` and the pictures,
# and prints the summary. ``result`` keeps what the run measured.

result = None

if __name__ == "__main__":
    result = demo_main(case, description="Pour: glass beads settle into a box")
