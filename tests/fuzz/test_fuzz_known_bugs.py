"""Reproducers of the bugs the fuzzer found (issue 19), each the smallest input found.

A bug not fixed yet is a strict xfail (`@_bug(name, what)`) with an entry of the same name in
known_bugs.py: it passes, and so fails the suite, once the bug is fixed; then remove the mark here
and the entry there, so that the fuzzer covers the input again. Every test below is such a
reproducer whose bug is fixed: it now checks the clear error that replaced the bug.

Hangs are bounded: in a fresh process killed after SUBPROCESS_HANG_LIMIT_S when the hang is in
C calls that an alarm cannot interrupt, else in process by an alarm after HANG_LIMIT_S. A fixed
dyadc answers these one-line changes in about a second on an idle machine; the bounds are those
of every fuzzed example (harness.TIME_LIMIT_S), since a machine shared by many test runs can
take 15 s just to start a process (measured at a load average of 11 on 2 cores), while the bugs
ran for minutes.
"""
from __future__ import annotations

import re

import pytest

from tests.fuzz.examples import example_dir, write_seed
from tests.fuzz.harness import TIME_LIMIT_S, is_located, problems, run_in_process, run_in_subprocess
from tests.fuzz.known_bugs import known_bug
from tests.fuzz.seeds import OSCILLATOR

HANG_LIMIT_S = TIME_LIMIT_S
SUBPROCESS_HANG_LIMIT_S = TIME_LIMIT_S
LIMIT = "more than the limit of 1,000,000"


def _oscillator_with(work, old: str, new: str) -> str:
    assert old in OSCILLATOR.text
    return str(write_seed(work, OSCILLATOR, OSCILLATOR.text.replace(old, new, 1)))


def _assert_clear(outcome, seconds):
    """No hang, internal error or traceback. A success passes too: every test adds the exit status
    and the message it expects."""
    found = problems(outcome, seconds)
    assert not found, f"{'; '.join(found)}\n{outcome.describe()}"


def _assert_plain_error(outcome, first_line: str):
    """Exit 1 with `first_line` as the first line of stderr (a clear error, never a success)."""
    assert outcome.status == 1, outcome.describe()
    assert outcome.stderr.splitlines()[0] == first_line, outcome.describe()
    assert "internal" not in outcome.stderr and "Traceback" not in outcome.stderr, outcome.describe()


def _assert_located(outcome, path: str, line: int, words: str):
    assert outcome.status == 1 and is_located(outcome), outcome.describe()
    first = outcome.stderr.splitlines()[0]
    assert re.match(rf"{re.escape(path)}:{line}:\d+: error: ", first), outcome.describe()
    assert words in first, outcome.describe()


def test_no_input_is_skipped_as_a_known_bug_any_more():
    assert known_bug(["check", "x" * 300, "a\x00"], "9^9^9 Real[1e308] 1:1000000000") is None


# -------------------------------------------------- was name-too-long: an internal OSError ENAMETOOLONG

@pytest.mark.parametrize("arguments, words", [
    (["check", "x" * 300], "no model `xxxx"),
    (["simulate", "{model}", "--stop", "1", "--output", "x" * 300 + ".csv"],
     "--output `xxx"),
    (["simulate", "{model}", "--stop", "1", "--plot", "d/" + "y" * 256 + "/p.png"], "is 256 bytes long"),
    (["check", "{folder}/" + "z" * 300 + ".dyad"], "is 305 bytes long"),
    (["parse", "q" * 300 + ".dyad"], "FILE `qqq"),
    (["check", "{model}", "-L", "L" * 256], "-L `LLL"),
], ids=["model-name", "output", "plot-folder", "model-file", "parse-file", "lib"])
def test_a_name_too_long_for_a_file_is_a_clear_error(fuzz_base, arguments, words):
    work = example_dir(fuzz_base)
    model = str(write_seed(work, OSCILLATOR))
    argv = [a.replace("{model}", model).replace("{folder}", str(work)) for a in arguments]
    outcome = run_in_process(argv, work)
    _assert_clear(outcome, HANG_LIMIT_S)
    assert outcome.status == 1 and outcome.stderr.startswith("error: ") and words in outcome.stderr, \
        outcome.describe()
    assert "internal" not in outcome.stderr and not list(work.glob("x*"))


def test_a_component_named_with_300_characters_in_a_model_file_checks(fuzz_base):
    # was looked up as components/<name>.dyad: an internal OSError (ENAMETOOLONG)
    work = example_dir(fuzz_base)
    text = OSCILLATOR.text.replace("component Oscillator", "component " + "x" * 300)
    outcome = run_in_process(["check", str(write_seed(work, OSCILLATOR, text))], work)
    _assert_clear(outcome, HANG_LIMIT_S)
    assert outcome.status == 0 and "balanced: 2 equations, 2 unknowns" in outcome.stdout, outcome.describe()


