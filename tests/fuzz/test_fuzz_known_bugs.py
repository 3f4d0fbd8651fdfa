"""Reproducers of the bugs the fuzzer found (issue 19), each the smallest input found, each a strict
xfail naming the bug: it passes, and so fails the suite, once the bug is fixed. Then remove the
mark here and the bug's entry in known_bugs.py, so that the fuzzer covers the input again.

Hangs are bounded: in a fresh process killed after SUBPROCESS_HANG_LIMIT_S when the hang is in
C calls that an alarm cannot interrupt (a dyadc process starts in about 1.5 s), else in process by
an alarm after HANG_LIMIT_S. A fixed dyadc answers these one-line changes in well under a second.
"""
from __future__ import annotations

import pytest

from tests.fuzz.examples import example_dir, write_seed
from tests.fuzz.harness import problems, run_in_process, run_in_subprocess
from tests.fuzz.known_bugs import known_bug
from tests.fuzz.seeds import OSCILLATOR

HANG_LIMIT_S = 4.0
SUBPROCESS_HANG_LIMIT_S = 6.0


def _oscillator_with(work, old: str, new: str) -> str:
    assert old in OSCILLATOR.text
    return str(write_seed(work, OSCILLATOR, OSCILLATOR.text.replace(old, new, 1)))


def _assert_clear(outcome, seconds):
    found = problems(outcome, seconds)
    assert not found, f"{'; '.join(found)}\n{outcome.describe()}"


def _bug(name: str, what: str):
    return pytest.mark.xfail(strict=True, reason=f"known bug {name}: {what}")


@_bug("name-too-long", "a model name or output file name over 255 bytes is an internal OSError "
                       "(ENAMETOOLONG) instead of a clear error")
@pytest.mark.parametrize("arguments", [["check", "x" * 300],
                                       ["simulate", "{model}", "--stop", "1", "--output", "x" * 300 + ".csv"]],
                         ids=["model", "output"])
def test_name_too_long(fuzz_base, arguments):
    work = example_dir(fuzz_base)
    model = str(write_seed(work, OSCILLATOR))
    argv = [a.replace("{model}", model) for a in arguments]
    assert known_bug(argv) == "name-too-long"
    _assert_clear(run_in_process(argv, work), HANG_LIMIT_S)


@_bug("name-too-long", "a component named with 300 characters in a model file is looked up as "
                       "components/<name>: an internal OSError (ENAMETOOLONG)")
def test_component_name_too_long(fuzz_base):
    work = example_dir(fuzz_base)
    text = OSCILLATOR.text.replace("component Oscillator", "component " + "x" * 300)
    path = str(write_seed(work, OSCILLATOR, text))
    assert known_bug(["check", path], text) == "name-too-long"
    _assert_clear(run_in_process(["check", path], work), HANG_LIMIT_S)


@_bug("exponent-size", "`variable w::Real[1e308]` is an internal ValueError (Maximum allowed "
                       "dimension exceeded) instead of a located error on the size")
def test_exponent_size(fuzz_base):
    work = example_dir(fuzz_base)
    text = "variable v::Real(initial = 0.0)\n  variable w::Real[1e308]"
    path = _oscillator_with(work, "variable v::Real(initial = 0.0)", text)
    assert known_bug(["check", path], text) == "exponent-size"
    _assert_clear(run_in_process(["check", path], work), HANG_LIMIT_S)


@_bug("nul-in-argument", "main(['check', 'a\\0']) is an internal ValueError (embedded null byte); "
                         "only callers of compiler.cli.main can pass one, a shell cannot")
def test_nul_in_argument(fuzz_base):
    work = example_dir(fuzz_base)
    argv = ["parse", "a\x00"]
    assert known_bug(argv) == "nul-in-argument"
    _assert_clear(run_in_process(argv, work), HANG_LIMIT_S)


def test_a_span_shorter_than_round_off_is_a_clear_error(fuzz_base):
    # found by the fuzzer: was an internal IndexError (an empty list of segment ends)
    work = example_dir(fuzz_base)
    argv = ["simulate", str(write_seed(work, OSCILLATOR)), "--stop", "1e-14", "--points", "5"]
    _assert_clear(run_in_process(argv, work), HANG_LIMIT_S)


def test_an_absolute_tolerance_below_what_a_solver_resolves_is_refused(fuzz_base):
    # found by the fuzzer: --atol 1e-300 ran for minutes
    work = example_dir(fuzz_base)
    argv = ["simulate", str(write_seed(work, OSCILLATOR)), "--stop", "1", "--points", "5", "--atol", "1e-300"]
    _assert_clear(run_in_process(argv, work, seconds=HANG_LIMIT_S), HANG_LIMIT_S)


@_bug("power-tower-hangs", "`parameter k::Real = 9^9^9` makes check/flatten evaluate 9^387420489 "
                           "exactly: no answer for minutes")
def test_power_tower(fuzz_base):
    work = example_dir(fuzz_base)
    path = _oscillator_with(work, "4.0", "9^9^9")
    assert known_bug(["check", path], "9^9^9") == "power-tower-hangs"
    _assert_clear(run_in_subprocess(["check", path], work, seconds=SUBPROCESS_HANG_LIMIT_S),
                  SUBPROCESS_HANG_LIMIT_S)


@_bug("huge-size", "a size of 1e9 is not estimated before allocating (issue 19 item 5): "
                   "`Real[1000000000]` is an internal MemoryError (7.45 GiB)")
def test_huge_array(fuzz_base):
    work = example_dir(fuzz_base)
    text = "variable v::Real(initial = 0.0)\n  variable w::Real[1000000000]"
    path = _oscillator_with(work, "variable v::Real(initial = 0.0)", text)
    assert known_bug(["check", path], text) == "huge-size"
    # in a fresh process under the 4 GiB limit: in process it would take the test worker's memory
    _assert_clear(run_in_subprocess(["check", path], work, seconds=60), 60)


@_bug("huge-size", "`for i in 1:1000000000` is unrolled without a bound: no answer for minutes")
def test_huge_for_loop(fuzz_base):
    work = example_dir(fuzz_base)
    relation = "for i in 1:1000000000\n    der(x) = v\n  end"
    path = _oscillator_with(work, "der(x) = v", relation)
    assert known_bug(["check", path], relation) == "huge-size"
    _assert_clear(run_in_subprocess(["check", path], work, seconds=SUBPROCESS_HANG_LIMIT_S),
                  SUBPROCESS_HANG_LIMIT_S)


@_bug("huge-size", "`sum([i for i in 1:1000000000])` is built element by element without a bound: "
                   "no answer for minutes")
def test_huge_comprehension(fuzz_base):
    work = example_dir(fuzz_base)
    relation = "der(x) = v + 0 * sum([i for i in 1:1000000000])"
    path = _oscillator_with(work, "der(x) = v", relation)
    assert known_bug(["check", path], relation) == "huge-size"
    _assert_clear(run_in_subprocess(["check", path], work, seconds=SUBPROCESS_HANG_LIMIT_S),
                  SUBPROCESS_HANG_LIMIT_S)
