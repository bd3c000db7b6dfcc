"""Long-time extrapolation of particle heat conduction from one period of DEM.

The method of Haydar, Martin & Bonnefoy (2023), "Long time extrapolation of DEM with
heat conduction in a moving granular medium", Chem. Eng. Sci. 277, 118815, built on the
motion extrapolation of Bednarek et al. (2019), Chem. Eng. Sci. 197, 223-234:

1. Run the DEM to a pseudo-periodic state at t0 and log every contact until t1 = t0 + tau
   (:meth:`gsi.dem.Simulation.start_contact_log`, :mod:`gsi.dem.contact_log`).
2. Pair the particles (their eq. 6, :func:`pair_particles`): the bijection sigma between
   the particles at t0 and at t1 that minimises the summed distance
   sum_a |x_a(t0) - x_sigma(a)(t1)|.  Particle sigma(a) stands at t1 where a stood at t0,
   so in the next period it does what a did: x_sigma(a)(t2) = x_a(t1).  After p periods
   the role of logged particle a is played by sigma^p(a).
3. Replay the log (their Algorithm 3 with eqs. 7-8, :class:`Replay`): period after
   period, each row (a, b, m, s) in the order of the log, applied to the particles
   k = sigma^p(a), l = sigma^p(b) that play a and b now:

       Q = H (T_k - T_l),  H = c s,  T_k <- T_k - Q m/C_k,  T_l <- T_l + Q m/C_l

   with C = m c_p (J/K) and c s the conductance of the DEM's heat model.  Rows with a
   wall that has a temperature exchange heat with it (T_k <- T_k + H m (T_w - T_k)/C_k,
   the wall's temperature fixed at its t0 value); rows with an adiabatic wall do
   nothing.  Each exchange conserves C_k T_k + C_l T_l, so sum C T is conserved to
   round-off.

   Stability (the explicit update of one row, their section 2.1.3): m < C/(2 K sqrt(a))
   = C/H, here with C the smaller heat capacity of the two.  A row that breaks it is
   replayed as s = floor(m H/C) + 1 equal sub-steps of m/s (each then within the
   bound), counted in :attr:`Replay.n_substepped`; ``on_unstable="error"`` refuses the
   log instead, naming the row and the largest stable ``dt_split``.

4. Between periods nothing else changes: the extrapolated configuration at every t_n is
   the configuration at t1 (particle sigma^(n-1)(a) stands at x_a(t1)), relabelled
   (:meth:`Replay.positions`).

5. A wall that is an FE heat structure (a heated kiln shell, :mod:`gsi.studies.kiln`):
   :class:`FEWallReplay` replays the period interval by interval, the FE stepping once
   per coupling interval with the wall rows' heat as its nodal loads (the live
   coupling's transfer), so the bed, the shell and the heat through the shell's
   boundary balance to round-off.

Error measures of the paper: :func:`cell_error` (its eq. 9, on Voronoi cells) and
:func:`energy_transfer_error` (its eq. 10).  Beside eq. 9, :func:`cell_sampling_level`
gives the eq.-9 error of two fields that hold the same temperatures in each cell but not
the same particles (a yardstick gsi adds: the granular flow is chaotic, so over a period
no method predicts which particle ends in which cell).


Modules: :mod:`~gsi.extrapolation.pairing` (eq. 6), :mod:`~gsi.extrapolation.replay`
(Algorithm 3), :mod:`~gsi.extrapolation.fe_replay` (an FE heat structure as the wall),
:mod:`~gsi.extrapolation.metrics` (eqs. 9-10), :mod:`~gsi.extrapolation.reference` (the
comparison with the full DEM), :mod:`~gsi.extrapolation.driver` (a case's ``[extrapolation]``),
:mod:`~gsi.extrapolation.figures` (its pictures).
"""
from gsi.extrapolation.driver import CaseExtrapolation
from gsi.extrapolation.fe_replay import FEWallReplay, rotate
from gsi.extrapolation.metrics import (cell_error, cell_means, cell_sampling_level,
                                       energy_transfer_error, finite_max, period_errors,
                                       voronoi_seeds)
from gsi.extrapolation.pairing import DENSE_PAIRING_MAX, pair_particles, pairing_cost
from gsi.extrapolation.reference import compare_with_dem
from gsi.extrapolation.replay import Replay

__all__ = ["pair_particles", "pairing_cost", "Replay", "FEWallReplay", "voronoi_seeds",
           "cell_means", "cell_error", "cell_sampling_level", "energy_transfer_error",
           "period_errors", "compare_with_dem", "CaseExtrapolation", "DENSE_PAIRING_MAX",
           "finite_max", "rotate"]
