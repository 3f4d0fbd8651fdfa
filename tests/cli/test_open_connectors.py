"""Issue 28: a missing `connect` (an open circuit) must not run silently. `check` and `simulate`
(compiled and from the cache) warn, naming each connector that nothing connects."""
from __future__ import annotations

import textwrap

from compiler.cli import main

OPEN_CIRCUIT = """
connector Pin
  potential v::Real
  flow i::Real
end
component Resistor
  p = Pin()
  n = Pin()
  parameter R::Real = 2
relations
  p.v - n.v = R * p.i
  p.i + n.i = 0
end
component Source
  p = Pin()
  n = Pin()
relations
  p.v - n.v = 12
  p.i + n.i = 0
end
component Ground
  g = Pin()
relations
  g.v = 0
end
component Circuit
  source = Source()
  resistor = Resistor()
  ground = Ground()
relations
  connect(source.p, resistor.p)
  connect(source.n, ground.g)
end
"""

EXPECTED = ("warning: 1 connector is connected to nothing, so its flows are zero (a free end, or "
            "a missing connect: an open circuit carries no current): resistor.n (i)\n")


def test_check_and_simulate_name_the_connectors_nothing_connects(tmp_path, capsys):
    path = tmp_path / "Circuit.dyad"
    path.write_text(textwrap.dedent(OPEN_CIRCUIT), encoding="utf-8")
    spec = f"{path}:Circuit"
    assert main(["check", spec]) == 0
    out, _ = capsys.readouterr()
    assert "  " + EXPECTED in out
    for _ in ("compiled", "from the cache"):
        assert main(["simulate", spec, "--stop", "1"]) == 0
        _, err = capsys.readouterr()
        assert err.count("warning: ") == 1 and EXPECTED in err, err
