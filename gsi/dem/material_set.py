"""The materials of a DEM simulation (:class:`MaterialSet`): names, their indices (a
particle's ``type``, a wall's material) and the pair table the contact laws read
(:func:`gsi.dem.materials.pair_table`)."""
from gsi.errors import GsiInputError
from gsi.dem.checks import pair_override_indices, rayleigh_time_min
from gsi.dem.materials import pair_table


class MaterialSet:
    """``materials`` (name -> :class:`gsi.dem.materials.Material`, validated by the
    caller) in index order, and their pair table with the laws' constants (``k_n`` N/m,
    ``h_c`` W/K, ``pipe_length`` m, ``pipe_resistance`` K m/W; None: 0) and
    ``pair_overrides`` ``{("mat_a", "mat_b"): {"e": .., "mu": .., "mu_r": ..}}``."""

    def __init__(self, materials, *, k_n=None, h_c=None, pipe_length=None,
                 pipe_resistance=None, pair_overrides=None):
        self.materials = dict(materials)
        self.names = list(self.materials)
        self._index = {k: i for i, k in enumerate(self.names)}
        overrides = pair_override_indices(pair_overrides, self._index)
        self.table = pair_table([self.materials[k] for k in self.names],
                                k_n=k_n or 0.0, h_c=h_c or 0.0, pipe_length=pipe_length or 0.0,
                                pipe_resistance=pipe_resistance or 0.0,
                                pair_overrides=overrides)

    def index(self, name, key="material") -> int:
        """Index of material ``name``; an unknown name is a one-line error naming ``key``."""
        if name not in self._index:
            raise GsiInputError(f"{key} = {name!r}: unknown material, known: {self.names}")
        return self._index[name]

    def rayleigh_time(self, radius, mtype) -> float:
        """min over particles (radii ``radius``, material indices ``mtype``) of the
        Rayleigh time t_R (s) (inf without particles)."""
        return rayleigh_time_min(radius, mtype, self.materials, self.names)
