"""The errors a newcomer meets (issue 13), recursive containment (issue 19.6), parameter values and
names (issue 19.10) and `dyadc check` on components that cannot run alone (issue 17.7).

Each must be `FILE:LINE:COL: error: ...` with the source line and a hint, a non-zero exit status and
no traceback; `dyadc check` and `dyadc simulate` must run the same checks and agree.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from compiler import api
from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.model.floating import floating_clusters
from compiler.model.model_check import assess
from tests.dyad_cli import GROUND, PIN, line_of, run, write

LIB = PIN + """
partial component TwoPin
  p = Pin()
  n = Pin()
  variable v::Real
  variable i::Real
relations
  v = p.v - n.v
  0 = p.i + n.i
  i = p.i
end
component Resistor
  extends TwoPin
  parameter R::Real = 1
relations
  v = R*i
end
component Capacitor
  extends TwoPin
  parameter C::Real = 1
relations
  C*der(v) = i
end
component Source
  extends TwoPin
  parameter V::Real = 1
relations
  v = V
end
""" + GROUND


@pytest.fixture
def lib(tmp_path: Path) -> Path:
    write(tmp_path, "Lib.dyad", LIB)
    return tmp_path


def assert_located(err: str, path: Path, line: int) -> None:
    """`FILE:LINE:COL: error:` at `line`, the source line under it, and a hint."""
    head = re.search(r"^(.*):(\d+):(\d+): error: ", err, re.MULTILINE)
    assert head, err
    assert Path(head.group(1)).resolve() == path.resolve() and int(head.group(2)) == line, err
    source = path.read_text().splitlines()[line - 1].strip()
    assert source in err.splitlines()[1], err
    assert "\nhint: " in err, err


def simulate_cli(capsys, spec: str, lib: Path, *extra: str) -> tuple[int, str, str]:
    return run(capsys, "simulate", spec, "--lib", str(lib), "--stop", "1", *extra)


# ---------------------------------------------------------------------- parameters without value

NO_VALUE = """
component Decay
  parameter k::Real
  variable x::Real
relations
  der(x) = -k*x
  initial x = 1
end
"""


def test_a_parameter_without_value_is_named_with_how_to_set_it(tmp_path, capsys):
    path = write(tmp_path, "Decay.dyad", NO_VALUE)
    code, _, err = simulate_cli(capsys, str(path), tmp_path)
    assert code == 1
    assert_located(err, path, line_of(path, "parameter k"))
    assert "parameter `k`" in err and "has no value" in err
    assert "-p k=" in err and "parameter k::Real = VALUE" in err


def test_a_parameter_without_value_runs_when_given(tmp_path, capsys):
    path = write(tmp_path, "Decay.dyad", NO_VALUE)
    code, out, err = simulate_cli(capsys, str(path), tmp_path, "-p", "k=0.1")
    assert code == 0, err
    final = float(out.split("\nx")[1].split()[0])
    assert abs(final - math.exp(-0.1)) < 1e-5
    result = api.simulate(str(path), 2.0, params={"k": 0.5}, rtol=1e-8, atol=1e-10)
    assert abs(result["x"][-1] - math.exp(-1.0)) < 1e-6


# ---------------------------------------------------------------------------- no ground

FLOATING = """
component Floating
  r = Resistor()
  c = Capacitor()
  s = Source()
relations
  initial c.v = 0
  connect(s.p, r.p)
  connect(r.n, c.p)
  connect(c.n, s.n)
