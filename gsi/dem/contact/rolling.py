"""Rolling resistance: constant directional torque (CDT, LIGGGHTS ``epsd``-like).

M_r = -mu_r R* |F_n| omega_rel/|omega_rel| on particle i (omega_rel = omega_i - omega_j;
a wall's omega is not included), limited to |omega_rel| I*/dt so that within one step the
torque can stop the relative rotation but never reverse it (this removes the chatter of
a pure CDT at rest).  I* = I_i I_j/(I_i + I_j) (kg m^2; a wall: I_i).
"""
from gsi.jit import njit, sqrt, uint
from gsi.dem.contact.lanes import REFF, IEFF, WX, WY, WZ, FN, MX, MY, MZ
from gsi.dem.materials import P_MUR


@njit(_nrt=False)
def cdt(l0, l1, B, tab, row, dt):
    """The rolling torque ``MX..MZ`` on i of lanes l0..l1-1 (after the normal model)."""
    mu_r = tab[row, P_MUR]
    for l in range(uint(l0), uint(l1)):
        wx = B[WX + l]
        wy = B[WY + l]
        wz = B[WZ + l]
        w = sqrt(wx * wx + wy * wy + wz * wz)
        M = mu_r * B[REFF + l] * abs(B[FN + l])
        M_stop = w * B[IEFF + l] / dt     # inf (or nan: no limit) for dt = 0
        if M > M_stop:
            M = M_stop
        s = -M / w if w > 0.0 else 0.0
        B[MX + l] = s * wx
        B[MY + l] = s * wy
        B[MZ + l] = s * wz


@njit(_nrt=False)
def none(l0, l1, B, tab, row, dt):
    """No rolling resistance: zero torque."""
    for l in range(uint(l0), uint(l1)):
        B[MX + l] = 0.0
        B[MY + l] = 0.0
        B[MZ + l] = 0.0
