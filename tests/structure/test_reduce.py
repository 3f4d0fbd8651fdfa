"""The structure stage on hand-built flat systems (no front end involved)."""
import math

import numpy as np
import pytest
import sympy

from compiler import runtime
from compiler.errors import DyadError
from compiler.model.flat import ALGEBRAIC, STATE_CANDIDATE
from compiler.lower.to_casadi import lower
from compiler.pipeline import compile_flat
from compiler.structure.alias import eliminate_aliases
from compiler.structure.reduce import StructureReport, reduce
from tests.reference import pendulum as closed_form
from tests.structure.flat_fixtures import D, S, build, cartesian_pendulum

G = closed_form.G


def test_cartesian_pendulum_is_index_3_with_two_states():
    report = StructureReport()
    reduced = reduce(cartesian_pendulum(g=G), report=report)
    assert report.structural_index == 3
    assert len(reduced.states) == 2
    assert report.counts["differentiated equations"] == 4


@pytest.mark.parametrize("theta0", [0.5, 2.0])
def test_pivoting_at_the_start_point_picks_the_well_conditioned_coordinate(theta0):
    # Near the bottom x is the good state (y is flat in x there); near horizontal, y.
    x0, y0 = math.sin(theta0), -math.cos(theta0)
    compilation = compile_flat(cartesian_pendulum(x0=x0, y0=y0, g=G))
    expected = {"x", "u"} if abs(y0) > abs(x0) else {"y", "v"}
    assert set(compilation.reduced.states) == expected


def test_cartesian_pendulum_matches_the_closed_form_to_8_digits():
    theta0 = 0.5
    flat = cartesian_pendulum(x0=math.sin(theta0), y0=-math.cos(theta0), g=G)
    model = compile_flat(flat).model
    result = runtime.simulate(model, 10.0, rtol=1e-10, atol=1e-10, points=201)
    exact = closed_form.solution(result.time, L=1.0, theta0=theta0, g=G)
    assert np.max(np.abs(result["x"] - exact["x"])) < 1e-8
    assert np.max(np.abs(result["y"] - exact["y"])) < 1e-8
    assert np.max(np.abs(result["x"] ** 2 + result["y"] ** 2 - 1.0)) < 1e-10
    # tension per unit mass (T multiplies the position in der(u) = -T x)
    assert np.max(np.abs(result["T"] - exact["tension"])) < 1e-6


def test_redundant_consistent_initial_conditions_are_accepted():
    theta0 = 0.5
    flat = cartesian_pendulum(x0=math.sin(theta0), y0=-math.cos(theta0), g=G, redundant=True)
    result = runtime.simulate(compile_flat(flat).model, 1.0, rtol=1e-8, atol=1e-8, points=11)
    assert abs(result["y"][0] + math.cos(theta0)) < 1e-12


def test_inconsistent_initial_conditions_name_the_residuals():
    flat = cartesian_pendulum(x0=0.5, y0=-0.5, g=G, redundant=True)   # not on the circle
    with pytest.raises(runtime.InitializationFailed, match="residual"):
        runtime.simulate(compile_flat(flat).model, 1.0, points=3)


def test_missing_initial_condition_fixes_the_free_state_at_its_start_value():
    # Under-determined initialization is normal in Dyad (issue 17 item 6): the free state is
    # fixed at its start value (0 without one) and named for the note.
    x, u = S("x"), S("u")
    flat = build("Oscillator", [("x", STATE_CANDIDATE, None, 0), ("u", STATE_CANDIDATE, None, 0)], [("k", 4.0)],
                 [D("x") - u, D("u") + S("k") * x], initial=[x - 1])
    assert reduce(flat).initial.chosen == {"u": 0.0}


def test_structurally_singular_system_names_the_culprits():
    a, b, c = S("a"), S("b"), S("c")
    flat = build("Bad", [("a", ALGEBRAIC, None, 0), ("b", ALGEBRAIC, None, 0), ("c", ALGEBRAIC, None, 0)], [],
                 [a + b - 1, 2 * a + 2 * b - 3 + sympy.sin(a) * 0, a * b + c - c])
    with pytest.raises(DyadError, match="structurally singular.*c"):
        reduce(flat)


def test_alias_elimination_follows_signs_offsets_and_derivatives():
    a, b, c, d = S("sub.a"), S("b"), S("c"), S("d")
    flat = build("Aliases", [("sub.a", ALGEBRAIC, None, 0), ("b", STATE_CANDIDATE, None, 0),
                             ("c", ALGEBRAIC, None, 0), ("d", ALGEBRAIC, None, 0)], [("p", 2.0)],
                 [a - b, c + b, d - c - S("p"), D("b") + d])
    result = eliminate_aliases(flat)
    assert result.kept == ["b"]
    assert result.eliminated["sub.a"] == b
    assert result.eliminated["c"] == -b
    assert sympy.simplify(result.eliminated["d"] - (-b + S("p"))) == 0
    (remaining,) = result.equations
    assert sympy.simplify(remaining.residual - (D("b") - b + S("p"))) == 0


