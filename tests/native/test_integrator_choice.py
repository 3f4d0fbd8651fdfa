"""Which integrator a run through the compiler gets (compiler/runtime/native/choice.py): the native IDAS
driver by default where it can run the model, CasADi's IDAS where it cannot, with the reason in
Result.stats and on the summary line; `integrator=`, `--integrator` and $DYADC_INTEGRATOR choose."""
from __future__ import annotations

import warnings

import pytest

from compiler import api
from compiler.runtime.native import INTEGRATOR_VARIABLE, NativeIdasWarning, library

pytestmark = pytest.mark.skipif(library.driver_library()[0] is None,
                                reason="native IDAS driver not built (make install builds it)")

# x starts on the zero of `x < 0` and leaves it: y = t on the path that finds it (the native one)
LEAVES = """component Leaves
  variable x::Real
  variable y::Real
relations
  initial x = 0
  initial y = 0
  der(x) = -1
  der(y) = if x < 0 then 1.0 else 0.0
end
"""


@pytest.fixture(scope="module")
def leaves(tmp_path_factory):
    path = tmp_path_factory.mktemp("choice") / "Leaves.dyad"
    path.write_text(LEAVES, encoding="utf-8")
    return str(path)


@pytest.fixture(scope="module")
def compilation(leaves):
    return api.compile(leaves)


@pytest.fixture(autouse=True)
def no_integrator_variable(monkeypatch):
    monkeypatch.delenv(INTEGRATOR_VARIABLE, raising=False)


def run(compilation, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("error", NativeIdasWarning)       # no fallback warning unless asked
        return api.simulate_compiled(compilation, 2.0, points=5, **options)


def test_a_model_in_c_runs_on_the_native_driver_by_default(compilation):
    result = run(compilation, codegen="c")
    assert (result.stats["codegen"], result.stats["integrator"]) == ("c", "native")
    assert "integrator_why" not in result.stats
    assert result["y"][-1] == pytest.approx(2.0, abs=1e-9)


def test_a_model_on_the_vm_runs_on_casadi_idas_and_says_why(compilation):
    result = run(compilation, codegen="vm")
    assert result.stats["integrator"] == "casadi"
    assert result.stats["integrator_why"] == "it is on CasADi's VM, with no C library"


def test_casadi_idas_asked_for_by_name_or_by_the_variable(compilation, monkeypatch):
    asked = run(compilation, codegen="c", integrator="casadi")
    monkeypatch.setenv(INTEGRATOR_VARIABLE, "casadi")
    by_variable = run(compilation, codegen="c")
    for result in (asked, by_variable):
        assert result.stats["integrator"] == "casadi" and "integrator_why" not in result.stats
    # the named integrator wins over the variable
    assert run(compilation, codegen="c", integrator="native").stats["integrator"] == "native"


def test_native_asked_for_where_it_cannot_run_warns(compilation, monkeypatch):
    monkeypatch.setenv(INTEGRATOR_VARIABLE, "native")
    with pytest.warns(NativeIdasWarning, match="on CasADi's VM, with no C library"):
        result = api.simulate_compiled(compilation, 2.0, points=5, codegen="vm")
    assert result.stats["integrator"] == "casadi"


def test_an_unknown_variable_value_is_warned_of_and_the_default_runs(compilation, monkeypatch):
    monkeypatch.setenv(INTEGRATOR_VARIABLE, "fast")
    with pytest.warns(NativeIdasWarning, match="DYADC_INTEGRATOR='fast' is neither"):
        result = api.simulate_compiled(compilation, 2.0, points=5, codegen="c")
    assert result.stats["integrator"] == "native"


def test_the_summary_line_names_the_integrator(leaves, capsys):
    from compiler.cli import main
    assert main(["simulate", leaves, "--stop", "2", "--codegen", "c", "--no-cache"]) == 0
    assert " s on native IDAS: " in capsys.readouterr().err
    assert main(["simulate", leaves, "--stop", "2", "--codegen", "vm", "--no-cache"]) == 0
    assert " s on CasADi's IDAS (it is on CasADi's VM, with no C library): " in capsys.readouterr().err
    assert main(["simulate", leaves, "--stop", "2", "--codegen", "c", "--no-cache",
                 "--integrator", "casadi"]) == 0
    assert " s on CasADi's IDAS: " in capsys.readouterr().err


def test_a_direct_runtime_call_makes_the_same_choice_as_the_compiler(compilation):
    """runtime.simulate applies the choice itself (it lives in the runtime), so a caller without
    the compiler (a script, a generated module, a sweep worker) takes the path simulate_compiled
    takes: in C the native driver with the same numbers; a model not yet on its code (the
    compilation's own) is put on it by its first run, the library `dyadc simulate` builds, and
    gives the same numbers; on the VM asked for, CasADi's IDAS, which says why."""
    from compiler import runtime
    from compiler.compiled_runs import model_on_its_code
    through_the_compiler = run(compilation, codegen="c")
    direct = runtime.simulate(model_on_its_code(compilation.model, "c"), 2.0, points=5)
    assert direct.stats["integrator"] == through_the_compiler.stats["integrator"] == "native"
    assert (direct.values == through_the_compiler.values).all()
    assert "codegen" not in compilation.model.metadata               # not on its code yet
    settled_by_the_run = runtime.simulate(compilation.model, 2.0, points=5)
    assert (settled_by_the_run.stats["codegen"], settled_by_the_run.stats["integrator"]) == ("c", "native")
    assert (settled_by_the_run.values == through_the_compiler.values).all()
    on_the_vm = runtime.simulate(model_on_its_code(compilation.model, "vm"), 2.0, points=5)
    assert (on_the_vm.stats["codegen"], on_the_vm.stats["integrator"]) == ("vm", "casadi")
    assert on_the_vm.stats["integrator_why"] == "it is on CasADi's VM, with no C library"
    by_name = runtime.simulate(model_on_its_code(compilation.model, "c"), 2.0, points=5, integrator="casadi")
    assert by_name.stats["integrator"] == "casadi" and "integrator_why" not in by_name.stats


def test_an_unknown_integrator_name_is_refused():
    from compiler import runtime
    with pytest.raises(runtime.ModelInputError, match="integrator must be 'casadi' or 'native' or make"):
        runtime.SimulationOptions(stop=1.0, integrator="fast").validated()