# ------------------------------------------------------ was nul-in-argument: an internal ValueError

def test_a_nul_byte_in_an_argument_is_a_clear_error(fuzz_base):
    # only callers of compiler.cli.main can pass one: a shell cannot
    work = example_dir(fuzz_base)
    model = str(write_seed(work, OSCILLATOR))
    for argv in (["parse", "a\x00"], ["simulate", model, "--stop", "1", "--output", "o\x00.csv"],
                 ["simulate", model, "--stop", "1", "-p", "k=1\x00"]):
        outcome = run_in_process(argv, work)
        _assert_clear(outcome, HANG_LIMIT_S)
        assert outcome.status == 1 and "contains a NUL byte" in outcome.stderr, outcome.describe()


# ------------------------------------------------------------------- fixed before: plain tests

def test_a_span_shorter_than_round_off_is_a_clear_error(fuzz_base):
    # found by the fuzzer: was an internal IndexError (an empty list of segment ends)
    work = example_dir(fuzz_base)
    argv = ["simulate", str(write_seed(work, OSCILLATOR)), "--stop", "1e-14", "--points", "5"]
    outcome = run_in_process(argv, work)
    _assert_clear(outcome, HANG_LIMIT_S)
    _assert_plain_error(outcome, "error: the span from --start 0 to --stop 1e-14 is shorter than round-off")


def test_an_absolute_tolerance_below_what_a_solver_resolves_is_refused(fuzz_base):
    # found by the fuzzer: --atol 1e-300 ran for minutes
    work = example_dir(fuzz_base)
    argv = ["simulate", str(write_seed(work, OSCILLATOR)), "--stop", "1", "--points", "5", "--atol", "1e-300"]
    outcome = run_in_process(argv, work, seconds=HANG_LIMIT_S)
    _assert_clear(outcome, HANG_LIMIT_S)
    _assert_plain_error(outcome, "error: --atol 1e-300 is below 1e-100: no solver resolves it")
    assert "hint: tolerances are relative (--rtol) or absolute (--atol) errors" in outcome.stderr, outcome.describe()


# --------------------------------------------- was power-tower-hangs: 9^387420489 evaluated exactly

def test_a_power_tower_is_a_located_error_at_once(fuzz_base):
    work = example_dir(fuzz_base)
    path = _oscillator_with(work, "4.0", "9^9^9")
    outcome = run_in_subprocess(["check", path], work, seconds=SUBPROCESS_HANG_LIMIT_S)
    _assert_clear(outcome, SUBPROCESS_HANG_LIMIT_S)
    _assert_located(outcome, path, 3, "the power 9^387420489 is too large: about 10^369,693,099")


@pytest.mark.parametrize("power, words", [
    ("4.0^4.0^4.0^4.0", "the power 4.0^1.34078e+154 is too large: about 10^8.07e+153"),
    ("2.0^2000.0", "the power 2.0^2000.0 is too large: about 10^602"),
    ("(-8.0)^(1/3)", "the power (-8.0)^(1/3) is not a real number"),
], ids=["float-tower", "beyond-float", "negative-base"])
def test_a_power_of_floats_is_checked_like_one_of_integers(fuzz_base, power, words):
    # found by the fuzzer (2000 examples, 2026-11-28): a float tower was an internal OverflowError
    # ("too many digits in integer") from sympy's arbitrary-precision power
    work = example_dir(fuzz_base)
    path = _oscillator_with(work, "4.0", power)
    outcome = run_in_process(["check", path], work)
    _assert_clear(outcome, HANG_LIMIT_S)
    _assert_located(outcome, path, 3, words)


def test_a_tower_of_parameters_beyond_a_float_is_a_clear_error_at_the_start(fuzz_base):
    # found by the fuzzer (2000 examples, 2026-11-28): the start-point completion evaluated
    # k^k^...^k with k = 4.0 exactly and raised an internal OverflowError
    work = example_dir(fuzz_base)
    path = _oscillator_with(work, "-k * x", "-k^k^k^k^k * x")
    outcome = run_in_process(["simulate", path, "--stop", "1", "--points", "5"], work)
    _assert_clear(outcome, HANG_LIMIT_S)
    _assert_plain_error(outcome, "error: simulation of Oscillator failed at t = 0: IDA_FIRST_RES_FAIL: the "
                        "residual function failed at the first call (IDAS: the equations have no "
                        "finite value at the start)")


# ------------------------------------ was exponent-size and huge-size: no estimate before allocating

