"""Shared by the tests that write Dyad files and run `dyadc` in this process: writing a source,
finding the line of a declaration, running a command, and the electrical parts their circuits
are made of (a pin, a ground, a constant voltage source, a resistor, and a circuit of the three
whose connects each test chooses)."""
from __future__ import annotations

import textwrap
from pathlib import Path

from compiler.cli import main

PIN = """
connector Pin
  potential v::Real
  flow i::Real
end
"""

GROUND = """
component Ground
  g = Pin()
relations
  g.v = 0
end
"""


def voltage_source(volts: float) -> str:
    """`component Source` with pins p and n and `volts` between them."""
    return f"""
component Source
  p = Pin()
  n = Pin()
relations
  p.v - n.v = {volts:g}
  p.i + n.i = 0
end
"""


def resistor(parameter: str) -> str:
    """`component Resistor` with pins p and n and Ohm's law in `R`, declared by the lines
    `parameter` (a test's point is often how R is declared)."""
    return f"""
component Resistor
  p = Pin()
  n = Pin()
{textwrap.indent(textwrap.dedent(parameter).strip(), "  ")}
relations
  p.v - n.v = R * p.i
  p.i + n.i = 0
end
"""


def resistor_circuit(*connects: str) -> str:
    """`component Circuit`: a Source, a Resistor and a Ground joined by `connects`."""
    lines = "".join(f"  {c}\n" for c in connects)
    return f"""
component Circuit
  source = Source()
  resistor = Resistor()
  ground = Ground()
relations
{lines}end
"""


def write(folder: Path, name: str, text: str) -> Path:
    """`text` (dedented, leading blank lines dropped) as the file `folder/name`."""
    path = folder / name
    path.write_text(textwrap.dedent(text).lstrip("\n"), encoding="utf-8")
    return path


def line_of(path: Path, marker: str) -> int:
    """The number of the first line of `path` that contains `marker`."""
    return next(i + 1 for i, line in enumerate(path.read_text().splitlines()) if marker in line)


def run(capsys, *argv) -> tuple[int, str, str]:
    """(exit status, stdout, stderr) of `dyadc ARGV...`; a traceback on stderr fails the test."""
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err and "internal error" not in err, err
    return code, out, err
