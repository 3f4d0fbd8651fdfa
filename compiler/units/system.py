"""The one unit system of dyadc: unit strings as the library writes them ("kg.m2", "N.m.s/rad",
"m/s2") and as users type them (`-p L=100mm`), read into a scale factor to SI and a dimension.
Both the unit check of equations (compiler/units/check.py) and `-p` value conversions use it.

Grammar: a product of factors joined by `.`, `*` or a space, divided by `/`; a factor is a symbol
with an optional SI prefix and an optional integer power (`m2`, `s-1`, `m^2`, `m**2`), or a
parenthesised unit; `1` is the dimensionless unit. Symbols are matched whole before a prefix is
tried, so `min` is a minute, `Pa` a pascal, `mm` a millimetre.

Angles (rad, sr) are dimensionless, as SI and Modelica define them: `Unit.exponents` holds the
seven SI base dimensions only, and an equation `v = k*w` with k in N.m/A and w in rad/s checks.
The angle is still recorded (`Unit.angle`) so that a value typed by a user converts only between
units that agree on it: 10 Hz is not 10 rad/s. Offset units (degC, degF) convert values as
absolute temperatures (`convert_value`) and have no Unit: they cannot appear in an equation.
"""
from __future__ import annotations

import math
import re

from compiler.units.quantity import NAMED, OFFSET_UNITS, ONE, PLAIN, PREFIXABLE, PREFIXES, SECOND, scaled, \
    Unit, UnitError

__all__ = ["ONE", "SECOND", "Unit", "UnitError", "conversion_factor", "convert_value", "describe",
           "describe_kind", "is_offset_unit", "parse_unit"]

_TOKEN = re.compile(r"\s*(?:(?P<symbol>[A-Za-z_%°µμΩ]+)|(?P<number>\d+)|(?P<op>\*\*|[.*/^()·-]))")
_PARSED: dict[str, Unit] = {}


def parse_unit(text: str) -> Unit:
    """The Unit of a unit string; a UnitError saying what could not be read (memoized: a library
    names a few hundred unit strings)."""
    found = _PARSED.get(text)
    if found is None:
        found = _PARSED[text] = _parse(text)
    return found


def is_offset_unit(text: str) -> bool:
    return text.strip() in OFFSET_UNITS


def conversion_factor(given: str, declared: str) -> float:
    """The number that turns a value in `given` units into one in `declared` units; a UnitError
    when the two measure different kinds of quantity (here the radian counts: Hz is not rad/s)."""
    if given.strip() == declared.strip():
        return 1.0                     # also for units with an offset, such as degC to degC
    source, target = parse_unit(given), parse_unit(declared)
    if source.exponents != target.exponents or source.angle != target.angle:
        raise UnitError(f"`{given}` ({source.dimension(angles=True)}) and `{declared}` "
                        f"({target.dimension(angles=True)}) measure different kinds of quantity")
    return source.factor / target.factor


def convert_value(value: float, given: str, declared: str) -> float:
    """`value` in `given` units as a value in `declared` units; temperatures in degC or degF
    convert to and from kelvin as absolute temperatures (20 degC is 293.15 K)."""
    given, declared = given.strip(), declared.strip()
    if given == declared:
        return value
    if given in OFFSET_UNITS or declared in OFFSET_UNITS:
        kelvin = _to_kelvin(value, given)
        return _from_kelvin(kelvin, declared)
    return value * conversion_factor(given, declared)


def describe_kind(text: str) -> str:
    """The kind of quantity a unit string measures, as a value conversion sees it (the radian
    counts): `kg.m/s2`, `rad/s`, `K` for a temperature in degC; a UnitError if unreadable."""
    if is_offset_unit(text):
        return "K"
    return parse_unit(text).dimension(angles=True)


def _to_kelvin(value: float, unit: str) -> float:
    if unit in OFFSET_UNITS:
        scale, offset = OFFSET_UNITS[unit]
        return value * scale + offset
    return value * conversion_factor(unit, "K")


def _from_kelvin(kelvin: float, unit: str) -> float:
    if unit in OFFSET_UNITS:
        scale, offset = OFFSET_UNITS[unit]
        return (kelvin - offset) / scale
    return kelvin * conversion_factor("K", unit)


