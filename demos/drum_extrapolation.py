# # Hours of heat from one turn: long-time extrapolation in a rotating drum
#
# A drum turns a bed of 5 mm spheres whose left half starts at 30 K and right half at
# 10 K; conduction through the contacts and the mixing of the bed bring them together
# over many turns.  Heat in moving granular media takes minutes to hours, the DEM step
# is 1e-4 s: here one period of DEM is logged and replayed instead of simulated again,
# the method of Haydar, Martin & Bonnefoy (2023), "Long time extrapolation of DEM with
# heat conduction in a moving granular medium", Chem. Eng. Sci. 277, 118815, and the
# replay is checked against the full DEM of the same drum run on.
#
# ## The physics
#
# Particles conduct through their contacts (the "area" model of LIGGGHTS, the paper's
# eqs. 1-5):
#
# $$ m_i c_p \frac{dT_i}{dt} = \sum_j H_{ij}(T_j - T_i), \qquad
#    H_{ij} = \frac{4 k_i k_j}{k_i + k_j}\sqrt{\pi a_{ij}^2} = 2 k \sqrt{A_{ij}}, $$
#
# a the Hertz contact radius; the drum wall is adiabatic.
#
# ## The method
#
# 1. From t0 (after one turn, a pseudo-periodic bed) to t1 = t0 + tau the DEM logs every
#    contact: the pair, its start, its duration m and its mean sqrt(A) (``contact_log.npz``;
#    sampled every n steps, a contact longer than Delta t_c^max split into rows, the
#    paper's Table 1 and Algorithm 2).
# 2. Pairing (eq. 6): the bijection sigma between the particles at t0 and at t1 that
#    minimises the summed distance; particle sigma(a) stands at t1 where a stood at t0, so
#    in the next period it does what a did.
# 3. Replay (Algorithm 3, eqs. 7-8), period after period through sigma: each row moves
#    Q m = H (T_k - T_l) m from k to l, in the order of the log.  Energy is conserved to
#    round-off; a row is stable for m < m c_p/H (it would be cut into sub-steps).
#
# The extrapolated configuration at every t_n is that of t1, relabelled.  The errors
# are the paper's: eq. 9 on 200 Voronoi cells (seeds: 200 particles drawn at random from
# the bed at t1), absolute and relative to the DEM's T_hot - T_cold; eq. 10, the heat
# moved from t_n to t_n+1.
#
# ## The drum
#
# The paper gives the particles and 5 s per turn, not the drum: gsi's family of drums
# (:mod:`gsi.studies.drum`) has 80,000 particles in R = 0.30 m, L = 0.60 m at 5 s per turn, Froude
# number omega^2 R/g = 0.048 (cascading, as the paper says of 5 s per turn), and smaller
# drums at the same Froude number.  This demo runs the CI size, 5,000 particles in
# R = 0.1191 m turning once in 3.15 s, one turn per period, six periods; ``--quick`` runs
# 640 particles in R = 0.06 m, a quarter turn per period (the paper also extrapolates by
# quarter turns, its Fig. 14).
#
# The same case is ``drum_extrapolation.toml``.

from gsi.studies.drum import drum_case, drum_geometry
from gsi.run import demo_main

# ## The case
#
# Materials of the paper's Tables 3-4 (E = 1e7 Pa, nu = 0.3, rho = 2500 kg/m^3, e = 0.2,
# mu_pp = 0.3, mu_pw = 0.5, mu_r = 0.002, k = 100 W/(m K), c_p = 840 J/(kg K)), a lattice
# fill settling for 0.8 s in the drum at rest, the halves set and the drum started at
# 0.8 s, one turn, then the logged period (sampled every 10 steps, rows of at most
# 0.01 s) and six periods of reference DEM.

case = drum_case(drum_geometry(5000), settle=0.8, extrapolation=True, spin_up=1.0,
                 period_turns=1.0, periods=6, every=10, dt_split=0.01,
                 name="drum_extrapolation")
case.output.pictures = True

# ## Quick form
#
# 640 particles: the drum of the family at the same Froude number, a quarter turn per
# period, settling for 0.5 s and a quarter turn of spin-up.

quick = drum_case(drum_geometry(640), settle=0.5, extrapolation=True, spin_up=0.25,
                  period_turns=0.25, periods=6, every=10, dt_split=0.01)
case.quick = {
    "run": {"duration": quick.run.duration},
    "dem": {"domain_lo": list(quick.dem.domain_lo), "domain_hi": list(quick.dem.domain_hi)},
    "particles": [{"count": 640, "region": {"radius": quick.particles[0].region.radius,
                                            "length": quick.particles[0].region.length}}],
    "walls": [{"radius": quick.walls[0].radius, "length": quick.walls[0].length,
               "facets": quick.walls[0].facets,
               "motion": {"events": [{"t": 0.5, "rpm": quick.walls[0].motion.events[0].rpm}]}}],
    "extrapolation": {"start": quick.extrapolation.start, "period": quick.extrapolation.period,
                      "halves": {"t": 0.5}},
    "output": {"interval": quick.output.interval},
}

# ## Run
#
# Output: ``contact_log.npz``; ``extrapolation.csv`` (per t_n: mean temperatures of the
# initially hot and cold particles, extrapolated and full DEM, eq. 9 absolute and
# relative, eq. 10, the drift of sum m c_p T); ``extrapolation_fields.png`` (the
# temperature field at t0, t1 and t7, full DEM above, extrapolated below, seen along the
# drum axis), ``extrapolation_means.png`` (T_hot and T_cold against time),
# ``extrapolation_cells.png`` (the eq. 9 error of each Voronoi cell at t7); the summary's
# last line holds the timings (DEM and extrapolated seconds per period, speed-up) and
# the error maxima.

result = None

if __name__ == "__main__":
    result = demo_main(case, description="Long-time heat extrapolation in a rotating drum")
