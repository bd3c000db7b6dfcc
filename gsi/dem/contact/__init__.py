"""Contact laws, one per file, registered by name.

A normal/tangential law is ONE numba function
``law(nx, ny, nz, delta, vx, vy, vz, R_eff, m_eff, tab, row, hist, k, dt) -> (fx, fy, fz, F_n)``
(``tab[row]`` is the pair-table row, ``hist[k]`` the tangential spring)
called by the particle–particle, particle–plane and particle–triangle geometry code
alike.  A rolling law is ``roll(wx, wy, wz, R_eff, F_n, tab, row, I_eff, dt) -> (Mx, My, Mz)``.
Each registry entry maps a name to ``(module, function name)``; the engine for a chosen
combination is generated once (see :mod:`gsi.dem.engine_factory`).
"""
CONTACT_LAWS = {
    "hertz": ("gsi.dem.contact.hertz", "hertz"),
    "linear": ("gsi.dem.contact.linear", "linear"),
}

ROLLING_LAWS = {
    False: ("gsi.dem.contact.rolling", "no_rolling"),
    True: ("gsi.dem.contact.rolling", "cdt"),
    "cdt": ("gsi.dem.contact.rolling", "cdt"),
}
