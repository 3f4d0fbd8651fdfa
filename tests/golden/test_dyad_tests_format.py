"""`dyadc test` reads test cases written the way Dyad's libraries write them (issue 17): an
`initial` map of start values, `expect.initial`, numbers as strings, and Dyad's default
comparison (Julia's isapprox: relative sqrt(eps), no absolute part) where no atol is given."""
from __future__ import annotations

import math
import os

import pytest

from compiler.cli import main
from compiler.errors import DyadError
from compiler.testing import golden
from compiler.testing.golden_cases import DYAD_DEFAULT_RTOL, cases_from_metadata

# x' = -x / tau with no initial condition of its own: the case's "initial" map gives x(0), so
# x(t) = x0 exp(-t / tau); y = 2 x; gain is a parameter the map may set too.
DECAY = """
component FreeDecay
  parameter tau::Real = 0.5
  parameter gain::Real = 2
  variable x::Real
  variable y::Real
relations
  der(x) = -x / tau
  y = gain * x
metadata {
  "Dyad": {
    "tests": {
      "CASES"
    }
  }
}
end
"""


def _write(tmp_path, cases: str):
    path = tmp_path / "FreeDecay.dyad"
    path.write_text(DECAY.replace('"CASES"', cases))
    return str(path)


def _case(**spec):
    base = {"stop": 1, "expect": {"final": {"a": 1.0}}}
    base.update(spec)
    (case,) = cases_from_metadata("M", {"tests": {"c": base}}, None)
    return case


# --------------------------------------------------------------------------- reading the case

def test_values_written_as_strings_are_numbers():
    case = _case(stop="2.5", initial={"x": "10"}, atol={"a": "1e-3"},
                 expect={"final": {"a": "0.31784799"}, "initial": {"a": "1"}})
    assert case.stop == 2.5 and case.initial_values == {"x": 10.0}
    assert case.final == {"a": 0.31784799} and case.expect_initial == {"a": 1.0}
    assert case.tube("a") == (1e-3, 0.0)


def test_without_atol_a_signal_is_compared_as_dyad_does():
    case = _case(expect={"signals": ["a", "b"], "final": {"a": 1}}, atol={"b": 0.1})
    assert DYAD_DEFAULT_RTOL == math.sqrt(2.0 ** -52)
    assert case.tube("a") == (0.0, DYAD_DEFAULT_RTOL)       # isapprox(x, y): rtol sqrt(eps)
    assert case.tube("b") == (0.1, 0.0)                     # isapprox(x, y; atol): rtol 0
    assert case.default_tube == ("a",)
    assert case.rtol is None                # a default-tube signal: run as the golden was made


def test_values_at_the_default_tube_are_judged_from_a_run_at_rtol_1e_12():
    assert golden.reference_rtol(_case()) == golden.STRICT_RTOL == 1e-12
    assert golden.reference_rtol(_case(atol={"a": 1e-3})) == golden.GOLDEN_RTOL == 1e-10
    signals_only = _case(atol={"a": 1e-3}, expect={"signals": ["b"], "final": {"a": 1}})
    assert golden.reference_rtol(signals_only) == golden.GOLDEN_RTOL


def test_a_case_with_only_expect_initial_is_a_case():
    case = _case(expect={"initial": {"a": 0.5}})
    assert case.expect_initial == {"a": 0.5} and not case.final and not case.signals


def test_unknown_keys_and_no_expectations_are_notes_as_dyad_ignores_them():
    # Dyad's generated test ignores a misplaced "signals" and then only checks that the run
    # succeeds; dyadc does the same and says so.
    case = _case(signals=["a"], colour=1, expect={})
    assert "ignored unknown key(s) colour, signals (did you mean expect.signals?)" in case.notes[0]
    assert "checks that the run succeeds" in case.notes[1]
    assert not case.signals and not case.final


@pytest.mark.parametrize("spec, words", [
    ({"stop": "soon"}, '"stop" must be a finite number'),
    ({"initial": {"x": "ten"}}, 'initial value of "x" must be a finite number'),
    ({"initial": [1]}, '"initial" must be an object'),
    ({"expect": {"final": {"a": 1}, "signal": ["a"]}}, "unknown key(s) expect.signal"),
    ({"expect": {"initial": {"a": "nan"}}}, "must be a finite number"),
])
def test_malformed_dyad_cases_are_errors(spec, words):
    with pytest.raises(DyadError) as caught:
        _case(**spec)
    assert words in caught.value.message


