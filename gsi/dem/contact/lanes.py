"""The lane buffer: the contacts of one batch, one field after the other.

A contact is evaluated in *lanes*: the geometry code (sphere pairs, planes, triangles)
writes each contact's geometry into one lane of a buffer ``B`` (``CH`` lanes per field;
field ``F`` of lane ``l`` is ``B[F + l]``), then each sub-model of the contact model
(:mod:`gsi.dem.contact.model`: normal, tangential, rolling, heat) runs one loop over the
lanes of a run that shares one pair-table row, reading and writing named fields.  A loop
touches only the buffer and the table row, so LLVM vectorizes it (4 lanes per AVX2
instruction, square roots and divisions included).  The same fields serve every kind of
contact: for a wall, R_j and m_j are infinite, so R* = R_i, m* = m_i, I* = I_i.

Inputs (written by the geometry code):

- ``NX, NY, NZ``   unit normal from particle i towards its partner (-); a sphere pair's
  gather writes the centre offset x_j - x_i here first (:func:`gsi.dem.engine.pair_geometry`)
- ``DELTA``        overlap (m), > 0
- ``VX, VY, VZ``   velocity of i relative to the partner at the contact point (m/s)
- ``REFF, MEFF, IEFF``  R* (m), m* (kg), I* = I_i I_j/(I_i + I_j) (kg m^2)
- ``WX, WY, WZ``   relative angular velocity omega_i - omega_j (rad/s), for rolling
- ``A2``           squared contact radius a^2 (m^2) (docs/design.md, "Contact geometry")
- ``RI, RJ``       radii of the two bodies (m; a wall: inf)
- ``DTEMP``        T_j - T_i (K)
- ``HX, HY, HZ``   the tangential spring (m): read, then written back by the tangential model

Outputs (written by the sub-models):

- ``FN``           normal force magnitude (N, > 0 repulsive), elastic + damping
- ``KT, GT``       tangential stiffness (N/m) and damping (N s/m, <= 0) for the tangential model
- ``FX, FY, FZ``   total contact force on i (N)
- ``MX, MY, MZ``   rolling-resistance torque on i (N m)
- ``Q``            heat rate into i (W)
- ``GN``           normal damping coefficient gamma_n (N s/m, >= 0) of the normal model
- ``CT``           the tangential model's Coulomb factor: exactly 1 in stick, < 1 when
  the spring was capped (sliding)
- ``QF``           power dissipated in the contact (W; only with frictional heating,
  :mod:`gsi.dem.contact.dissipation`)
- ``FDX..FDZ``     the dissipative part of the force on i (N; frictional heating)

The sphere-pair path also uses ``AI, AJ`` (lever arms), the raw inputs ``MI, MJ, II, IJ``,
``WIX..WJZ`` and the torques ``TIX..TJZ`` on i and j.

Offsets are unsigned (``gsi.jit.uint``): numba tests a signed index for wrap-around, a
select that hides the address from LLVM's loop vectorizer.
"""
from gsi.jit import uint

#: lanes per batch: 72 lanes x 51 fields x 8 bytes = 29 kB stay in a 32 kB L1 cache
#: (40, 72, 136 and 264 lanes timed the same in the batched engine of 2026-12-03)
CH = 72

_NAMES = ("NX NY NZ DELTA VX VY VZ REFF MEFF IEFF WX WY WZ A2 RI RJ DTEMP HX HY HZ "
          "FN KT GT FX FY FZ MX MY MZ Q "
          "AI AJ MI MJ II IJ WIX WIY WIZ TIX TIY TIZ TJX TJY TJZ GN CT QF FDX FDY FDZ").split()
#: number of fields of the buffer (its size is NB * CH)
NB = len(_NAMES)

(NX, NY, NZ, DELTA, VX, VY, VZ, REFF, MEFF, IEFF, WX, WY, WZ, A2, RI, RJ, DTEMP, HX, HY, HZ,
 FN, KT, GT, FX, FY, FZ, MX, MY, MZ, Q,
 AI, AJ, MI, MJ, II, IJ, WIX, WIY, WIZ, TIX, TIY, TIZ, TJX, TJY, TJZ, GN, CT, QF, FDX, FDY,
 FDZ) = [
    uint(f * CH) for f in range(NB)]
