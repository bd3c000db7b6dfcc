"""Thermal silo: hot clinker charged into a small steel bin whose outer wall is cooled.

What it shows
-------------
About 450 clinker particles (radius 3.5-4.5 mm) at 800 K are dropped into a small steel
bin (inner radius 5 cm, 8 cm high, 3 mm wall, flat 3 mm floor bolted to its foundation)
that starts at 293 K; the outer wall loses heat to 293 K air by convection
(h = 25 W/(m^2 K)). The particles settle, conduct heat to each other and to the wall;
the wall warms, expands and carries both the weight of the bed and the thermal stress of
its restrained floor (the floor's underside is clamped, so the heated floor cannot expand:
sigma ~ E alpha dT/(1 - nu), 3.6 MPa per kelvin; linear elasticity, no yield). The particle
loads alone give a few kPa: the thermal stress dominates by orders of magnitude, which the
run shows by splitting the stress into its thermal and particle-load parts (``stress.png``).
The summary prints the heat balance: the heat the particles lose
to the wall equals, step by step, the heat the wall receives (round-off), and the total
energy of particles + wall + convective loss drifts only by round-off.

Equations (DESIGN.md "Heat in particles", "Coupling", "Thermo-elastic")
----------------------------------------------------------------------
* particles: m c_p dT_i/dt = sum_j H_ij (T_j - T_i), H = 4 k_i k_j/(k_i + k_j) sqrt(pi a^2)
  (``area`` model; a the Hertz contact radius), explicit each DEM step;
* particle-wall: the same H with the steel's k, against the FE wall temperature
  interpolated at the contact point with the triangle's barycentric weights; the heat
  goes back to the wall as nodal heat loads -Q w_k, averaged over the sub-cycle;
* wall: rho c dT/dt = div(k grad T), -k dT/dn = h (T - T_amb) on the outer surface;
  sigma = C : (eps(u) - alpha (T - T_ref) I), loaded by the particle forces; the wall
  the DEM sees follows the deformation.

Time scale (documented choice)
------------------------------
Heat soaks into a steel wall over minutes, a DEM step is 30 microseconds. To see the
wall heat within a run of about a second of DEM time, the heat capacities of the
particles AND of the steel are divided by ``thermal.time_scale`` = 200: every thermal
time constant (contact conduction, conduction through the wall, convection) shrinks by
the same factor, so the temperatures at simulated time t are those of the real bin at
t_thermal = 200 t (the plots use t_thermal). Heat flows (W), temperatures and stresses
are physical; stored and exchanged energies (J) are the physical ones / 200. The energy
balance is exact in the scaled run. The mechanics (gravity, contact forces, the bed's
weight on the wall) is not scaled. The DEM uses a soft particle modulus (50 MPa, as usual
in DEM), which sets the contact radius a and thus the contact conductance.

The case lives in ``thermal_silo.toml`` beside this script (``gsi run
demos/thermal_silo.toml`` runs the same). Output (see :mod:`gsi.drivers.thermal_silo`):
``structure.xdmf`` (wall temperature, displacement, von Mises), ``particles.pvd``
(particles with temperature), ``energy.csv`` (energy record per coupling step),
``stress.csv``, ``history.png``, ``stress.png``, ``silo_*.png`` and ``silo.gif``.

Run: ``python demos/thermal_silo.py [--quick] [--out DIR]``; with MPI:
``mpirun -n 2 python demos/thermal_silo.py --quick`` (FE on both ranks, DEM on rank 0).
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _common import main  # noqa: E402

CASE = pathlib.Path(__file__).with_suffix(".toml")

if __name__ == "__main__":
    result = main(CASE, __doc__.splitlines()[0])