# --------------------------------------------------------------------------------- running it

def test_initial_map_sets_the_state_and_a_parameter(tmp_path, capsys):
    x0, tau, gain, stop = 4.0, 0.5, 3.0, 1.0
    final = x0 * math.exp(-stop / tau)
    model = _write(tmp_path, f'''"c1": {{"stop": {stop}, "initial": {{"x": {x0}, "gain": "{gain}"}},
        "expect": {{"initial": {{"x": "{x0}", "y": {gain * x0}}},
                   "final": {{"x": {final!r}, "y": "{gain * final!r}"}}}}}}''')
    assert main(["test", model, "--golden", str(tmp_path / "g"), "--accept"]) == 0, \
        capsys.readouterr().out
    out = capsys.readouterr().out
    assert "PASS FreeDecay.c1" in out and "1 accepted, 0 failed" in out


def test_a_wrong_expected_initial_value_fails_and_names_it(tmp_path, capsys):
    model = _write(tmp_path, '''"c1": {"stop": 1, "initial": {"x": 4},
        "expect": {"initial": {"y": 9}}}''')
    assert main(["test", model, "--golden", str(tmp_path / "g"), "--accept"]) == 1
    out = capsys.readouterr().out
    assert "FreeDecay.c1 (initial value): signal y leaves its tube at t = 0: got 8, golden 9" in out
    assert not (tmp_path / "g").exists()            # nothing is written for a failing case


def test_dyad_default_tolerance_is_relative_sqrt_eps(tmp_path, capsys):
    # exp(-2) written to 10 digits is off by < 4e-10 relative (the reference run at rtol 1e-12
    # adds far less: passes sqrt(eps) = 1.5e-8); to 6 digits by ~2e-6 relative (fails), unless
    # the case states an atol, which then alone makes the tube.
    exact = math.exp(-2.0)
    model = _write(tmp_path, f'''
        "ten": {{"stop": 1, "initial": {{"x": 1}}, "expect": {{"final": {{"x": "{exact:.10g}"}}}}}},
        "six": {{"stop": 1, "initial": {{"x": 1}}, "expect": {{"final": {{"x": "{exact:.6g}"}}}}}},
        "six_atol": {{"stop": 1, "initial": {{"x": 1}}, "atol": {{"x": 1e-5}},
                     "expect": {{"final": {{"x": "{exact:.6g}"}}}}}}''')
    assert main(["test", model, "--golden", str(tmp_path / "g"), "--accept"]) == 1
    out = capsys.readouterr().out
    assert "PASS FreeDecay.ten" in out and "FAIL FreeDecay.six " in out
    assert "PASS FreeDecay.six_atol" in out and "2 accepted, 1 failed" in out


def test_a_case_without_expectations_passes_when_the_run_succeeds(tmp_path, capsys):
    model = _write(tmp_path, '"smoke": {"stop": 1, "initial": {"x": 1}, "signals": ["x"]}')
    assert main(["test", model, "--golden", str(tmp_path / "g"), "--accept"]) == 0
    out = capsys.readouterr().out
    assert "PASS FreeDecay.smoke" in out and "did you mean expect.signals?" in out


def test_an_initial_map_naming_nothing_of_the_model_is_a_located_error(tmp_path, capsys):
    model = _write(tmp_path, '''"c1": {"stop": 1, "initial": {"xx": 1}, "expect": {"final": {"x": 0}}}''')
    assert main(["test", model, "--golden", str(tmp_path / "g"), "--accept"]) == 1
    out = capsys.readouterr().out
    assert "neither a variable nor a parameter of FreeDecay" in out and "did you mean `x`?" in out
    line = next(n for n, text in enumerate(open(model).read().splitlines(), 1) if '"c1"' in text)
    assert f"{os.path.basename(model)}:{line}:" in out     # the case's key in the source


def test_the_initial_map_replaces_the_models_own_initial_condition(tmp_path):
    path = tmp_path / "Fixed.dyad"
    path.write_text(DECAY.replace("FreeDecay", "Fixed")
                    .replace("relations\n", "relations\n  initial x = 1\n")
                    .replace('"CASES"', '"c1": {"stop": 1, "initial": {"x": 5}, '
                                        '"expect": {"initial": {"x": 5}}}'))
    reports = golden.run_tests(str(path), [], golden_dir=tmp_path / "g", accept=True)
    assert [r.passed for r in reports] == [True], reports[0].format()
