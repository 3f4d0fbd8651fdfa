"""A model that reaches runtime.simulate with its code unsettled is put on it before its first run
(compiler/runtime/model_code.py): compiled C by the installation's build (the one `dyadc simulate`
uses) where a C compiler is present, once per model object; a model put on the VM stays there; a
standalone module's runtime builds nothing and says why."""
from __future__ import annotations

import pytest

from compiler import runtime
from compiler.cache.c_code import compile_c, on_vm
from compiler.lower.ccodegen import find_compiler
from compiler.runtime import model_code
from compiler.runtime.model_code import STANDALONE_WHY, code_builder, on_its_code
from tests.runtime import runtime_systems as systems
from tests.runtime.lowered import compile_model

pytestmark = pytest.mark.skipif(find_compiler() is None, reason="no C compiler")


@pytest.fixture(scope="module")
def lowered():
    """The RC circuit lowered, its code not chosen (each test takes a copy: what a model settles
    is kept with the model object)."""
    return compile_model(systems.rc_circuit())


def test_the_installation_declares_the_build_dyadc_simulate_uses():
    from compiler.cache.c_code import for_a_run
    assert code_builder() == (for_a_run, None)


def test_an_unsettled_model_is_built_in_c_once_and_runs_as_its_compiled_copy(lowered):
    model = lowered.replace()
    assert model_code.needs_code(model)
    settled = on_its_code(model)
    assert settled.native_library is not None and settled.metadata["codegen"] == "c"
    assert on_its_code(model) is settled and on_its_code(settled) is settled
    compiled = compile_c(lowered)
    assert settled.native_library == compiled.native_library          # one content-keyed library
    first = runtime.simulate(model, 0.1, points=5)
    assert (first.stats["codegen"], first.stats["integrator"]) == ("c", "native")
    assert (first.values == runtime.simulate(compiled, 0.1, points=5).values).all()


def test_a_c_model_read_back_without_its_library_gets_it_again(lowered):
    compiled = compile_c(lowered)
    again = runtime.CompiledModel.from_dict(compiled.to_dict())
    assert again.metadata["codegen"] == "c" and again.native_library is None
    assert on_its_code(again).native_library == compiled.native_library


def test_a_model_put_on_the_vm_stays_there(lowered):
    asked = on_vm(lowered)
    assert on_its_code(asked) is asked
    result = runtime.simulate(asked, 0.1, points=5)
    assert (result.stats["codegen"], result.stats["integrator"]) == ("vm", "casadi")
    assert "codegen_why" not in result.stats


def test_a_standalone_runtime_builds_no_c_and_says_why(lowered):
    assert code_builder(package="dyad_runtime") == (None, STANDALONE_WHY)
    on_the_vm = on_its_code(lowered.replace(), package="dyad_runtime")
    assert on_the_vm.native_library is None
    assert (on_the_vm.metadata["codegen"], on_the_vm.metadata["codegen_why"]) == ("vm", STANDALONE_WHY)
    result = runtime.simulate(on_the_vm, 0.1, points=5)
    assert result.stats["codegen_why"] == STANDALONE_WHY
    assert result.stats["integrator_why"] == f"it is on CasADi's VM: {STANDALONE_WHY}"
