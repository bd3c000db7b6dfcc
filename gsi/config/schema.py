"""Typed, validated dataclasses from TOML tables.

A case section is a dataclass whose fields are declared with :func:`param`, which records the
unit, the allowed values and a one-line doc. :func:`load` walks a TOML table into such a
dataclass and raises :class:`gsi.errors.GsiInputError` with one line naming the key path, the
value and what is allowed::

    particles.radius = -0.001: must be > 0 (m)
    dem.contcat: unknown key; did you mean 'contact'? (allowed: contact, rolling, ...)

Field types understood: ``float``, ``int``, ``bool``, ``str``, ``tuple[float, ...]`` (a
vector, with ``length``), ``Optional[...]``, nested dataclasses, ``list[Dataclass]`` (TOML
array of tables) and ``dict[str, Dataclass]`` (a table of named tables).
"""
from __future__ import annotations

import dataclasses
import difflib
import math
import types
import typing
import warnings
from typing import Any, Callable

from gsi.errors import GsiInputError

__all__ = ["param", "load", "Check", "positive", "nonnegative", "between", "one_of", "Sane",
           "SANE"]


@dataclasses.dataclass(frozen=True)
class Check:
    """A predicate on a value and the words that say what it allows ("must be > 0")."""

    test: Callable[[Any], bool]
    says: str


def positive() -> Check:
    return Check(lambda v: v > 0, "must be > 0")


def nonnegative() -> Check:
    return Check(lambda v: v >= 0, "must be >= 0")


def between(lo: float, hi: float, *, open_lo: bool = False, open_hi: bool = False) -> Check:
    lo_op = (lambda a, b: a > b) if open_lo else (lambda a, b: a >= b)
    hi_op = (lambda a, b: a < b) if open_hi else (lambda a, b: a <= b)
    brl, brh = ("(" if open_lo else "["), (")" if open_hi else "]")
    return Check(lambda v: lo_op(v, lo) and hi_op(v, hi), f"must be in {brl}{lo}, {hi}{brh}")


def one_of(*choices: str) -> Check:
    return Check(lambda v: v in choices, "must be one of " + ", ".join(repr(c) for c in choices))


@dataclasses.dataclass(frozen=True)
class Sane:
    """The sane range of one physical quantity: a value outside [lo, hi] is refused (one
    line naming the key, the range and, via ``slips``, the unit the user probably typed);
    a value below ``warn_below`` gives a warning with ``warn_says``. Zero is left to the
    field's own check (0 often means "off")."""

    lo: float
    hi: float
    what: str
    #: (factor, unit): "did you give <unit>?" when value x factor lands inside [lo, hi]
    slips: tuple = ()
    warn_below: float | None = None
    warn_says: str = ""

    def verdict(self, v: float, unit: str) -> tuple[str, str] | None:
        """('error' or 'warning', words) for value ``v``, or None when it is sane."""
        a = abs(v)
        if v == 0 or not math.isfinite(v):
            return None
        if a < self.lo or a > self.hi:
            words = f"outside {self.lo:g} to {self.hi:g} {unit} for {self.what}"
            for factor, other in self.slips:
                if self.lo <= a * factor <= self.hi:
                    return "error", (f"{words}; did you give {other}? ({v:g} {other} = "
                                     f"{v * factor:g} {unit})")
            return "error", f"{words}; check the value and its unit"
        if self.warn_below is not None and a < self.warn_below:
            return "warning", self.warn_says.format(v=v, unit=unit, kelvin=f"{v + 273.15:g}")
        return None


