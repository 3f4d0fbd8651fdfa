"""State-set variants derived at compile time and carried by the compiled model
(compiler/structure/state_selection/enumeration.py, compiler/lower/state_set_variants.py,
compiler/runtime/variants.py), and over the limit the universal system in their place
(compiler/lower/universal_variant.py, compiler/runtime/universal.py)."""
import dataclasses
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from compiler import api, runtime
from compiler.lower.state_set_variants import VariantLimitWarning, build_variant, with_variants
from compiler.lower.universal_variant import with_universal
from compiler.runtime.variants import DUMMIES

MODELS = Path(__file__).resolve().parents[1] / "models"
SPEC = "Hard.CartesianPendulumLarge"


@pytest.fixture(scope="module")
def compilation():
    return api.compile(SPEC, lib_dirs=(str(MODELS),))


def test_the_pendulum_carries_its_two_state_sets(compilation):
    # the alias rows der(der(x)) - der(u) = 0 are folded (state_selection/folds.py): x and u are states
    # together or dummies together, so the choice is one of the rod's two coordinates
    model = compilation.model
    assert len(model.variants) == 1                     # and the first one, the model itself
    keys = set(model.variants) | {frozenset(model.metadata[DUMMIES])}
    assert keys == {frozenset({"der(der(x))", "der(der(y))", "der(u)", "der(x)"}),
                    frozenset({"der(der(x))", "der(der(y))", "der(v)", "der(y)"})}
    sets = {tuple(v.state_names) for v in model.variants.values()} | {tuple(model.state_names)}
    assert sets == {("x", "u"), ("y", "v")}
    for key, variant in model.variants.items():
        assert frozenset(variant.metadata[DUMMIES]) == key and not variant.variants


def test_the_model_round_trips_through_plain_data_with_its_variants(compilation):
    model = compilation.model
    data = json.loads(json.dumps(model.to_dict()))
    again = runtime.CompiledModel.from_dict(data)
    assert set(again.variants) == set(model.variants)
    for key, variant in model.variants.items():
        assert again.variants[key].state_names == variant.state_names
        assert again.variants[key].output_names == variant.output_names
    assert json.loads(json.dumps(again.to_dict())) == data
    # and it switches as the original does
    first = runtime.simulate(model, 2.0, rtol=1e-8, atol=1e-8, points=21)
    second = runtime.simulate(again, 2.0, rtol=1e-8, atol=1e-8, points=21)
    assert [s["time"] for s in first.switches] == [s["time"] for s in second.switches]
    assert len(first.switches) >= 3
    assert np.array_equal(first.values, second.values)


def test_a_model_of_the_previous_format_still_reads(compilation):
    data = compilation.model.variants[next(iter(compilation.model.variants))].to_dict()
    data["format_version"] = 2
    data.pop("variants", None)
    assert runtime.CompiledModel.from_dict(data).variants == {}


def test_over_the_limit_the_model_carries_one_state_set_and_says_so(compilation):
    root = build_variant(compilation.flat, compilation.analysis, None,
                         reduced=compilation.reduced, report=compilation.report)
    with pytest.warns(VariantLimitWarning) as caught:
        kept = with_variants(compilation.flat, compilation.analysis, root, limit=1)
    message = str(caught[0].message)
    assert "has 2 possible state sets, more than the 1 compiled with it" in message
    assert "a run makes the others from its index-1 system when it reaches them" in message
    assert kept.model.variants == {}
    with pytest.raises(runtime.SimulationFailed, match="carries one state set"):
        runtime.simulate(kept.model, 2.0, rtol=1e-8, atol=1e-8, points=21)
    # the pipeline gives such a model its universal system: in-process, as in generated code, the
    # run switches among the state sets made from it, at the times and to the sets of the carried ones
    over = dataclasses.replace(compilation, model=with_universal(compilation.analysis, kept).model, variant=kept)
    # on CasADi's IDAS both: the state sets made at run time have no C library, so on the default
    # path they would run on CasADi's IDAS (switching at the check after a crossing) where the
    # carried ones run natively (switching at the root): 8e-4 s apart at the second switch
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        made = api.simulate_compiled(over, 2.0, rtol=1e-8, atol=1e-8, points=21, integrator="casadi")
    carried = api.simulate_compiled(compilation, 2.0, rtol=1e-8, atol=1e-8, points=21, integrator="casadi")
    assert len(made.switches) >= 3
    assert [s["to"] for s in made.switches] == [s["to"] for s in carried.switches]
    assert np.allclose([s["time"] for s in made.switches], [s["time"] for s in carried.switches], rtol=0, atol=1e-6)
    assert np.max(np.abs(made["x"] - carried["x"])) < 1e-6


def test_a_five_body_cartesian_chain_is_over_the_limit_and_says_how_far(tmp_path):
    from tests.hard.cartesian_chain import dyad_source
    path = tmp_path / "CartesianChain5.dyad"
    path.write_text(dyad_source(5, [0.5] * 5))
    with pytest.warns(VariantLimitWarning, match=r"CartesianChain5 has 122 possible state sets, "
                                                 r"more than the 64 compiled with it"):
        compiled = api.compile(str(path))
    assert compiled.dynamic and compiled.model.variants == {}