end
"""


def test_a_circuit_without_ground_names_the_floating_sets_and_the_reference(lib, capsys):
    path = write(lib, "Floating.dyad", FLOATING)
    for command in (["simulate", "--stop", "1"], ["check"]):
        code, _, err = run(capsys, command[0], str(path), "--lib", str(lib), *command[1:])
        assert code == 1
        assert_located(err, path, line_of(path, "connect(s.p, r.p)"))
        assert "{r.p, s.p} {r.n, c.p} {c.n, s.n}" in err and "float" in err
        assert "Ground" in err.split("hint:")[1]
        assert "over-determined: 0" not in err


def test_the_same_circuit_with_a_ground_runs_and_matches_the_closed_form(lib):
    path = write(lib, "Grounded.dyad", FLOATING.replace("Floating", "Grounded")
                 .replace("  s = Source()\n", "  s = Source()\n  g = Ground()\n")
                 .replace("connect(c.n, s.n)", "connect(c.n, s.n, g.g)"))
    assert floating_clusters(flatten_model(str(path), [str(lib)])) == []
    result = api.simulate(str(path), 2.0, lib_dirs=[str(lib)], rtol=1e-8, atol=1e-10)
    assert abs(result["c.v"][-1] - (1 - math.exp(-2.0))) < 1e-6


def test_a_free_mechanical_system_is_not_called_floating(tmp_path):
    """Positions that are states get their constant from the initial values: no reference needed."""
    path = write(tmp_path, "Free.dyad", """
        connector Flange
          potential s::Real
          flow f::Real
        end
        component Mass
          flange = Flange()
          parameter m::Real = 1
          variable s::Real
          variable v::Real
        relations
          s = flange.s
          der(s) = v
          m*der(v) = flange.f
        end
        component Spring
          a = Flange()
          b = Flange()
          parameter c::Real = 4
        relations
          a.f = c*(a.s - b.s)
          a.f + b.f = 0
        end
        component Free
          m1 = Mass(s(initial = 0), v(initial = 0))
          m2 = Mass(s(initial = 1), v(initial = 0))
          k = Spring()
        relations
          connect(m1.flange, k.a)
          connect(k.b, m2.flange)
        end
        """)
    flat = flatten_model(str(path))
    assert floating_clusters(flat) == [] and not assess(flat).is_partial
    result = api.simulate(str(path), 1.0, rtol=1e-8, atol=1e-10)
    # the centre of mass stays put; the stretch oscillates at sqrt(2c/m) = sqrt(8)
    assert abs(result["m1.s"][-1] + result["m2.s"][-1] - 1.0) < 1e-6
    assert abs(result["m2.s"][-1] - result["m1.s"][-1] - math.cos(math.sqrt(8.0))) < 1e-5


# ------------------------------------------------------------------- partial and open connectors

def test_a_component_with_open_connectors_is_partial_in_check_and_in_simulate(lib, capsys):
    path = lib / "Lib.dyad"
    code, out, _ = run(capsys, "check", f"{path}:Resistor")
    assert code == 0
    assert "partial: balanced as a component, 2 open connectors (p, n)" in out
    assert not re.search(r"^\s+balanced:", out, re.MULTILINE)
    code, _, err = simulate_cli(capsys, f"{path}:Resistor", lib)
    assert code == 1
    assert_located(err, path, line_of(path, "component Resistor"))
    assert "partial model" in err and "p, n are left open" in err
    assert "structurally singular" not in err.splitlines()[0]


def test_a_component_declared_partial_says_so(lib, capsys):
    path = lib / "Lib.dyad"
    code, out, _ = run(capsys, "check", f"{path}:TwoPin")
    assert code == 0 and "partial: declared partial" in out and "(p, n)" in out
    code, _, err = simulate_cli(capsys, f"{path}:TwoPin", lib)
    assert code == 1
    assert_located(err, path, line_of(path, "partial component TwoPin"))
    assert "declared partial" in err and "p, n" in err


def test_check_of_a_library_folder_reports_partial_components(lib, capsys):
    code, out, _ = run(capsys, "check", str(lib))
    assert code == 0, out
    assert "partial: Resistor: balanced as a component, 2 open connectors (p, n)" in out
    assert "ok: Ground (2 equations, 2 unknowns)" in out
    assert "ok: Resistor" not in out


def test_unconnected_connectors_of_subcomponents_are_named(lib, capsys):
    path = write(lib, "Loose.dyad", """
        component Loose
          c = Capacitor()
          r = Resistor()
        relations
          initial c.v = 1
          connect(c.p, r.p)
        end
        """)
    code, _, err = simulate_cli(capsys, str(path), lib)
    assert code == 1
    assert_located(err, path, 1)
    assert "2 connector(s) are left unconnected" in err
    assert "connector `c.n` (Pin) is not connected" in err
    assert "connector `r.n` (Pin) is not connected" in err


# --------------------------------------------------------------------------- unconnected input

OPEN_INPUT = """
connector RealInput = input Real
component Lag
  u = RealInput()
  variable x::Real
relations
  der(x) = u - x
  initial x = 0
