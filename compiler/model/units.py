"""Unit strings as the library writes them ("kg.m2", "N.m.s/rad", "m/s2") and as users type them
(`-p L=100mm`, `-p k=1e5N/m`): parsed into a scale factor to SI and a dimension, so that a value
given in one unit converts to a parameter's declared unit or is refused when they differ in kind.

Grammar: a product of factors joined by `.`, `*` or a space, divided by `/`; a factor is a symbol
with an optional SI prefix and an optional integer power (`m2`, `s-1`, `m^2`, `m**2`), or a
parenthesised unit; `1` is the dimensionless unit. Symbols are matched whole before a prefix is
tried, so `min` is a minute, `Pa` a pascal, `mm` a millimetre. Angles are a dimension of their
own: a frequency in Hz must not silently become an angular velocity in rad/s.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

# Base dimensions, in the order of the exponent tuple.
DIMENSIONS = ("m", "kg", "s", "A", "K", "mol", "cd", "rad")


@dataclass(frozen=True)
class Quantity:
    """`factor` SI units of the dimension `exponents` (one integer per DIMENSIONS entry)."""
    factor: float
    exponents: tuple[int, ...]

    def __mul__(self, other: "Quantity") -> "Quantity":
        return Quantity(self.factor * other.factor,
                        tuple(a + b for a, b in zip(self.exponents, other.exponents)))

    def __truediv__(self, other: "Quantity") -> "Quantity":
        return self * other ** -1

    def __pow__(self, power: int) -> "Quantity":
        return Quantity(self.factor ** power, tuple(a * power for a in self.exponents))

    def dimension(self) -> str:
        """The dimension in base units, e.g. `kg.m/s2`, `1` when dimensionless."""
        up = [_power_text(d, e) for d, e in zip(DIMENSIONS, self.exponents) if e > 0]
        down = [_power_text(d, -e) for d, e in zip(DIMENSIONS, self.exponents) if e < 0]
        text = ".".join(up) or "1"
        if len(down) > 1:
            return f"{text}/({'.'.join(down)})"
        return text + ("/" + down[0] if down else "")


class UnitError(ValueError):
    """A unit string that cannot be read, or two units of different kinds."""


def _base(**powers: int) -> Quantity:
    return Quantity(1.0, tuple(powers.get(d, 0) for d in DIMENSIONS))


_ONE = _base()
_M, _KG, _S, _A, _K = _base(m=1), _base(kg=1), _base(s=1), _base(A=1), _base(K=1)
_N = _KG * _M / _S ** 2
_J = _N * _M
_W = _J / _S
_C = _A * _S
_V = _W / _A

# Symbols that take SI prefixes.
_PREFIXABLE: dict[str, Quantity] = {
    "m": _M, "g": Quantity(1e-3, _KG.exponents), "s": _S, "A": _A, "K": _K, "mol": _base(mol=1),
    "cd": _base(cd=1), "rad": _base(rad=1), "sr": _base(rad=2),
    "N": _N, "Pa": _N / _M ** 2, "J": _J, "W": _W, "C": _C, "V": _V, "F": _C / _V, "Ohm": _V / _A,
    "S": _A / _V, "Wb": _V * _S, "T": _V * _S / _M ** 2, "H": _V * _S / _A, "Hz": _ONE / _S,
    "L": Quantity(1e-3, (_M ** 3).exponents), "l": Quantity(1e-3, (_M ** 3).exponents),
    "bar": Quantity(1e5, (_N / _M ** 2).exponents), "eV": Quantity(1.602176634e-19, _J.exponents),
}
_PREFIXABLE["Ω"] = _PREFIXABLE["ohm"] = _PREFIXABLE["Ohm"]

# Symbols used only as they are.
_PLAIN: dict[str, Quantity] = {
    "1": _ONE, "min": Quantity(60.0, _S.exponents), "h": Quantity(3600.0, _S.exponents),
    "d": Quantity(86400.0, _S.exponents), "deg": Quantity(math.pi / 180, _base(rad=1).exponents),
    "rpm": Quantity(2 * math.pi / 60, (_base(rad=1) / _S).exponents),
    "t": Quantity(1e3, _KG.exponents), "%": Quantity(0.01, _ONE.exponents),
}

_PREFIXES = {
    "Y": 1e24, "Z": 1e21, "E": 1e18, "P": 1e15, "T": 1e12, "G": 1e9, "M": 1e6, "k": 1e3, "h": 1e2,
    "da": 1e1, "d": 1e-1, "c": 1e-2, "m": 1e-3, "u": 1e-6, "µ": 1e-6, "μ": 1e-6, "n": 1e-9,
    "p": 1e-12, "f": 1e-15, "a": 1e-18, "z": 1e-21, "y": 1e-24,
}

# Units with an offset (a temperature in degrees Celsius is not a multiple of one in kelvin).
_AFFINE = {"degC", "°C", "degF", "°F"}

_TOKEN = re.compile(r"\s*(?:(?P<symbol>[A-Za-z_%°µμΩ]+)|(?P<number>\d+)|(?P<op>\*\*|[.*/^()·-]))")


def parse_unit(text: str) -> Quantity:
    """The Quantity of a unit string; a UnitError saying what could not be read."""
    tokens = _tokenize(text)
    if not tokens:
        raise UnitError(f"empty unit `{text}`")
    parser = _Parser(text, tokens)
    quantity = parser.expression()
    if parser.position != len(tokens):
        raise UnitError(f"cannot read unit `{text}` after `{_joined(tokens[:parser.position])}`")
    return quantity


def conversion_factor(given: str, declared: str) -> float:
    """The number that turns a value in `given` units into one in `declared` units; a UnitError
    when the two measure different kinds of quantity."""
    if given.strip() == declared.strip():
        return 1.0                     # also for units with an offset, such as degC to degC
    source, target = parse_unit(given), parse_unit(declared)
    if source.exponents != target.exponents:
        raise UnitError(f"`{given}` ({source.dimension()}) and `{declared}` ({target.dimension()}) "
                        "measure different kinds of quantity")
    return source.factor / target.factor


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

    def expression(self) -> Quantity:
        result = self.factor()
        while self.peek() is not None and self.peek() != ")":
            op = self.peek()
            if op in (".", "*", "·", "/"):
                self.take()
            result = result / self.factor() if op == "/" else result * self.factor()
        return result

    def factor(self) -> Quantity:
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
            return _ONE
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


def _symbol(token: str, text: str) -> Quantity:
    if token in _AFFINE:
        raise UnitError(f"`{token}` has an offset from the SI unit and cannot be converted by a factor")
    if token in _PREFIXABLE:
        return _PREFIXABLE[token]
    if token in _PLAIN:
        return _PLAIN[token]
    for prefix in sorted(_PREFIXES, key=len, reverse=True):
        rest = token[len(prefix):]
        if token.startswith(prefix) and rest in _PREFIXABLE:
            base = _PREFIXABLE[rest]
            return Quantity(_PREFIXES[prefix] * base.factor, base.exponents)
    raise UnitError(f"unknown unit `{token}` in `{text}`")


def _power_text(symbol: str, power: int) -> str:
    return symbol if power == 1 else f"{symbol}{power}"


def _joined(tokens: list[str]) -> str:
    return "".join(tokens)
