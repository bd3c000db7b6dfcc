# # Hours in a heated kiln from one quarter turn: long-time extrapolation with an FE wall
#
# A rotary kiln turns a bed of 5 mm spheres inside a steel shell whose outside is held
# at 393.15 K (the heating jacket).  The bed takes heat from the shell wherever it
# touches it, and the turning bed spreads it.  A bed heats over many minutes to hours,
# while the DEM step is 1e-4 s: here one period of the coupled DEM + FE run is logged
# and replayed instead of simulated again -- the method of Haydar, Martin & Bonnefoy
# (2023), "Long time extrapolation of DEM with heat conduction in a moving granular
# medium", Chem. Eng. Sci. 277, 118815, carried over to a wall that is an FE heat
# structure -- and the replay is checked against the full DEM + FE run of the same kiln.
#
# ## The physics
#
# Particles conduct through their contacts, to each other and to the shell (the "area"
# model, the paper's eqs. 1-5):
#
# $$ m_i c_p \frac{dT_i}{dt} = \sum_j H_{ij}(T_j - T_i) + \sum_w H_{iw}(T_w - T_i), \qquad
#    H = \frac{4 k_i k_j}{k_i + k_j}\sqrt{\pi a^2}, $$
#
# a the Hertz contact radius, T_w the shell's temperature at the contact.  The shell
# conducts, rho c dT/dt = div(k grad T), with T = 393.15 K on its outer surface,
# insulated ends, and the particles' heat as nodal heat loads on its inner surface (the
# live coupling of gsi.coupling.thermal, every 0.25 s).  The shell turns with the bed;
# its FE problem lives in the shell's own frame.
#
# ## The method
#
# 1. From t0 (a quarter turn after the kiln starts) to t1 = t0 + tau the DEM logs every
#    contact, wall contacts with their wall triangle (``contact_log.npz``).
# 2. Pairing (eq. 6): the bijection between the particles at t0 and at t1 that
#    minimises the summed distance; in each later period particle sigma(a) does what a
#    did.
# 3. Replay (Algorithm 3, eqs. 7-8), interval by interval: the rows of each 0.25 s
#    coupling interval move heat between particles, and between particles and the
#    shell's triangles at the shell's temperature at the interval's start; the heat the
#    shell gave becomes its nodal heat loads through the live coupling's own transfer,
#    and the FE takes one step.  The shell turns a quarter turn per period, so the
#    triangle a logged contact meets is turned back with it.  Energy -- sum m c_p T of
#    the bed, the shell's heat content and the heat in through its outer surface -- is
#    balanced to round-off.
#
# Errors against the full DEM + FE run on over the first periods: the paper's eq. 9 on
# Voronoi cells (absolute, and relative to T_hot - T_cold of the initially hot and cold
# halves), eq. 10 (the heat moved in each period), and the bed's and shell's mean
# temperatures.
#
# ## The kiln
#
# gsi.studies.kiln: the drum family of gsi.studies.drum at the seed's Froude number, turned about x
# once per 2 s (Fr = 0.06 for 640 particles in R = 0.06 m, cascading); the grains of
# the seed's Tables 3-4 with a limestone-like conductivity k = 2 W/(m K) (the seed's
# 100 would heat this small bed within minutes); the half y < 0 at 313.15 K and the
# other at 293.15 K when the kiln starts; a 5 mm steel shell (P1 tetrahedra) starting
# at 393.15 K; stationary adiabatic end plates.  This demo runs 640 particles, six
# periods of full DEM + FE and two hours extrapolated; ``--quick`` runs 300 particles
# (R = 0.047 m), three periods of full run and half an hour.
#
# The same case is ``kiln.toml``.

from gsi.studies.kiln import kiln_case, kiln_geometry
from gsi.run import demo_main

# ## The case
#
# A lattice fill settling 0.5 s in the kiln at rest, the halves set and the kiln
# started at 0.5 s, a quarter turn of spin-up, the logged quarter turn (sampled every 10
# steps, rows of at most 0.01 s), six quarter turns of full DEM + FE, 14,400 quarter
# turns (2 h) extrapolated.

case = kiln_case(kiln_geometry(640), settle=0.5, spin_up=0.25, period_turns=0.25,
                 hours=2.0, compare_periods=6, name="kiln")
case.output.pictures = True

# ## Quick form
#
# 300 particles in the kiln of the family for them (the same 2 s per turn), three
# periods of full run, half an hour extrapolated.

quick = kiln_case(kiln_geometry(300), settle=0.5, spin_up=0.25, period_turns=0.25,
                  hours=0.5, compare_periods=3, name="kiln")
shell = quick.structures[0]
case.quick = {
    "case": {"description": quick.case.description},
    "run": {"duration": quick.run.duration},
    "dem": {"domain_lo": list(quick.dem.domain_lo), "domain_hi": list(quick.dem.domain_hi)},
    "particles": [{"count": 300, "region": {"radius": quick.particles[0].region.radius,
                                            "length": quick.particles[0].region.length}}],
    "walls": [{}, {"point": list(quick.walls[1].point)}],
    "structures": [{"geometry": {"radius": shell.geometry["radius"],
                                 "length": shell.geometry["length"]}}],
    "extrapolation": {"periods": quick.extrapolation.periods, "compare_periods": 3},
}

# ## Run
#
# Output: ``shell.xdmf`` (ParaView: the shell's temperature in its own frame) and
# ``particles/``, ``walls/`` series of the live run; ``contact_log.npz``;
# ``extrapolation.csv`` (per period: the bed's mean, the hot and cold halves' means and
# the shell's mean temperature, extrapolated and -- over the live window -- full DEM +
# FE; eqs. 9 and 10; the bed's and shell's heat, the heat in through the outer surface);
# ``extrapolation_hours.png`` (bed and shell temperature against hours, the live window
# beside the extrapolated hours), ``extrapolation_fields.png``,
# ``extrapolation_means.png``, ``extrapolation_cells.png``.  The summary prints the mean
# bed temperature at t1 and at the end, the wall heat flow, and the energy balance.

result = None

if __name__ == "__main__":
    result = demo_main(case, description="Hours in a heated kiln: long-time heat "
                                         "extrapolation with an FE wall")
