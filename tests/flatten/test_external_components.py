"""`external component`: its behaviour is implemented in Julia, only its interface is written in
Dyad. `dyadc check` instantiates the interface and says so (exit 0); `simulate` refuses it, located
at the component, and a model that uses it is not balanced by it."""
from __future__ import annotations

from compiler.cli import main

SOURCE = """
connector In = input Real
connector Out = output Real

external component Lookup
  u = In()
  y = Out()
end

component Uses
  src_value = Out()
  table = Lookup()
relations
  src_value = 2
  connect(src_value, table.u)
end
"""


def _run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


def test_check_of_an_external_component_reports_its_interface(sources, capsys):
    path = sources.write("Lib.dyad", SOURCE)
    code, out, _ = _run(capsys, "check", f"{path}:Lookup")
    assert code == 0
    assert "external: interface only, 2 unknowns and 1 open connector (u)" in out
    assert "implemented in Julia" in out


def test_simulate_refuses_an_external_component_with_a_located_error(sources, capsys):
    path = sources.write("Lib.dyad", SOURCE)
    code, _, err = _run(capsys, "simulate", f"{path}:Lookup", "--stop", "1")
    assert code == 1
    first = err.splitlines()[0]
    assert first.startswith(f"{path}:4:1: error:")
    assert "external component" in first and "implemented in Julia" in first


def test_a_model_using_an_external_component_is_not_balanced_by_it(sources, capsys):
    path = sources.write("Lib.dyad", SOURCE)
    code, _, err = _run(capsys, "check", f"{path}:Uses")
    assert code == 1
    assert "unbalanced" in err.splitlines()[0] and "table" in err
