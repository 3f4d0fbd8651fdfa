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
from fractions import Fraction
from operator import add, sub

# The SI base dimensions, in the order of the exponent tuple.
DIMENSIONS = ("kg", "m", "s", "A", "K", "mol", "cd")


class Unit:
    """`factor` times the SI unit of the dimension `exponents` (one per DIMENSIONS entry, ints or
    Fractions after a square root); `angle`: the power of the radian it was written with.
    Immutable by convention; a plain slotted class because the check builds tens of thousands."""
    __slots__ = ("factor", "exponents", "angle")

    def __init__(self, factor: float, exponents: tuple, angle: int | Fraction = 0):
        self.factor = factor
        self.exponents = exponents
        self.angle = angle

    def __mul__(self, other: "Unit") -> "Unit":
        return Unit(self.factor * other.factor, tuple(map(add, self.exponents, other.exponents)),
                    self.angle + other.angle)

    def __truediv__(self, other: "Unit") -> "Unit":
        return Unit(self.factor / other.factor, tuple(map(sub, self.exponents, other.exponents)),
                    self.angle - other.angle)

    def __pow__(self, power: int | Fraction) -> "Unit":
        if type(power) is int:
            return Unit(self.factor ** power, tuple(a * power for a in self.exponents),
                        self.angle * power)
        return Unit(self.factor ** float(power), tuple(_exact(a * power) for a in self.exponents),
                    _exact(self.angle * power))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Unit) and self.exponents == other.exponents \
            and self.factor == other.factor and self.angle == other.angle

    def __hash__(self) -> int:
        return hash((self.factor, self.exponents, self.angle))

    def __repr__(self) -> str:
        return f"Unit({self.factor!r}, {self.exponents!r}, {self.angle!r})"

    @property
    def is_dimensionless(self) -> bool:
        return not any(self.exponents)

    def consistent_with(self, other: "Unit") -> bool:
        """Same dimension (angles dimensionless) and conversion factor 1."""
        return self.exponents == other.exponents and math.isclose(self.factor, other.factor,
                                                                  rel_tol=1e-9)

    def dimension(self, angles: bool = False) -> str:
        """The dimension in SI base units, e.g. `kg.m/s2`, `1` when dimensionless; with
        `angles`, the radian as if it were a base unit (for value conversions)."""
        pairs = list(zip(DIMENSIONS, self.exponents)) + ([("rad", self.angle)] if angles else [])
        up = [_power_text(d, e) for d, e in pairs if e > 0]
        down = [_power_text(d, -e) for d, e in pairs if e < 0]
        text = ".".join(up) or "1"
        if len(down) > 1:
            return f"{text}/({'.'.join(down)})"
        return text + ("/" + down[0] if down else "")


class UnitError(ValueError):
    """A unit string that cannot be read, or two units of different kinds."""


def _exact(value):
    if isinstance(value, Fraction) and value.denominator == 1:
        return int(value)
    return value


def base(**powers: int) -> Unit:
    return Unit(1.0, tuple(powers.get(d, 0) for d in DIMENSIONS))


ONE = base()
SECOND = base(s=1)
_M, _KG, _A, _K = base(m=1), base(kg=1), base(A=1), base(K=1)
_RAD = Unit(1.0, ONE.exponents, 1)
_N = _KG * _M / SECOND ** 2
_J = _N * _M
_W = _J / SECOND
_C = _A * SECOND
_V = _W / _A


def _scaled(factor: float, unit: Unit) -> Unit:
    return Unit(factor * unit.factor, unit.exponents, unit.angle)


# Symbols that take SI prefixes.
_PREFIXABLE: dict[str, Unit] = {
    "m": _M, "g": _scaled(1e-3, _KG), "s": SECOND, "A": _A, "K": _K, "mol": base(mol=1),
    "cd": base(cd=1), "rad": _RAD, "sr": _RAD ** 2,
    "N": _N, "Pa": _N / _M ** 2, "J": _J, "W": _W, "C": _C, "V": _V, "F": _C / _V, "Ohm": _V / _A,
    "S": _A / _V, "Wb": _V * SECOND, "T": _V * SECOND / _M ** 2, "H": _V * SECOND / _A,
    "Hz": ONE / SECOND, "L": _scaled(1e-3, _M ** 3), "l": _scaled(1e-3, _M ** 3),
    "bar": _scaled(1e5, _N / _M ** 2), "eV": _scaled(1.602176634e-19, _J),
}
_PREFIXABLE["Ω"] = _PREFIXABLE["ohm"] = _PREFIXABLE["Ohm"]

# Symbols used only as they are.
_PLAIN: dict[str, Unit] = {
    "1": ONE, "min": _scaled(60.0, SECOND), "h": _scaled(3600.0, SECOND),
    "d": _scaled(86400.0, SECOND), "deg": _scaled(math.pi / 180, _RAD),
    "rpm": _scaled(2 * math.pi / 60, _RAD / SECOND), "t": _scaled(1e3, _KG),
    "%": _scaled(0.01, ONE),
}

_PREFIXES = {
    "Y": 1e24, "Z": 1e21, "E": 1e18, "P": 1e15, "T": 1e12, "G": 1e9, "M": 1e6, "k": 1e3, "h": 1e2,
    "da": 1e1, "d": 1e-1, "c": 1e-2, "m": 1e-3, "u": 1e-6, "µ": 1e-6, "μ": 1e-6, "n": 1e-9,
    "p": 1e-12, "f": 1e-15, "a": 1e-18, "z": 1e-21, "y": 1e-24,
}

# Units with an offset: a value in them is converted to kelvin as an absolute temperature.
OFFSET_UNITS = {"degC": (1.0, 273.15), "°C": (1.0, 273.15),
                "degF": (5 / 9, 273.15 - 32 * 5 / 9), "°F": (5 / 9, 273.15 - 32 * 5 / 9)}

# Named units a message shows a dimension with (factor 1), before falling back to base units.
NAMED = ("V", "A", "Ohm", "W", "J", "N", "Pa", "H", "F", "kg", "m", "s", "K", "mol", "cd", "m2",
         "m3", "m/s", "m/s2", "N/m", "kg.m2", "m3/s", "1/s", "1")

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
    if token in _PREFIXABLE:
        return _PREFIXABLE[token]
    if token in _PLAIN:
        return _PLAIN[token]
    for prefix in sorted(_PREFIXES, key=len, reverse=True):
        rest = token[len(prefix):]
        if token.startswith(prefix) and rest in _PREFIXABLE:
            return _scaled(_PREFIXES[prefix], _PREFIXABLE[rest])
    raise UnitError(f"unknown unit `{token}` in `{text}`")


def _power_text(symbol: str, power) -> str:
    if power == 1:
        return symbol
    return f"{symbol}{power}" if not isinstance(power, Fraction) else f"{symbol}^({power})"
