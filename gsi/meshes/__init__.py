"""gmsh-API builders of the structures gsi ships, picked by name (e.g. from TOML).

>>> from gsi import meshes
>>> sm = meshes.build("membrane", shape="circle", radius=0.5, thickness=0.01, h=0.05)
>>> sm.tags        # {'contact': 1, 'support': 2, 'outer': 3, 'volume': 100}

A user's own gmsh ``.geo`` or ``.msh`` file with physical groups:
``meshes.load_file("belt.geo", params={"length": 1.2})`` (:mod:`gsi.meshes.file`); the
repository's top-level ``meshes/`` folder (:data:`DIR`) holds the shipped gmsh geometries,
``belt.geo`` among them (a belt section with its own group names).

Every builder returns a :class:`StructureMesh` (dolfinx mesh, cell and facet tags, and the
name -> number map of its physical groups). Every builder tags at least "contact" (the
surface the bulk solid touches), "support" (where it is held) and "outer"; "box" (the
validation bar) tags its six faces instead.
"""
from __future__ import annotations

import inspect
import pathlib

from gsi.errors import GsiInputError

from . import box, drum, hopper, membrane, shell, silo
from ._common import StructureMesh
from .file import load as load_file
from .file import physical_groups

#: directory of the shipped gmsh files (belt.geo): the top-level ``meshes/`` folder of the
#: source checkout (gsi is installed editable from it); this package holds only the Python
DIR = pathlib.Path(__file__).resolve().parents[2] / "meshes"


BUILDERS = {
    "membrane": membrane.build,
    "hopper": hopper.build,
    "silo": silo.build,
    "shell": shell.build,
    "drum": drum.build,
    "box": box.build,
}

#: surface groups each builder tags (without "volume")
GROUPS = {
    "membrane": list(membrane.NAMES),
    "hopper": list(hopper.NAMES),
    "silo": list(silo.NAMES),
    "shell": list(shell.NAMES),
    "drum": list(drum.NAMES),
    "box": list(box.FACES),
}

__all__ = ["BUILDERS", "StructureMesh", "build", "load_file", "physical_groups", "DIR", "GROUPS"]


def build(name: str, **params) -> StructureMesh:
    """Build the structure ``name`` with keyword parameters (units: m).

    Raises
    ------
    GsiInputError
        Unknown builder name, unknown parameter, or a bad parameter value.
    """
    if name not in BUILDERS:
        raise GsiInputError(f"structure.mesh = {name!r}: must be one of {sorted(BUILDERS)}")
    f = BUILDERS[name]
    allowed = [p for p in inspect.signature(f).parameters]
    for key in params:
        if key not in allowed:
            raise GsiInputError(f"structure.{name}.{key} = {params[key]!r}: unknown parameter; "
                                f"allowed: {', '.join(allowed)}")
    return f(**params)
