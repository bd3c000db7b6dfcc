"""Contact laws, one per file, registered by name.

A normal/tangential law is ONE numba function
``law(nx, ny, nz, delta, vx, vy, vz, R_eff, m_eff, tab, row, hx, hy, hz, dt)
-> (fx, fy, fz, F_n, hx, hy, hz)`` (``tab[row]`` is the pair-table row, ``h`` the
tangential spring before and after the step) called by the particle–particle,
particle–plane and particle–triangle geometry code alike.  A rolling law is
``roll(wx, wy, wz, R_eff, F_n, tab, row, I_eff, dt) -> (Mx, My, Mz)``.

A law reads only ``tab`` and writes no memory, so the engine's loop of laws over a batch
of contacts vectorizes.  Laws are compiled ``inline="always"`` (copied into the caller's
numba IR): a separately compiled law reaches the caller with LLVM's pairs of lanes (SLP)
already formed, which stop the loop vectorizer; they take roots with
:data:`gsi.jit.sqrt` (libm's ``sqrt`` is an opaque call to LLVM).
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