@pytest.mark.parametrize("declaration, words", [
    ("variable w::Real[1e308]", "the array `w` would create about 1e+308 elements, " + LIMIT),
    ("variable w::Real[-1e308]", "an array size cannot be negative, got about -1e+308"),
    ("variable w::Real[1000000000]", "the array `w` would create 1,000,000,000 elements, " + LIMIT),
], ids=["1e308", "-1e308", "1e9"])
def test_a_huge_array_is_refused_before_allocating(fuzz_base, declaration, words):
    # was an internal ValueError (Maximum allowed dimension exceeded) or MemoryError (7.45 GiB)
    work = example_dir(fuzz_base)
    text = "variable v::Real(initial = 0.0)\n  " + declaration
    path = _oscillator_with(work, "variable v::Real(initial = 0.0)", text)
    # in a fresh process under the 4 GiB limit: were it allocated, it would take the worker's memory
    outcome = run_in_subprocess(["check", path], work, seconds=SUBPROCESS_HANG_LIMIT_S)
    _assert_clear(outcome, SUBPROCESS_HANG_LIMIT_S)
    _assert_located(outcome, path, 7, words)


@pytest.mark.parametrize("old, new, line, words", [
    ("der(x) = v", "for i in 1:1000000000\n    der(x) = v\n  end", 8,
     "this range would create 1,000,000,000 elements, " + LIMIT),
    ("der(x) = v", "der(x) = v + 0 * sum([i for i in 1:1000000000])", 8,
     "this range would create 1,000,000,000 elements, " + LIMIT),
], ids=["for-loop", "comprehension"])
def test_a_huge_range_is_refused_before_unrolling(fuzz_base, old, new, line, words):
    # was no answer for minutes
    work = example_dir(fuzz_base)
    path = _oscillator_with(work, old, new)
    outcome = run_in_subprocess(["check", path], work, seconds=SUBPROCESS_HANG_LIMIT_S)
    _assert_clear(outcome, SUBPROCESS_HANG_LIMIT_S)
    _assert_located(outcome, path, line, words)


def test_a_sweep_whose_every_sample_fails_ends_with_an_error_line(fuzz_base):
    """Found by fuzzing `dyadc sweep` (issue 25 item 4): every sample failed and the command
    exited 1 with the summary only, no `error:` line. A velocity bound every sample leaves."""
    work = example_dir(fuzz_base)
    path = _oscillator_with(work, "variable v::Real(initial = 0.0)", "variable v::Real(initial = 0.0, min = -0.5)")
    outcome = run_in_process(["sweep", path, "--stop", "1", "--points", "5", "-p", "k=[3,4]", "--serial",
                              "--no-progress"], work)
    _assert_clear(outcome, HANG_LIMIT_S)
    assert outcome.status == 1, outcome.describe()
    assert outcome.stderr.startswith("Oscillator: 0 of 2 samples succeeded, 2 failed\n"), outcome.describe()
    assert outcome.stderr.splitlines()[-1] == "error: no sample of 2 succeeded (the reasons are above)"


def test_a_capacitance_of_1e308_simulates(fuzz_base):
    """Found by fuzzing `dyadc simulate` on branch meta25, before it landed: the derivative-rank
    analysis with the capacitor's current replaced by C * der(v) met an infinite coefficient
    (C = 1e308 times the capacitor's own), and numpy's least squares raised an internal
    LinAlgError. Non-finite coefficients now leave the row out."""
    from tests.fuzz.seeds import LIBRARY_RC
    work = example_dir(fuzz_base)
    text = LIBRARY_RC.text.replace("Capacitor(C = 1e-3)", "Capacitor(C = 1e308)")
    assert text != LIBRARY_RC.text
    outcome = run_in_process(["simulate", str(write_seed(work, LIBRARY_RC, text)), "--stop", "0.5", "--points", "5"], work)
    _assert_clear(outcome, HANG_LIMIT_S)
    assert outcome.status == 0, outcome.describe()


def test_linearize_of_a_mass_that_underflows_to_zero_gives_a_clear_error(fuzz_base):
    """Found by fuzzing `dyadc linearize` (issue 25 item 4): m = 1e-400 is 0, der(v) = -k x / m
    made A infinite and numpy's eigenvalues raised an internal LinAlgError. Fixed 2026-11-28: a
    linearization that is not finite is refused with the located error of a run from the start
    (compiler/linear/request.py), the one `dyadc simulate` gives."""
    work = example_dir(fuzz_base)
    path = _oscillator_with(work, "parameter m::Real = 1.0", "parameter m::Real = 1e-400")
    outcome = run_in_process(["linearize", path], work)
    _assert_clear(outcome, HANG_LIMIT_S)
    assert outcome.status == 1 and is_located(outcome), outcome.describe()
    assert f"{path}:9:3: error: the model is singular at the start: with `m` = 0" in outcome.stderr, outcome.describe()
