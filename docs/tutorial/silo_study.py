# # Your own silo, in Python
#
# The case of `silo.toml` built from the objects of `gsi.case`, run, and its wall load
# compared with Janssen's theory. Run from the repository's root:
#
#     python docs/tutorial/silo_study.py [--quick] [--out DIR]
#
# ## Janssen's silo
#
# In a bin of diameter $D$ filled to a depth $z$ with a bulk solid of bulk density
# $\rho_b$, wall friction $\mu_w$ and lateral pressure ratio $K = \sigma_h/\sigma_v$,
# the vertical stress tends to a limit instead of growing as $\rho_b g z$:
#
# $$ \sigma_v(z) = \frac{\rho_b g D}{4\mu_w K}\left(1 - e^{-4\mu_w K z/D}\right). $$
#
# Of the weight $\rho_b g A h$ of a bed of depth $h$ in the cylinder ($A = \pi D^2/4$), the
# part $A\,\sigma_v(h)$ rests on what is below it; the walls carry the rest by friction:
#
# $$ F_\text{wall} = \rho_b g A h - A\,\sigma_v(h). $$

import math
import pathlib
import sys

import numpy as np

from gsi.case import (Case, CaseInfo, Dem, Material, Monitor, Motion, Output, Pair,
                      ParticleSource, Region, Run, Size, Structure, Wall)
from gsi.case.structure import Contact
from gsi.case.walls import MotionEvent

HERE = pathlib.Path(__file__).resolve().parent

# ## The parts
#
# Soft glass beads (a soft material keeps the time step large) and steel for the hopper
# cone and the gate.

glass = Material(E=5.0e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5)
steel = Material(E=2.1e11, nu=0.3, rho=7850.0, e=0.5, mu=0.3)
beads_on_steel = Pair(materials=["glass", "steel"], e=0.5, mu=0.3)   # Janssen's mu_w

beads = ParticleSource(
    name="beads", material="glass", fill="lattice", count=2000,
    size=Size(kind="single", radius=0.003),
    region=Region(kind="cylinder", centre=(0.0, 0.0, 0.004), axis=(0.0, 0.0, 1.0),
                  radius=0.037, length=0.15))

hopper = Wall(name="hopper", kind="cone", material="steel", centre=(0.0, 0.0, -0.015),
              outlet_radius=0.012, top_radius=0.043, length=0.015)
gate = Wall(name="gate", kind="plate", material="steel", centre=(0.0, 0.0, -0.016),
            edge_u=(0.04, 0.0, 0.0), edge_v=(0.0, 0.04, 0.0),
            motion=Motion(kind="schedule", events=[MotionEvent(t=0.6, velocity=(0.5, 0.0, 0.0)),
                                                   MotionEvent(t=0.7)]))

# The silo wall is the user's gmsh file: `tags` maps gsi's names (`contact`, `support`)
# onto the file's physical groups; `geometry` overrides its `DefineConstant`s.

silo = Structure(
    name="silo", file="silo.geo",
    geometry={"radius": 0.04, "height": 0.16, "thickness": 0.003, "h": 0.006},
    tags={"contact": "silo_inner", "support": "silo_foot"}, material="steel", degree=2,
    scheme="static", supports=["support"],
    contact=Contact(tags=["contact"], mode="mechanical", wall_material="steel", n_sub=20))

monitors = [Monitor(name="silo", kind="structure", target="silo"),
            Monitor(name="hopper", kind="wall", target="hopper"),
            Monitor(name="bed", kind="particles"),
            Monitor(name="discharged", kind="discharge", point=(0.0, 0.0, -0.04),
                    normal=(0.0, 0.0, -1.0))]

case = Case(
    case=CaseInfo(name="silo", description="glass beads fill a steel silo (user .geo), settle "
                  "on a hopper, and discharge"),
    run=Run(duration=1.5, seed=1),
    dem=Dem(contact="hertz", gravity=(0.0, 0.0, -9.81),
            domain_lo=(-0.08, -0.08, -0.12), domain_hi=(0.08, 0.08, 0.17)),
    materials={"glass": glass, "steel": steel}, pairs=[beads_on_steel], particles=[beads], walls=[hopper, gate],
    structures=[silo], monitors=monitors,
    output=Output(interval=0.05, color_by="speed", picture_every=2),
    quick={"run": {"duration": 0.9}, "particles": [{"count": 1500}]})
case.base_dir = HERE          # silo.geo is found beside this script

# ## Janssen against the run
#
# Two moments: the bed at rest before the gate opens (0.55 s), and the bed sliding down
# the wall while the silo discharges (0.75 s). From the monitors: the bed's top $h$
# (`bed.csv`), its mass (count × bead mass) and the wall's vertical load (`silo.csv`,
# `load_z_N`: the force of the beads on the wall). The bulk density follows from the
# mass in the hopper cone and the cylinder, $\rho_b = M/(V_\text{cone} + A h)$.


def janssen_wall_load(rho_b, D, h, mu_w, K, g=9.81):
    """Janssen's load (N) that a bed of depth h (m) puts on the wall by friction."""
    A = math.pi * D ** 2 / 4
    sigma_v = rho_b * g * D / (4 * mu_w * K) * (1 - math.exp(-4 * mu_w * K * h / D))
    return rho_b * g * A * h - A * sigma_v


def compare(out, *, t=0.55, D=0.08, mu_w=0.3, r=0.003, rho=2500.0):
    """Measured wall load at time t against Janssen's for K from 0.4 to 0.6."""
    def row(name):
        data = np.genfromtxt(pathlib.Path(out) / "monitors" / f"{name}.csv", delimiter=",",
                             names=True)
        return data[np.argmin(abs(data["time_s"] - t))]
    bed, wall = row("bed"), row("silo")
    m = rho * 4 / 3 * math.pi * r ** 3 * bed["count"]
    h = float(bed["bed_top_m"])                    # the cylinder starts at z = 0
    cone = math.pi * 0.015 / 3 * (0.043 ** 2 + 0.043 * 0.012 + 0.012 ** 2)
    rho_b = m / (cone + math.pi * D ** 2 / 4 * h)
    measured = -float(wall["load_z_N"])
    print(f"t = {t} s: bed {int(bed['count'])} beads, {m:.3f} kg, top {1000 * h:.1f} mm, "
          f"bulk density {rho_b:.0f} kg/m^3")
    print(f"wall load measured {measured:.3f} N (weight of the bed in the cylinder "
          f"{rho_b * 9.81 * math.pi * D ** 2 / 4 * h:.3f} N)")
    for K in (0.4, 0.5, 0.6):
        print(f"  Janssen, mu_w = {mu_w}, K = {K}: {janssen_wall_load(rho_b, D, h, mu_w, K):.3f} N")
    return measured


# ## Run
#
# `demo_main` gives the script the options of `gsi run` (`--quick`, `--out`, ...).

if __name__ == "__main__":
    from gsi.run import demo_main
    result = demo_main(case, description="Your own silo")
    args = sys.argv[1:]
    out = args[args.index("--out") + 1] if "--out" in args else pathlib.Path("out") / "silo"
    for t in (0.55, 0.75):
        compare(out, t=t)
