"""The valid models the fuzzer starts from, and the hostile values it puts into them.

Each seed simulates cleanly as written (tests/fuzz/test_fuzz_cli.py checks that first), so every
failure the fuzzer sees comes from its mutation, not from the seed.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Seed:
    name: str            # the component, and the file's stem
    text: str
    stop: str            # a --stop short enough for the example budget


OSCILLATOR = Seed("Oscillator", """\
"A mass on a linear spring: x = cos(2 t)."
component Oscillator
  parameter k::Real = 4.0
  parameter m::Real = 1.0
  variable x::Real(initial = 1.0)
  variable v::Real(initial = 0.0)
relations
  der(x) = v
  m * der(v) = -k * x
end
""", "1")

# Flat equations with an array, a for loop, a time event and SI suffixes: more syntax to mutate.
RC_LADDER = Seed("RCLadder", """\
"Two RC low-pass stages in series, driven by a step at 1 ms."
component RCLadder
  parameter R::Real = 1k
  parameter C::Real = 10u
  parameter V::Real = 5
  variable u::Real
  variable v::Real[2]
relations
  u = if time >= 0.001 then V else 0
  for i in 1:2
    initial v[i] = 0
  end
  R * C * der(v[1]) = u - v[1]
  R * C * der(v[2]) = v[1] - v[2]
end
""", "0.05")

# Library components, connectors and modifiers: exercises lookup, extends and connect.
LIBRARY_RC = Seed("LibraryRC", """\
"A constant source charges a capacitor through a resistor of the shipped library."
component LibraryRC
  source = ElectricalComponents.ConstantVoltage(V = 10)
  resistor = ElectricalComponents.Resistor(R = 100)
  capacitor = ElectricalComponents.Capacitor(C = 1e-3)
  ground = ElectricalComponents.Ground()
relations
  initial capacitor.v = 0
  connect(source.p, resistor.p)
  connect(resistor.n, capacitor.p)
  connect(capacitor.n, source.n, ground.g)
end
""", "0.5")

SEEDS = (OSCILLATOR, RC_LADDER, LIBRARY_RC)

# Numbers at and beyond the edges of a double, and integers far beyond them.
EXTREME_NUMBERS = ("nan", "inf", "-inf", "1e308", "-1e308", "1e400", "1e-400", "5e-324", "-0", "-0.0",
                   "0", "0.0", "1" + "0" * 5000, "9" * 400, "1e99999", ".5e", "0x1F", "1_000",
                   "00012", "1.7976931348623157e308", "2.2250738585072014e-308",
                   # sizes and exact powers beyond any model (issue 19 item 5): a located error
                   "1000000000", "9^9^9", "2^100000")

# Names a careless or hostile user might give: quotes, code, Unicode, path separators, keywords.
HOSTILE_NAMES = ('a"b', "a'b", '"""', "'''", "ω₀", "x\u202ey", "名前", "__import__",
                 '__import__("os").system("touch PWNED")', "a/b", "../up", "a\\b", "a.b", "a:b",
                 "time", "der", "end", "relations", "x" * 300, "_", "a b", "a\tb", "$HOME",
                 "{0}", "%s%n", "\U0001F600", "NUL\x00", "e\u0301")

# How deep the fuzzer nests an expression (issue 19 crashed at 5000).
NESTING_DEPTHS = (10, 300, 3000)


def nested(kind: str, depth: int, inner: str = "x") -> str:
    """An expression `depth` levels deep: parentheses, sin calls, unary minuses or a long sum."""
    if kind == "parens":
        return "(" * depth + inner + ")" * depth
    if kind == "sin":
        return "sin(" * depth + inner + ")" * depth
    if kind == "minus":
        return "-" * depth + inner
    if kind == "power":
        return "^".join([inner] * depth)
    return " + ".join([inner] * depth)          # a flat but long sum


NESTING_KINDS = ("parens", "sin", "minus", "power", "sum")
