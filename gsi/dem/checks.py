"""Checks of a DEM simulation: its options, the time-step rule and the heat-stability
check (thresholds: the
DT_* constants of :mod:`gsi.dem.materials`; the same rule as
``gsi.case.Case.time_step``, which a runner applies first and then passes
``dt_checked=True``).

Choices made here (beyond docs/design.md, "DEM physics"):

- Time step: Hertz: warn above 0.3 t_R, refuse above t_R (GsiInputError) unless
  ``force_dt``; t_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766), min over the particles.
  Linear: the pair contact lasts t_c = pi sqrt(m*/k_n) with m* = m_min/2; refuse
  dt > t_c/10 (fewer than 10 steps per contact), warn dt > t_c/50.
- Heat: explicit Euler T += dt Q/(m c_p) each step.  ``heat_stability()`` returns
  max_i dt sum_j H_ij/(m_i c_p,i) (pairs and planes with a temperature); it is checked
  at every neighbour rebuild: above 1 a GsiRunError (unless ``force_dt``), above 0.5 a
  warning.
- Radiation (off unless ``sim.set_radiation(...)``, :mod:`gsi.dem.radiation`): its own
  cached kernels and cell list at the radiation cut-off; every ``every`` steps the step
  loop stops the compiled chunk and applies the exchange at T_n over the interval
  (operator splitting beside the engine's contact heat).
- A particle outside the domain box is deleted and counted in ``n_lost``
  (``lost="error"`` raises GsiRunError instead).  A NaN or a speed above ``v_max``
  (m/s, default 100) stops the run with GsiRunError.
- Particles can be held in place: ``sim.fix(ids)`` (they feel forces, exchange heat,
  but do not move).
"""
import math
import warnings

import numpy as np

from gsi.errors import GsiInputError, GsiRunError
from gsi.dem.materials import (Material, DT_DEFAULT, DT_LINEAR_DEFAULT, DT_LINEAR_REFUSE, DT_REFUSE,
                               DT_WARN, rayleigh_time)


def rayleigh_time_min(radius, mtype, materials: dict, names: list) -> float:
    """min over particles of the Rayleigh time t_R (s) (inf without particles)."""
    tR = math.inf
    for t in np.unique(mtype):
        tR = min(tR, rayleigh_time(radius[mtype == t].min(), materials[names[t]]))
    return tR


def check_dt(sim) -> None:
    """Refuse ``sim.dt`` above DT_REFUSE t_R (linear law: DT_LINEAR_REFUSE t_c) unless
    ``sim.force_dt``, warn above DT_WARN t_R (DT_LINEAR_DEFAULT t_c)."""
    if sim.contact == "linear":
        t_ref = math.pi * math.sqrt(0.5 * sim.mass.min() / sim.k_n)
        name, default, warn, refuse = ("t_c = pi sqrt(m*/k_n) of the linear law",
                                       DT_LINEAR_DEFAULT, DT_LINEAR_DEFAULT, DT_LINEAR_REFUSE)
    else:
        t_ref = sim.rayleigh_time()
        name, default, warn, refuse = ("the Rayleigh time t_R", DT_DEFAULT, DT_WARN, DT_REFUSE)
    if sim.dt > refuse * t_ref * (1 + 1e-12):
        msg = (f"dt = {sim.dt}: above {refuse:g} x {name} = {t_ref:.3g} s; use dt <= "
               f"{default * t_ref:.3g} s or pass force_dt=True")
        if not sim.force_dt:
            raise GsiInputError(msg)
        warnings.warn(msg)
    elif sim.dt > warn * t_ref * (1 + 1e-12):
        warnings.warn(f"dt = {sim.dt} s is above {warn:g} x {name} = {t_ref:.3g} s; "
                      f"dt <= {default * t_ref:.3g} s is safe")


