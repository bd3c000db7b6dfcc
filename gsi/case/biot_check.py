"""The Biot-number check of a case (seed 001 (thesis), eq. II.4).

:func:`check_biot` is the case-level entry point for the runner and ``gsi check``
(:class:`gsi.run.Runner` calls it on the built DEM before the first step;
``gsi check`` through :func:`check_biot_at_start`, which builds the DEM): given a
case and its DEM (after :func:`gsi.run.build_simulation`, after ``Runner.setup`` or at
any time of a run), it reports the Biot number Bi = H/(k pi R) of the particle contacts
(:func:`gsi.post.biot.contact_biot`) and warns, naming ``dem.heat``, when Bi is not << 1
(above :data:`gsi.post.biot.BIOT_LIMIT` = 0.1). The thesis's case 4 (two particles of
R = 2 mm overlapping by 0.2 mm, ``radius`` model) gives Bi = 0.199 and a warning.
"""
from __future__ import annotations

import warnings

from gsi.post.biot import BIOT_LIMIT, BiotReport, contact_biot

__all__ = ["check_biot", "check_biot_at_start", "BiotWarning"]


class BiotWarning(UserWarning):
    """The particles' Biot number is not << 1 (their lumped temperature is questionable)."""


def check_biot(case, sim, *, limit: float = BIOT_LIMIT, warn: bool = True) -> BiotReport | None:
    """Biot number of the particle contacts of ``sim``; a :class:`BiotWarning` above ``limit``.

    Parameters
    ----------
    case : gsi.case.Case
        The case (its ``dem.heat`` names the model; 'none' returns None).
    sim : gsi.dem.Simulation
        The case's DEM, at the instant to report (its current contacts).
    limit : float
        Bi above which to warn (-), default 0.1.
    warn : bool
        Emit the warning (else only report).

    Returns
    -------
    gsi.post.biot.BiotReport or None
        None when the case has no particle heat.
    """
    if not case.thermal:
        return None
    rep = contact_biot(sim)
    if warn and rep.n_contacts and rep.max > limit:
        warnings.warn(
            f"dem.heat = {case.dem.heat!r}: {rep.describe()}; above {limit:g}, so the particles "
            f"are not isothermal and the lumped model misstates the conduction (seed 001 "
            f"(thesis) eq. II.4 asks Bi << 1); smaller overlaps (a stiffer contact: dem.k_n or "
            f"the materials' E) lower it", BiotWarning, stacklevel=2)
    return rep


def check_biot_at_start(case, dt: float, *, limit: float = BIOT_LIMIT) -> BiotReport | None:
    """:func:`check_biot` on the case's DEM as built at t = 0 (``gsi check``): the contacts
    the start positions make (e.g. the thesis's case 4, two particles overlapping by
    0.2 mm). None without particle heat, or when the set-up itself fails (an error only
    the set-up finds, e.g. positions drawn at the start; ``gsi run`` reports it)."""
    if not case.thermal:
        return None
    from gsi.case.build_dem import build_simulation
    from gsi.errors import GsiInputError
    try:
        sim, _, _ = build_simulation(case, dt=dt)
    except GsiInputError:
        return None
    return check_biot(case, sim, limit=limit)