def describe(unit: Unit) -> str:
    """A unit for a message: a named unit of the same dimension (with its factor when not 1),
    and the SI base form, e.g. `V (kg.m2/(s3.A))`, `0.001 m`."""
    for name in NAMED:
        named = parse_unit(name)
        if named.exponents == unit.exponents:
            scale = "" if math.isclose(unit.factor, 1.0, rel_tol=1e-9) else f"{unit.factor:g} "
            shown = f"{scale}{name}"
            base_form = unit.dimension()
            return shown if base_form == name else f"{shown} ({base_form})"
    scale = "" if math.isclose(unit.factor, 1.0, rel_tol=1e-9) else f"{unit.factor:g} "
    return f"{scale}{unit.dimension()}"


def _parse(text: str) -> Unit:
    tokens = _tokenize(text)
    if not tokens:
        raise UnitError(f"empty unit `{text}`")
    parser = _Parser(text, tokens)
    unit = parser.expression()
    if parser.position != len(tokens):
        raise UnitError(f"cannot read unit `{text}` after `{''.join(tokens[:parser.position])}`")
    return unit


def _tokenize(text: str) -> list[str]:
    tokens, position = [], 0
    stripped = text.strip()
    while position < len(stripped):
        match = _TOKEN.match(stripped, position)
        if match is None or match.end() == position:
            raise UnitError(f"cannot read unit `{text}`: unexpected `{stripped[position]}`")
        tokens.append(match.group(match.lastgroup))
        position = match.end()
    return tokens


class _Parser:
    """Recursive descent over tokens: expression := factor ((. | * | / | juxtaposition) factor)*."""

    def __init__(self, text: str, tokens: list[str]):
        self.text, self.tokens, self.position = text, tokens, 0

    def peek(self) -> str | None:
        return self.tokens[self.position] if self.position < len(self.tokens) else None

    def take(self) -> str:
        token = self.tokens[self.position]
        self.position += 1
        return token

    def expression(self) -> Unit:
        result = self.factor()
        while self.peek() is not None and self.peek() != ")":
            op = self.peek()
            if op in (".", "*", "·", "/"):
                self.take()
            result = result / self.factor() if op == "/" else result * self.factor()
        return result

    def factor(self) -> Unit:
        token = self.peek()
        if token is None:
            raise UnitError(f"unit `{self.text}` ends where a unit symbol is expected")
        if token == "(":
            self.take()
            inner = self.expression()
            if self.peek() != ")":
                raise UnitError(f"unit `{self.text}` has an unclosed `(`")
            self.take()
            return inner ** self.power()
        self.take()
        if token.isdigit():
            if token != "1":
                raise UnitError(f"unit `{self.text}`: a number `{token}` where a unit symbol is expected")
            return ONE
        if token[0].isalpha() or token[0] in "%°µμΩ_":
            return _symbol(token, self.text) ** self.power()
        raise UnitError(f"unit `{self.text}`: `{token}` where a unit symbol is expected")

    def power(self) -> int:
        """An optional exponent after a symbol: `2`, `-1`, `^2`, `^-1`, `**2`."""
        explicit = self.peek() in ("^", "**")
        if explicit:
            self.take()
        sign = 1
        if self.peek() == "-" and self.position + 1 < len(self.tokens) \
                and self.tokens[self.position + 1].isdigit():
            self.take()
            sign = -1
        if self.peek() is not None and self.peek().isdigit():
            return sign * int(self.take())
        if explicit or sign < 0:
            raise UnitError(f"unit `{self.text}`: an exponent is missing")
        return 1


def _symbol(token: str, text: str) -> Unit:
    if token in OFFSET_UNITS:
        raise UnitError(f"`{token}` has an offset from the SI unit and cannot be converted by a factor")
    if token in PREFIXABLE:
        return PREFIXABLE[token]
    if token in PLAIN:
        return PLAIN[token]
    for prefix in sorted(PREFIXES, key=len, reverse=True):
        rest = token[len(prefix):]
        if token.startswith(prefix) and rest in PREFIXABLE:
            return scaled(PREFIXES[prefix], PREFIXABLE[rest])
    raise UnitError(f"unknown unit `{token}` in `{text}`")
