"""The one rule for every name that becomes part of a file name (``case.name``, walls,
structures, monitors, particle groups): letters, digits, '_', '-', '.', starting with a
letter, digit or '_', at most :data:`MAX_NAME` characters. So no name can hold a path
separator, start with '.' (``..``) or be empty, and nothing a case names is written
outside ``--out``."""
from __future__ import annotations

import re

from gsi.errors import GsiInputError

__all__ = ["NAME_RULE", "MAX_NAME", "check_name", "check_unique_across"]

NAME_RULE = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$")
MAX_NAME = 100


def check_name(key: str, name, what: str = "a file name") -> None:
    """One-line error for ``key = name`` unless it follows the rule (module docstring)."""
    if not isinstance(name, str) or not NAME_RULE.match(name) or len(name) > MAX_NAME:
        too_long = isinstance(name, str) and len(name) > MAX_NAME
        why = f"longer than {MAX_NAME} characters" if too_long else \
            "use letters, digits, '_', '-' or '.' only, not starting with '.'"
        raise GsiInputError(f"{key} = {name!r}: {why} (it becomes {what}; no paths)")


def check_unique_across(named: list[tuple[str, str]], what: str) -> None:
    """``named``: (key, name) pairs of several tables that share one name space (walls
    and structures: a wall monitor's target names either); refuse a repeat."""
    seen: dict[str, str] = {}
    for key, name in named:
        if name in seen:
            raise GsiInputError(f"{key} = {name!r}: already used by {seen[name]}; {what} "
                                f"names must be unique")
        seen[name] = key
