"""The bound of the fuzzer, proven in a fresh process: the worst inputs of issue 19 (huge literals,
deep nesting, huge sizes, huge output grids) and a few fuzzed examples run under a 4 GiB address-
space limit and a timeout, and end in a success or a clear error.

In process (test_fuzz_cli.py) a runaway allocation or a C loop could take the test process down;
here the kernel stops it and the test names the input.
"""
from __future__ import annotations

import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from tests.fuzz.examples import example_dir, fuzz_settings, write_seed
from tests.fuzz.harness import problems, run_in_subprocess
from tests.fuzz.known_bugs import known_bug
from tests.fuzz.mutations import mutate_source
from tests.fuzz.seeds import OSCILLATOR, SEEDS, nested
from tests.fuzz.test_fuzz_cli import COMMANDS, command_line, source_mutation

SUBPROCESS_TIME_LIMIT_S = 60.0


def _oscillator(replace: str, by: str) -> str:
    assert replace in OSCILLATOR.text
    return OSCILLATOR.text.replace(replace, by, 1)


# (id, model text, dyadc arguments after the model path)
WORST_CASES = [
    ("5000-digit-integer", _oscillator("4.0", "1" + "0" * 5000), ["simulate", "--stop", "1", "--points", "5"]),
    ("sin-5000-deep", _oscillator("-k * x", nested("sin", 5000, "-k * x")), ["check"]),
    ("unary-minus-5000", _oscillator("-k * x", nested("minus", 5000, "k") + " * x"), ["check"]),
    ("sum-20000-terms", _oscillator("-k * x", "-k * x + " + nested("sum", 20000, "0")), ["check"]),
    ("metadata-5000-deep", OSCILLATOR.text.replace("end\n", "metadata " + '{"a": ' * 5000 + "1" + "}" * 5000
                                                   + "\nend\n"), ["check"]),
    ("power-tower", _oscillator("4.0", "9^9^9"), ["check"]),
    ("array-1e9", _oscillator("variable v::Real(initial = 0.0)",
                              "variable v::Real(initial = 0.0)\n  variable w::Real[1000000000]"), ["check"]),
    ("array-1e308", _oscillator("variable v::Real(initial = 0.0)",
                                "variable v::Real(initial = 0.0)\n  variable w::Real[1e308]"), ["check"]),
    ("for-1e9", _oscillator("der(x) = v", "for i in 1:1000000000\n    der(x) = v\n  end"), ["check"]),
    ("points-1e8", OSCILLATOR.text, ["simulate", "--stop", "1", "--points", "100000000"]),
    ("saveat-1e-9", OSCILLATOR.text, ["simulate", "--stop", "1", "--saveat", "1e-9"]),
    ("rtol-nan", OSCILLATOR.text, ["simulate", "--stop", "1", "--rtol", "nan"]),
]


@pytest.mark.parametrize("text, arguments", [case[1:] for case in WORST_CASES],
                         ids=[case[0] for case in WORST_CASES])
def test_worst_inputs_stay_bounded_in_a_fresh_process(fuzz_base, text, arguments):
    work = example_dir(fuzz_base)
    path = write_seed(work, OSCILLATOR, text)
    outcome = run_in_subprocess([arguments[0], str(path), *arguments[1:]], work, SUBPROCESS_TIME_LIMIT_S)
    found = problems(outcome, SUBPROCESS_TIME_LIMIT_S)
    assert not found, f"{'; '.join(found)}\n{outcome.describe()}"


@fuzz_settings(3, share=0.02)
@given(seed=st.sampled_from(SEEDS), command=st.sampled_from(COMMANDS),
       mutations=st.lists(source_mutation(), min_size=1, max_size=3))
def test_fuzzed_models_stay_bounded_in_a_fresh_process(fuzz_base, seed, command, mutations):
    text = seed.text
    for operation, i, j, payload in mutations:
        text = mutate_source(text, operation, i, j, payload)
    work = example_dir(fuzz_base)
    argv = command_line(command, str(write_seed(work, seed, text)), seed)
    assume(known_bug(argv, text) is None)           # recorded in test_fuzz_known_bugs.py
    outcome = run_in_subprocess(argv, work, SUBPROCESS_TIME_LIMIT_S)
    found = problems(outcome, SUBPROCESS_TIME_LIMIT_S)
    assert not found, f"{'; '.join(found)}\n{outcome.describe()}"


def test_a_million_components_are_refused_in_a_fresh_process(fuzz_base):
    # issue 19: `[Osc() for i in 1:1000000]` ran for minutes up to 7.7 GB, then a MemoryError
    work = example_dir(fuzz_base)
    text = OSCILLATOR.text + "component Many\n  oscs = [Oscillator() for i in 1:1000000]\nend\n"
    path = write_seed(work, OSCILLATOR, text)
    outcome = run_in_subprocess(["check", f"{path}:Many"], work, SUBPROCESS_TIME_LIMIT_S)
    assert not problems(outcome, SUBPROCESS_TIME_LIMIT_S), outcome.describe()
    assert outcome.status == 1, outcome.describe()
    assert "(1,000,000 x Oscillator) would create 5,000,000 elements, more than the limit of 1,000,000" \
        in outcome.stderr, outcome.describe()