#: the sane range of every quantity, by unit: every scalar key of that unit gets it
#: (``param(sane=False)`` opts out, e.g. a traction in Pa that is not a modulus)
SANE = {
    "Pa": Sane(1e4, 1e13, "a Young's modulus", slips=((1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa"))),
    "kg/m^3": Sane(10.0, 3e4, "a density", slips=((1e3, "g/cm^3"),)),
    "K": Sane(1.0, 5000.0, "a temperature", slips=(),
              warn_below=200.0,
              warn_says="below 200 K; did you give \u00b0C? ({v:g} \u00b0C = {kelvin} K); "
                        "temperatures are in K"),
    "W/(m K)": Sane(1e-3, 1e4, "a thermal conductivity", slips=()),
    "J/(kg K)": Sane(10.0, 1e5, "a specific heat capacity",
                     slips=((1e3, "kJ/(kg K)"),)),
}


def param(default: Any = dataclasses.MISSING, *, unit: str = "", check: Check | None = None,
          length: int | None = None, doc: str = "", default_factory: Any = dataclasses.MISSING,
          sane: bool = True):
    """A dataclass field with a unit, a check, a vector length and a doc line. A scalar
    of a unit in :data:`SANE` gets that quantity's sane range (``sane=False``: none)."""
    meta = {"unit": unit, "check": check, "length": length, "doc": doc,
            "sane": SANE.get(unit) if sane else None}
    if default_factory is not dataclasses.MISSING:
        return dataclasses.field(default_factory=default_factory, metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def _fmt(value: Any) -> str:
    if isinstance(value, str):
        return repr(value)
    if isinstance(value, dict):
        return "{...}"
    return str(value).replace("(", "[").replace(")", "]") if isinstance(value, tuple) else str(value)


def _fail(path: str, value: Any, says: str, unit: str = "") -> GsiInputError:
    u = f" ({unit})" if unit else ""
    return GsiInputError(f"{path} = {_fmt(value)}: {says}{u}")


def _strip_optional(tp: Any) -> tuple[Any, bool]:
    origin = typing.get_origin(tp)
    if origin in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        if len(args) == 1 and len(typing.get_args(tp)) == 2:
            return args[0], True
    return tp, False


def _convert(tp: Any, value: Any, path: str, meta: dict) -> Any:
    unit = meta.get("unit", "")
    tp, optional = _strip_optional(tp)
    if value is None:
        if optional:
            return None
        raise _fail(path, value, "must be given", unit)
    origin = typing.get_origin(tp)
    if dataclasses.is_dataclass(tp):
        if not isinstance(value, dict):
            raise _fail(path, value, f"must be a table of {tp.__name__} keys")
        return load(tp, value, path)
    if origin is list:
        (item,) = typing.get_args(tp)
        if not isinstance(value, list):
            raise _fail(path, value, "must be a list" + (" of tables ([[...]])" if dataclasses.is_dataclass(item) else ""))
        return [_convert(item, v, f"{path}[{i}]", meta) for i, v in enumerate(value)]
    if origin is dict:
        _, item = typing.get_args(tp)
        if not isinstance(value, dict):
            raise _fail(path, value, "must be a table")
        return {k: _convert(item, v, f"{path}.{k}", meta) for k, v in value.items()}
    if origin is tuple:
        args = typing.get_args(tp)
        item = args[0]
        if item is str:
            if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
                raise _fail(path, value, "must be a list of strings")
            return tuple(value)
        if not isinstance(value, (list, tuple)) or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
            raise _fail(path, value, "must be a list of numbers", unit)
        if item is int and not all(isinstance(v, int) for v in value):
            raise _fail(path, value, "must be a list of integers (counts)", unit)
        n = meta.get("length")
        if n is not None and len(value) != n:
            raise _fail(path, value, f"must have {n} components", unit)
        out = tuple(item(v) for v in value)
        if not all(math.isfinite(v) for v in out):
            raise _fail(path, value, "must be finite", unit)
        return out
    if tp is bool:
        if not isinstance(value, bool):
            raise _fail(path, value, "must be true or false")
        return value
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise _fail(path, value, "must be an integer", unit)
        return value
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise _fail(path, value, "must be a number", unit)
        if not math.isfinite(value):
            raise _fail(path, value, "must be finite", unit)
        return float(value)
    if tp is str:
        if not isinstance(value, str):
            raise _fail(path, value, "must be a string")
        return value
    if tp is Any:
        return value
    raise TypeError(f"schema: unsupported field type {tp!r} at {path}")  # programming error


def _check(value: Any, raw: Any, path: str, meta: dict) -> None:
    """Apply the field's check to ``value`` (each component of a vector); show ``raw``."""
    check: Check | None = meta.get("check")
    if check is None or value is None:
        return
    values = value if isinstance(value, tuple) else (value,)
    for v in values:
        if not check.test(v):
            raise _fail(path, raw, check.says, meta.get("unit", ""))


def _sane(value: Any, raw: Any, path: str, meta: dict) -> None:
    """The quantity's sane range (:class:`Sane`): a one-line error or warning."""
    sane: Sane | None = meta.get("sane")
    if sane is None or not isinstance(value, float):
        return
    found = sane.verdict(value, meta.get("unit", ""))
    if found is None:
        return
    level, words = found
    if level == "error":
        raise _fail(path, raw, words)
    warnings.warn(f"{path} = {_fmt(raw)}: {words}", stacklevel=4)


def load(cls: type, table: dict, path: str = "") -> Any:
    """Build dataclass ``cls`` from a TOML ``table``; ``path`` prefixes key names in errors."""
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    hints = typing.get_type_hints(cls)
    prefix = f"{path}." if path else ""
    for key in table:
        if key not in fields:
            near = difflib.get_close_matches(key, list(fields), n=1, cutoff=0.6)
            hint = f"did you mean '{near[0]}'? " if near else ""
            raise GsiInputError(f"{prefix}{key}: unknown key; {hint}(allowed: {', '.join(fields)})")
    kwargs = {}
    for name, f in fields.items():
        key_path = f"{prefix}{name}"
        if name in table:
            value = _convert(hints[name], table[name], key_path, dict(f.metadata))
            _check(value, table[name], key_path, dict(f.metadata))
            _sane(value, table[name], key_path, dict(f.metadata))
            kwargs[name] = value
        elif f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
            unit = f.metadata.get("unit", "")
            u = f" ({unit})" if unit else ""
            doc = f.metadata.get("doc", "")
            raise GsiInputError(f"{key_path}: missing; give {doc or 'a value'}{u}")
    obj = cls(**kwargs)
    validate = getattr(obj, "validate", None)
    if validate is not None:
        validate(path)
    return obj


def describe(cls: type, path: str = "") -> list[str]:
    """One line per key: path, type, unit, default and doc (for ``gsi check --keys``).

    Arrays of tables show as ``walls[].kind``, tables of named tables as
    ``materials.NAME.E``."""
    lines = []
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        if not f.init:
            continue
        tp, _ = _strip_optional(hints[f.name])
        p = f"{path}.{f.name}" if path else f.name
        origin = typing.get_origin(tp)
        args = typing.get_args(tp)
        if dataclasses.is_dataclass(tp):
            lines += describe(tp, p)
            continue
        if origin is list and args and dataclasses.is_dataclass(args[0]):
            lines.append(f"{p}[]  {f.metadata.get('doc', '')}".rstrip())
            lines += describe(args[0], f"{p}[]")
            continue
        if origin is dict and len(args) == 2 and dataclasses.is_dataclass(args[1]):
            lines += describe(args[1], f"{p}.NAME")
            continue
        if f.default is not dataclasses.MISSING:
            default = f" = {_fmt(f.default)}"
        elif f.default_factory is not dataclasses.MISSING:
            default = f" = {_fmt(f.default_factory())}"
        else:
            default = " (required)"
        unit = f" [{f.metadata.get('unit')}]" if f.metadata.get("unit") else ""
        lines.append(f"{p}{default}{unit}  {f.metadata.get('doc', '')}".rstrip())
    return lines
