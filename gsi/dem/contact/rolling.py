"""Rolling resistance: constant directional torque (CDT, LIGGGHTS ``epsd``-like).

M_r = -mu_r R* |F_n| omega_rel/|omega_rel| on particle i (omega_rel = omega_i - omega_j,
a wall: its omega is not included), limited to |omega_rel| I_eff/dt so that within one
step the torque can stop the relative rotation but never reverse it (this removes the
chatter of a pure CDT at rest).  I_eff = I_i I_j/(I_i + I_j) (kg m^2; a wall: I_i).
"""
from gsi.jit import njit, sqrt
from gsi.dem.materials import P_MUR


@njit(inline="always")   # into numba's IR: see gsi/dem/contact/__init__.py
def cdt(wx, wy, wz, R_eff, F_n, tab, row, I_eff, dt):
    """Rolling-resistance torque on particle i (N m).

    Parameters
    ----------
    wx, wy, wz : float
        Relative angular velocity omega_i - omega_j (rad/s).
    R_eff : float
        Effective radius (m).
    F_n : float
        Normal force magnitude (N).
    tab, row : ndarray, int
        Flattened pair table and the pair's row (uses ``P_MUR``).
    I_eff : float
        Effective moment of inertia (kg m^2).
    dt : float
        Time step (s).
    """
    w = sqrt(wx * wx + wy * wy + wz * wz)
    if w == 0.0:
        return 0.0, 0.0, 0.0
    M = tab[row, P_MUR] * R_eff * abs(F_n)
    M_stop = w * I_eff / dt if dt > 0.0 else M
    if M > M_stop:
        M = M_stop
    s = -M / w
    return s * wx, s * wy, s * wz


@njit(inline="always")
def no_rolling(wx, wy, wz, R_eff, F_n, tab, row, I_eff, dt):
    """No rolling resistance (zero torque)."""
    return 0.0, 0.0, 0.0