def check_heat(ratio: float, step: int, *, force: bool, warned: bool) -> bool:
    """The explicit heat update's stability ``ratio`` = max dt sum H/(m c_p): a
    GsiRunError above 1 (unless ``force``), a warning above 0.5 (once: returns whether
    it has been given)."""
    if ratio > 1.0 and not force:
        raise GsiRunError(
            f"heat: dt sum H/(m c_p) = {ratio:.3g} > 1 at step {step}: the explicit "
            "heat update is unstable; reduce run.dt, the conductivity or run.heat_time_scale, "
            "or set dem.force_dt = true (force_dt=True in Python)")
    if ratio > 0.5 and not warned:
        warnings.warn(f"heat: dt sum H/(m c_p) = {ratio:.3g} (stable below 1)")
        return True
    return warned


def check_options(materials, dt, skin, contact, k_n, heat, h_c, pipe_length,
                  pipe_resistance, lost, domain):
    """One-line errors for the simulation's options; returns the domain's corners."""
    if not materials:
        raise GsiInputError("materials = {}: give at least one Material")
    for name, m in materials.items():
        if not isinstance(m, Material):
            raise GsiInputError(f"materials.{name} = {m!r}: must be a gsi.dem.Material")
        m.validate(name)
    if not (dt > 0 and math.isfinite(dt)):
        raise GsiInputError(f"dt = {dt}: must be > 0 (s)")
    if not (skin > 0):
        raise GsiInputError(f"skin = {skin}: must be > 0 (m)")
    if contact == "linear" and not (k_n is not None and k_n > 0):
        raise GsiInputError(f"k_n = {k_n}: the linear law needs a normal stiffness > 0 (N/m)")
    if heat == "constant" and not (h_c is not None and h_c >= 0):
        raise GsiInputError(f"h_c = {h_c}: the constant heat model needs a conductance >= 0 "
                            "(W/K)")
    if heat == "pipe" and not (pipe_length is not None and pipe_length > 0
                               and pipe_resistance >= 0):
        raise GsiInputError(f"pipe_length = {pipe_length}: the pipe heat model needs a pipe "
                            "length > 0 (m) and pipe_resistance >= 0 (K m/W)")
    if lost not in ("delete", "error"):
        raise GsiInputError(f"lost = {lost!r}: must be 'delete' or 'error'")
    lo, hi = (np.asarray(domain[0], float), np.asarray(domain[1], float))
    if lo.shape != (3,) or hi.shape != (3,) or not (hi > lo).all():
        raise GsiInputError(f"domain = {domain}: must be ((xlo, ylo, zlo), (xhi, yhi, "
                            "zhi)) with hi > lo (m)")
    return lo, hi


def check_particles(x, radius, lo, hi):
    """Centres ``x`` (k, 3) finite and inside the domain box [lo, hi], radii > 0 (a
    number or (k,)); returns them as arrays ``(x, r)``."""
    x = np.atleast_2d(np.asarray(x, float))
    k = len(x)
    if x.shape != (k, 3) or not np.isfinite(x).all():
        raise GsiInputError(f"particles.x shape {x.shape}: must be (k, 3) finite (m)")
    r = np.broadcast_to(np.asarray(radius, float), (k,)).copy()
    if not (r > 0).all():
        raise GsiInputError(f"particles.radius = {r[~(r > 0)][:3].tolist()}: must be > 0 (m)")
    if ((x < lo) | (x > hi)).any():
        raise GsiInputError("particles.x: some centres lie outside the domain box; "
                            "enlarge domain or move them")
    return x, r


def pair_override_indices(pair_overrides, index: dict) -> dict:
    """``{("mat_a", "mat_b"): {...}}`` by material index; an unknown name is an error."""
    out = {}
    for (a, b), d in (pair_overrides or {}).items():
        for mname in (a, b):
            if mname not in index:
                raise GsiInputError(f"pair_overrides.{a}-{b}: unknown material {mname!r}")
        out[(index[a], index[b])] = d
    return out