def test_alias_of_a_state_candidate_maps_its_derivative():
    x, y = S("x"), S("y")
    flat = build("Der", [("x", STATE_CANDIDATE, None, 0), ("y", ALGEBRAIC, None, 5)], [],
                 [x + y, D("x") + x])
    result = eliminate_aliases(flat)
    # x is the state candidate: it stays, y = -x becomes an observable
    assert result.kept == ["x"] and result.eliminated["y"] == -x


def test_constants_propagate_through_substitution_to_a_fixpoint():
    phi, r0, xb = S("phi"), S("r0"), S("xb")
    flat = build("Chain", [("phi", ALGEBRAIC, None, 0), ("r0", ALGEBRAIC, None, 0), ("xb", ALGEBRAIC, None, 0)],
                 [("r", 0.5)], [phi, r0 - sympy.cos(phi) * S("r"), xb - r0 - 1])
    result = eliminate_aliases(flat)
    assert result.kept == [] and result.equations == []
    assert result.eliminated["xb"] == S("r") + 1


def test_derivatives_in_linear_combinations_reveal_the_true_state_count():
    from tests.structure.flat_fixtures import capacitor_mirror
    compilation = compile_flat(capacitor_mirror(u0=0.0))
    assert len(compilation.reduced.states) == 1
    assert compilation.report.counts["derivative-dependent equations combined"] == 1
    result = runtime.simulate(compilation.model, 5.0, rtol=1e-10, atol=1e-10, points=51)
    t = result.time
    # u = y1 - y2 solves u' = -u/2 - 1/4 + sin(t)/2 (derived by hand in flat_fixtures)
    u = -0.5 + 0.2 * np.sin(t) - 0.4 * np.cos(t) + 0.9 * np.exp(-t / 2)
    y2 = (np.sin(t) + 0.5 - u) / 2
    assert np.max(np.abs(result["y1"] - result["y2"] - u)) < 1e-8
    assert np.max(np.abs(result["y2"] - y2)) < 1e-8


def test_a_dependency_hidden_behind_a_named_derivative_combination_is_found():
    """The same circuit with `a = y1' - y2'` named and used in the mirror equation (the metamorphic
    tests' TRANSAMP seed 0: index reduction failed): one state, the same solution, and a = u'."""
    from tests.structure.flat_fixtures import capacitor_mirror_named
    compilation = compile_flat(capacitor_mirror_named(u0=0.0))
    assert compilation.model.state_names in (["y1"], ["y2"])      # not a: no derivative of it exists
    assert compilation.report.counts["derivative-dependent equations combined"] == 1
    result = runtime.simulate(compilation.model, 5.0, rtol=1e-10, atol=1e-10, points=51)
    t = result.time
    u = -0.5 + 0.2 * np.sin(t) - 0.4 * np.cos(t) + 0.9 * np.exp(-t / 2)
    du = 0.2 * np.cos(t) + 0.4 * np.sin(t) - 0.45 * np.exp(-t / 2)
    assert np.max(np.abs(result["y1"] - result["y2"] - u)) < 1e-8
    assert np.max(np.abs(result["a"] - du)) < 1e-7


def test_large_swings_switch_states_and_keep_the_constraint():
    """Released at 2 rad the bob passes the horizontal: no static state choice is valid."""
    from compiler.api import simulate_compiled
    theta0 = 2.0
    compilation = compile_flat(cartesian_pendulum(x0=math.sin(theta0), y0=-math.cos(theta0), g=G))
    assert compilation.dynamic
    result = simulate_compiled(compilation, 6.0, rtol=1e-12, atol=1e-12, points=601)
    switches = result.stats["state_switches"]
    assert len(switches) >= 8
    assert {tuple(s["to"]) for s in switches} == {("x", "u"), ("y", "v")}
    exact = closed_form.solution(result.time, L=1.0, theta0=theta0, g=G)
    assert np.max(np.abs(result["x"] - exact["x"])) < 1e-8
    assert np.max(np.abs(result["y"] - exact["y"])) < 1e-8
    assert np.max(np.abs(result["x"] ** 2 + result["y"] ** 2 - 1.0)) < 1e-12


def test_hinted_tree_mechanism_is_never_monitored():
    from compiler.api import compile as compile_model
    compilation = compile_model("MultibodyComponents.PlanarMechanics.examples.excavator.Excavator")
    assert not compilation.dynamic
    assert {"boom_joint.phi", "stick_joint.phi", "bucket_joint.phi",
            "boom_joint.w", "stick_joint.w", "bucket_joint.w"} <= set(compilation.reduced.states)