end
"""


def test_check_and_simulate_agree_on_an_unconnected_input_and_name_it(tmp_path, capsys):
    path = write(tmp_path, "Lag.dyad", OPEN_INPUT)
    code, out, _ = run(capsys, "check", str(path))
    assert code == 0
    assert "partial: balanced as a component, 1 open connector (u)" in out
    assert not re.search(r"^\s+balanced:", out, re.MULTILINE)
    code, _, err = simulate_cli(capsys, str(path), tmp_path)
    assert code == 1
    assert_located(err, path, line_of(path, "component Lag"))
    assert "connector u is left open" in err and "input" in err.split("hint:")[1]


# ------------------------------------------------------------------------------ local balance

def test_an_unbalanced_model_names_the_component_whose_own_count_is_off(lib, capsys):
    path = write(lib, "Unbalanced.dyad", """
        component LeakyResistor
          extends TwoPin
          parameter R::Real = 1
        end
        component Unbalanced
          r = LeakyResistor()
          c = Capacitor()
          s = Source()
          g = Ground()
        relations
          initial c.v = 0
          connect(s.p, r.p)
          connect(r.n, c.p)
          connect(c.n, s.n, g.g)
        end
        """)
    for command in (["simulate", "--stop", "1"], ["check"]):
        code, _, err = run(capsys, command[0], str(path), "--lib", str(lib), *command[1:])
        assert code == 1
        assert_located(err, path, line_of(path, "component Unbalanced"))
        assert "component `r` (LeakyResistor) is unbalanced on its own" in err.splitlines()[0]
        assert "3 equation(s) for 4 unknown(s); 2 more, the flows of its connectors" in err
        assert f"{path.name}:{line_of(path, 'r = LeakyResistor()')}:" in err
        assert "`c." not in err and "`s." not in err and "`g." not in err   # nothing unrelated


def test_a_component_checked_alone_counts_its_connector_flows_as_given(lib, capsys):
    path = write(lib, "Leaky.dyad", """
        component Leaky
          extends TwoPin
        end
        """)
    code, _, err = run(capsys, "check", str(path), "--lib", str(lib))
    assert code == 1
    assert_located(err, path, 1)
    assert "component `Leaky` is unbalanced: 3 equation(s) for 4 unknown(s)" in err
    assert "flows of its connectors p, n" in err


def test_an_overdetermined_component_checked_alone_names_its_equation_set(lib, capsys):
    path = write(lib, "Pinned.dyad", """
        component Pinned
          extends TwoPin
          parameter R::Real = 1
        relations
          v = R*i
          p.v = 1
        end
        """)
    code, _, err = run(capsys, "check", str(path), "--lib", str(lib))
    assert code == 1
    assert_located(err, path, 1)
    assert "component `Pinned` is unbalanced: 5 equation(s) for 4 unknown(s)" in err
    assert f"{path.name}:{line_of(path, 'p.v = 1')}:3: note: over-determined: `p.v - 1 = 0`" in err


# ------------------------------------------------------------------------ recursive containment

def test_a_component_containing_itself_is_a_located_error(tmp_path, capsys):
    path = write(tmp_path, "Osc.dyad", """
        component Osc
          sub = Osc()
          variable x::Real
        relations
          der(x) = -x
        end
        """)
    code, _, err = run(capsys, "check", str(path))
    assert code == 1
    assert_located(err, path, line_of(path, "sub = Osc()"))
    assert "component `Osc` contains itself: Osc -> sub: Osc" in err


def test_indirect_containment_names_the_whole_cycle(tmp_path, capsys):
    path = write(tmp_path, "Top.dyad", """
        component Holder
          inner = Osc()
        end
        component Osc
          h = Holder()
          variable x::Real
        relations
          der(x) = -x
        end
        component Top
          o = Osc()
        end
        """)
    code, _, err = simulate_cli(capsys, str(path), tmp_path)
    assert code == 1
    assert_located(err, path, line_of(path, "inner = Osc()"))
    assert "Osc -> h: Holder -> inner: Osc" in err
    assert f"{path.name}:{line_of(path, 'h = Holder()')}:3: note:" in err


# ------------------------------------------------------------------------ parameter values, names

@pytest.mark.parametrize("declaration, words", [
    ("parameter k::Real = sqrt(-1)", "the value of `k` is not a real number"),
    # the literal itself may be refused by the parser, or its value here
    ("parameter k::Real = 1e400", "(the value of `k` overflows a floating-point number|"
                                  "number `1e400` is too large)"),
    ("parameter k::Real = 10^400", "the value of `k` overflows a floating-point number"),
    ("parameter k::Real = 2*asin(3)", "the value of `k` is not a real number"),
])
def test_parameter_values_must_be_finite_reals(tmp_path, capsys, declaration, words):
    path = write(tmp_path, "P.dyad", f"""
        component P
          {declaration}
          variable x::Real
        relations
          der(x) = -k*x
          initial x = 1
        end
        """)
    code, _, err = simulate_cli(capsys, str(path), tmp_path)
    assert code == 1
    assert_located(err, path, 2)
    assert re.search(words, err.splitlines()[0]), err


@pytest.mark.parametrize("declaration", ["parameter time::Real = 1", "variable time::Real"])
def test_time_is_not_a_name_of_the_simulated_model_itself(tmp_path, capsys, declaration):
    path = write(tmp_path, "P.dyad", f"""
        component P
          {declaration}
          variable x::Real
        relations
          der(x) = -x
        end
        """)
    code, _, err = run(capsys, "check", str(path))
    assert code == 1
    assert_located(err, path, 2)
    assert "`time` cannot be declared by the simulated model itself" in err and "defined twice" not in err


def test_model_errors_reach_the_api_as_dyad_errors(lib):
    with pytest.raises(DyadError, match="partial model"):
        api.simulate(f"{lib / 'Lib.dyad'}:Resistor", 1.0)
