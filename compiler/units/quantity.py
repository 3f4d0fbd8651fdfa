"""The quantities of dyadc's unit system (compiler/units/system.py reads unit strings into them):
`Unit`, a scale factor to SI times a dimension over the seven SI base dimensions, with the power
of the radian it was written with kept aside (angles are dimensionless); the symbols, prefixes
and offset units the library and users write.
"""
from __future__ import annotations

import math
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


def scaled(factor: float, unit: Unit) -> Unit:
    return Unit(factor * unit.factor, unit.exponents, unit.angle)


# Symbols that take SI prefixes.
PREFIXABLE: dict[str, Unit] = {
    "m": _M, "g": scaled(1e-3, _KG), "s": SECOND, "A": _A, "K": _K, "mol": base(mol=1),
    "cd": base(cd=1), "rad": _RAD, "sr": _RAD ** 2,
    "N": _N, "Pa": _N / _M ** 2, "J": _J, "W": _W, "C": _C, "V": _V, "F": _C / _V, "Ohm": _V / _A,
    "S": _A / _V, "Wb": _V * SECOND, "T": _V * SECOND / _M ** 2, "H": _V * SECOND / _A,
    "Hz": ONE / SECOND, "L": scaled(1e-3, _M ** 3), "l": scaled(1e-3, _M ** 3),
    "bar": scaled(1e5, _N / _M ** 2), "eV": scaled(1.602176634e-19, _J),
}
PREFIXABLE["Ω"] = PREFIXABLE["ohm"] = PREFIXABLE["Ohm"]

# Symbols used only as they are.
PLAIN: dict[str, Unit] = {
    "1": ONE, "min": scaled(60.0, SECOND), "h": scaled(3600.0, SECOND),
    "d": scaled(86400.0, SECOND), "deg": scaled(math.pi / 180, _RAD),
    "rpm": scaled(2 * math.pi / 60, _RAD / SECOND), "t": scaled(1e3, _KG),
    "%": scaled(0.01, ONE),
}

PREFIXES = {
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


def _power_text(symbol: str, power) -> str:
    if power == 1:
        return symbol
    return f"{symbol}{power}" if not isinstance(power, Fraction) else f"{symbol}^({power})"
