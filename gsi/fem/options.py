"""Choices of the FE linear solvers that need neither dolfinx nor PETSc (``gsi check``).

See :mod:`gsi.fem._base` for the solvers themselves.
"""
from __future__ import annotations

import math
import re

from gsi.errors import GsiInputError

__all__ = ["SOLVERS", "ITERATIVE_RTOL", "AUTO_ITERATIVE_DOFS", "ITERATIVE_DEFAULTS",
           "choose_solver", "petsc_option_strings"]

SOLVERS = ("direct", "iterative", "auto")

#: Relative tolerance of the iterative solvers: the true (unpreconditioned) residual
#: ||b - A x|| <= ITERATIVE_RTOL ||b||. At 1e-10 the validation cases give the direct
#: solver's answers to their tolerances (see tests/unit/fem/test_fem_solvers.py).
ITERATIVE_RTOL = 1e-10

#: ``solver = "auto"`` takes the iterative solver from this many global dofs on.
#: Measured on this project's 2-core test machine with benchmarks/fe_scale.py (P2 silo
#: shell, one rank): see ``crossover`` in that script's docstring for the figures.
AUTO_ITERATIVE_DOFS = {"elasticity": 200_000, "heat": 200_000}

#: gsi's PETSc defaults of the iterative solvers (``petsc_options`` override them)
ITERATIVE_DEFAULTS = {
    "elasticity": {"ksp_type": "cg", "pc_type": "gamg", "pc_gamg_coarse_eq_limit": "1000",
                   "mg_levels_ksp_type": "chebyshev", "mg_levels_pc_type": "jacobi",
                   "mg_levels_esteig_ksp_type": "cg"},
    "heat_hypre": {"ksp_type": "cg", "pc_type": "hypre", "pc_hypre_type": "boomeramg"},
    "heat_gamg": {"ksp_type": "cg", "pc_type": "gamg", "pc_gamg_coarse_eq_limit": "1000",
                  "mg_levels_ksp_type": "chebyshev", "mg_levels_pc_type": "jacobi",
                  "mg_levels_esteig_ksp_type": "cg"},
}

_KEY_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def choose_solver(solver: str, n_dofs: int, problem: str, *, key: str = "structure.solver") -> str:
    """The solver actually used: ``solver`` itself, or for "auto" iterative from
    ``AUTO_ITERATIVE_DOFS[problem]`` global dofs on ("elasticity" or "heat")."""
    if solver not in SOLVERS:
        raise GsiInputError(f"{key} = {solver!r}: must be one of {', '.join(map(repr, SOLVERS))}")
    if solver != "auto":
        return solver
    return "iterative" if n_dofs >= AUTO_ITERATIVE_DOFS[problem] else "direct"


def petsc_option_strings(options, key: str = "structure.petsc") -> dict[str, str]:
    """Check the form of PETSc pass-through options and turn the values into PETSc's strings.

    Keys are option names without the leading dash (letters, digits, '_'); values are
    numbers, strings or booleans (a flag: ``ksp_monitor = true``).
    """
    if options is None:
        return {}
    if not isinstance(options, dict):
        raise GsiInputError(f"{key} = {options!r}: must be a table of PETSc options, e.g. "
                            "{ ksp_rtol = 1e-10 }")
    out = {}
    for k, v in options.items():
        if not isinstance(k, str) or not _KEY_RE.match(k):
            raise GsiInputError(f"{key}.{k}: not a PETSc option name; write it without the "
                                "leading '-' (letters, digits and '_', e.g. ksp_rtol)")
        if isinstance(v, bool):
            out[k] = "" if v else "false"       # a flag: present without a value
        elif isinstance(v, int):
            out[k] = str(v)
        elif isinstance(v, float):
            if not math.isfinite(v):
                raise GsiInputError(f"{key}.{k} = {v!r}: must be finite")
            out[k] = repr(v)
        elif isinstance(v, str) and v and not any(c.isspace() for c in v):
            out[k] = v
        else:
            raise GsiInputError(f"{key}.{k} = {v!r}: must be a number, a word or true/false")
    return out


