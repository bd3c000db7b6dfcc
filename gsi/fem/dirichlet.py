"""Prescribed values on tagged surfaces (Dirichlet conditions) of an FE problem:
:class:`Dirichlet` builds the dolfinx conditions of a structure's facet tags and keeps the
owned dofs of each tag (for reactions and boundary heat flows)."""
from __future__ import annotations

import numpy as np
from petsc4py import PETSc

from gsi.errors import GsiInputError

from . import compat


class Dirichlet:
    """The Dirichlet conditions of one problem on ``structure`` (a
    :class:`gsi.meshes.StructureMesh`).

    Attributes
    ----------
    bcs : list
        The dolfinx conditions, in the order given (the assembly's ``bcs``).
    values : list of (tag, components, values)
        What each :meth:`prescribe` call asked for (components None: a scalar space).
    """

    def __init__(self, structure):
        self.structure = structure
        self.bcs = []
        self.values: list[tuple[str, tuple | None, np.ndarray]] = []
        self._dofs: dict[str, np.ndarray] = {}

    def prescribe(self, tag: str, V, value, *, components=None) -> None:
        """Prescribe ``value`` on surface ``tag`` of the space ``V``: one number for a
        scalar space (``components`` None), one per component of ``components`` of a
        vector space."""
        facets = compat.meshtag_find(self.structure.facet_tags,
                                     self.structure.facet_tag(tag))
        fdim = self.structure.mesh.topology.dim - 1
        if components is None:
            spaces, vals = [V], [value]
        else:
            spaces, vals = [V.sub(c) for c in components], list(value)
        owned = []
        for Vc, vc in zip(spaces, vals):
            dofs = compat.locate_dofs_topological(Vc, fdim, facets)
            bc = compat.dirichletbc(PETSc.ScalarType(vc), dofs, Vc)
            self.bcs.append(bc)
            owned.append(compat.bc_dofs_owned(bc))
        self.values.append((tag, components, np.atleast_1d(np.asarray(value, float))))
        prev = self._dofs.get(tag, np.zeros(0, dtype=np.int64))
        self._dofs[tag] = np.unique(np.concatenate([prev] + owned))

    @property
    def tags(self) -> tuple[str, ...]:
        """The tags with a prescribed value, in the order given."""
        return tuple(self._dofs)

    def dofs(self, tag: str | None = None, *, key: str = "tag") -> np.ndarray:
        """Owned (local, unrolled) dofs prescribed on ``tag`` (all tags if None), sorted;
        an unknown tag is an error naming ``key``."""
        if tag is None:
            return np.unique(np.concatenate([np.zeros(0, np.int64)] + list(self._dofs.values())))
        if tag not in self._dofs:
            raise GsiInputError(f"{key} = {tag!r}: must be one of the prescribed tags "
                                f"{sorted(self._dofs)}")
        return self._dofs[tag]

    def moves(self) -> bool:
        """Whether some prescribed value is nonzero (local, no MPI call)."""
        return any(np.any(v) for _, _, v in self.values)
