"""Issue 28: a missing `connect` (an open circuit) must not run silently. `check` and `simulate`
(compiled and from the cache) warn, naming each connector that nothing connects."""
from __future__ import annotations

from tests.dyad_cli import GROUND, PIN, resistor, resistor_circuit, run, voltage_source, write

# resistor.n is left open: nothing connects it
OPEN_CIRCUIT = (PIN + resistor("parameter R::Real = 2") + voltage_source(12) + GROUND
                + resistor_circuit("connect(source.p, resistor.p)", "connect(source.n, ground.g)"))

EXPECTED = ("warning: 1 connector is connected to nothing, so its flows are zero (a free end, or "
            "a missing connect: an open circuit carries no current): resistor.n (i)\n")


def test_check_and_simulate_name_the_connectors_nothing_connects(tmp_path, capsys):
    spec = f"{write(tmp_path, 'Circuit.dyad', OPEN_CIRCUIT)}:Circuit"
    code, out, _ = run(capsys, "check", spec)
    assert code == 0
    assert "  " + EXPECTED in out
    for _ in ("compiled", "from the cache"):
        code, _, err = run(capsys, "simulate", spec, "--stop", "1")
        assert code == 0
        assert err.count("warning: ") == 1 and EXPECTED in err, err
