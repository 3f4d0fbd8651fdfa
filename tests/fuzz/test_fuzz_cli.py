"""Fuzzing `dyadc` (issue 19): mutated models, mutated command lines and hostile names end in a
success or a clear error (exit 1, `FILE:LINE:COL: error:` or `error:`; argparse's usage error,
exit 2), never in an internal error, a traceback, a hang or unbounded memory.

Runs in process through `compiler.cli.main` (see harness.py for the bounds); `make fuzz` runs the
same tests with DYADC_FUZZ_EXAMPLES examples each.
"""
from __future__ import annotations

import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from tests.fuzz.examples import example_dir, fuzz_settings, write_seed
from tests.fuzz.harness import ExampleTimeout, Outcome, is_located, problems, run_in_process
from tests.fuzz.known_bugs import known_bug
from tests.fuzz.mutations import ARGV_OPERATIONS, SOURCE_OPERATIONS, mutate_argv, mutate_source
from tests.fuzz.seeds import EXTREME_NUMBERS, HOSTILE_NAMES, NESTING_DEPTHS, NESTING_KINDS, SEEDS

COMMANDS = ("parse", "fmt", "check", "flatten", "simulate")
# Every other command that reads a model (compiler/cli): each reads the same mutated sources.
MODEL_COMMANDS = ("inspect", "compile", "run", "sweep", "test", "linearize", "animate", "fmu")
# A parameter of each seed that `sweep` varies over two values
SWEPT = {"Oscillator": "k=[3,4]", "RCLadder": "R=[1000,2000]", "LibraryRC": "resistor.R=[100,200]"}


def command_line(command: str, path: str, seed) -> list[str]:
    """The command on the seed's file (for `run`, the file holds the analysis `with_analysis` adds)."""
    if command == "simulate":
        return ["simulate", path, "--stop", seed.stop, "--points", "5"]
    if command == "inspect":
        return ["inspect", path, "--stop", seed.stop]
    if command == "compile":
        return ["compile", path, "-o", "generated"]
    if command == "run":
        return ["run", path, "--points", "5"]
    if command == "sweep":
        return ["sweep", path, "--stop", seed.stop, "--points", "5", "-p", SWEPT[seed.name], "--serial",
                "--no-progress", "--output", "sweep.csv"]
    if command == "test":
        return ["test", path, "--golden", "golden"]
    if command == "animate":
        return ["animate", path, "--stop", seed.stop, "--frames", "2", "--output", "side.gif"]
    if command == "fmu":
        return ["fmu", path, "-o", "model.fmu"]
    return [command, path]


def with_analysis(command: str, text: str, seed) -> str:
    """The seed's source with, for `run`, a transient analysis of the seed (before mutation, so
    that the analysis's fields are mutated too: `stop = 9^9^9` once hung `dyadc run`)."""
    if command != "run":
        return text
    return text + (f"\nanalysis {seed.name}Run\n  extends TransientAnalysis(stop = {seed.stop})\n"
                   f"  model = {seed.name}()\nend\n")


@st.composite
def source_mutation(draw):
    operation = draw(st.sampled_from(SOURCE_OPERATIONS))
    payload = ""
    if operation == "number":
        payload = draw(st.sampled_from(EXTREME_NUMBERS))
    elif operation in ("rename", "string"):
        payload = draw(st.sampled_from(HOSTILE_NAMES))
    elif operation == "nest":
        payload = f"{draw(st.sampled_from(NESTING_KINDS))}:{draw(st.sampled_from(NESTING_DEPTHS))}"
    return operation, draw(st.integers(0, 10**6)), draw(st.integers(0, 10**6)), payload


def assert_clear(outcome):
    found = problems(outcome)
    assert not found, f"{'; '.join(found)}\n{outcome.describe()}"


def test_the_oracle_tells_clear_errors_from_internal_ones():
    def judged(status, stderr, seconds=0.1, escaped=None):
        return problems(Outcome(["check", "M.dyad"], status, "", stderr, seconds, escaped))
    assert judged(0, "") == []
    assert judged(1, "M.dyad:3:7: error: unknown variable `y`\n    der(x) = y\n") == []
    assert judged(1, "error: --rtol must be positive, got 0\n") == []
    assert judged(2, "usage: dyadc check ...\ndyadc check: error: the following arguments are required\n") == []
    assert judged(2, "internal error: IndexError: list index out of range\n") == ["internal error"]
    assert "traceback on stderr" in judged(1, "Traceback (most recent call last):\nerror: x\n")
    assert judged(1, "it failed\n") == ["exit 1 without a clear message"]
    assert judged(-9, "") == ["killed by signal 9"]
    assert judged(None, "", escaped=RecursionError("deep")) == ["RecursionError escaped main(): deep"]
    assert judged(None, "", 60.0, ExampleTimeout("60 s")) == ["no outcome within 60 s"]
    assert judged(0, "", seconds=61.0) == ["took 61.0 s (limit 60 s)"]


@pytest.mark.parametrize("seed", SEEDS, ids=lambda s: s.name)
def test_every_seed_simulates(seed, fuzz_base):
    work = example_dir(fuzz_base)
    outcome = run_in_process(command_line("simulate", str(write_seed(work, seed)), seed), work)
    assert outcome.status == 0, outcome.describe()


# What each model-reading command answers on a seed as written: `test` finds no test cases and
# `animate` no planar parts in the seeds, both a located error (exit 1); the others succeed.
SEED_STATUS = {"test": 1, "animate": 1}


@pytest.mark.parametrize("command", MODEL_COMMANDS)
@pytest.mark.parametrize("seed", SEEDS, ids=lambda s: s.name)
def test_every_seed_goes_through_every_command(seed, command, fuzz_base):
    work = example_dir(fuzz_base)
    argv = command_line(command, str(write_seed(work, seed, with_analysis(command, seed.text, seed))), seed)
    outcome = run_in_process(argv, work)
    assert outcome.status == SEED_STATUS.get(command, 0), outcome.describe()
    assert_clear(outcome)
    if outcome.status:
        assert is_located(outcome), outcome.describe()


@fuzz_settings(300)
@given(seed=st.sampled_from(SEEDS), command=st.sampled_from(COMMANDS + MODEL_COMMANDS),
       mutations=st.lists(source_mutation(), min_size=1, max_size=3))
def test_mutated_model_gives_success_or_clear_error(fuzz_base, seed, command, mutations):
    text = with_analysis(command, seed.text, seed)
    for operation, i, j, payload in mutations:
        text = mutate_source(text, operation, i, j, payload)
    work = example_dir(fuzz_base)
    argv = command_line(command, str(write_seed(work, seed, text)), seed)
    assume(known_bug(argv, text) is None)           # recorded in test_fuzz_known_bugs.py
    outcome = run_in_process(argv, work)
    assert_clear(outcome)
    if outcome.status == 1 and command in ("parse", "fmt"):
        assert is_located(outcome), f"a syntax error without FILE:LINE:COL\n{outcome.describe()}"


# Values an option may get: extreme numbers, hostile names (a NUL byte too: a shell cannot pass
# one, a caller of compiler.cli.main can), paths that are folders, missing, or of an unknown
# format, parameter overrides and signal names.
ARGUMENT_VALUES = EXTREME_NUMBERS + HOSTILE_NAMES + (
    ".", "", "-", "no/such/dir/out.csv", "out.xyz", "out.csv/", "out.csv", "out.npz", "out.mat",
    "out.parquet", "plot.png", "plot.bad", "x.png.csv", "0,0.5,1", "0:0.1:1", "1:-0.1:0", "0:0:1",
    "1e-9", "0.3", "1,nan", "2,1", "k=nan", "k=inf", "k=1e400", "k=-0", "k=5mm", "k=1 furlong", "R=nan",
    "V=1e308", "resistor.R=0", "capacitor.C=-1", "m=0", "nope=1", "=1", "k", "k==1", "x", "v",
    "v[1]", "v[3]", "time", "capacitor.v", "1", "2", "-1", "100000000", "1000000000", "x" * 300 + ".csv",
    "d/" + "y" * 256 + "/p.png")

SIMULATE_OPTIONS = ("--start", "--stop", "--rtol", "--atol", "--points", "--saveat", "-p", "--vars",
                    "--output", "--plot", "--max-output-values", "--max-elements")


def base_arguments(command: str, path: str, seed, options) -> list[str]:
    """The seed's command line with each (option, value) pair set: an option given twice keeps the
    last value, as argparse does."""
    if command == "fmt":
        return ["fmt", path] + (["--write"] if options else [])
    if command != "simulate":
        return [command, path]
    argv = ["simulate", path, "--stop", seed.stop, "--points", "5"]
    for option, value in options:
        if option in ("--points", "--saveat"):           # mutually exclusive: replace the other
            argv = [a for k, a in enumerate(argv) if a not in ("--points", "--saveat")
                    and (k == 0 or argv[k - 1] not in ("--points", "--saveat"))]
        argv += [option, value]
    return argv


@fuzz_settings(300)
@given(seed=st.sampled_from(SEEDS), command=st.sampled_from(COMMANDS + ("simulate",) * 5),
       options=st.lists(st.tuples(st.sampled_from(SIMULATE_OPTIONS), st.sampled_from(ARGUMENT_VALUES)),
                        max_size=4),
       mutations=st.lists(st.tuples(st.sampled_from(ARGV_OPERATIONS), st.integers(0, 10**6),
                                    st.integers(0, 10**6), st.sampled_from(ARGUMENT_VALUES)),
                          max_size=2))
def test_mutated_command_line_gives_success_or_clear_error(fuzz_base, seed, command, options, mutations):
    work = example_dir(fuzz_base)
    argv = base_arguments(command, str(write_seed(work, seed)), seed, options)
    for operation, i, j, payload in mutations:
        argv = mutate_argv(argv, operation, i, j, payload)
    assume(known_bug(argv, seed.text) is None)      # recorded in test_fuzz_known_bugs.py
    assert_clear(run_in_process(argv, work))


def _usable_as_path(name: str) -> bool:
    return "\x00" not in name and name not in ("", ".", "..") and len(name.encode()) < 200


@fuzz_settings(100)
@given(seed=st.sampled_from(SEEDS), name=st.sampled_from(HOSTILE_NAMES),
       where=st.sampled_from(["file", "folder", "component", "spec", "library"]),
       command=st.sampled_from(("check", "flatten", "simulate", "parse")))
def test_hostile_names_give_success_or_clear_error(fuzz_base, seed, name, where, command):
    """A hostile name as the model file's name, its folder, its component name, the model spec
    (`FILE:NAME`) or a package name on the library path (`-L DIR`, `Package.Model`)."""
    work = example_dir(fuzz_base)
    text, spec, extra = seed.text, None, []
    if where == "file" and _usable_as_path(name):
        path = work / f"{name}.dyad"
        path.parent.mkdir(parents=True, exist_ok=True)
        text = text.replace(f"component {seed.name}", f"component {name}")
        path.write_text(text, encoding="utf-8")
        spec = str(path)
    elif where == "folder" and _usable_as_path(name):
        folder = work / name
        folder.mkdir(parents=True, exist_ok=True)
        spec = str(write_seed(folder, seed))
    elif where == "component":
        text = text.replace(f"component {seed.name}", f"component {name}")
        spec = str(write_seed(work, seed, text))
    elif where == "spec":
        spec = f"{write_seed(work, seed)}:{name}"
    elif where == "library" and _usable_as_path(name):
        package = work / "lib" / name
        package.mkdir(parents=True, exist_ok=True)
        write_seed(package, seed)
        spec, extra = f"{name}.{seed.name}", ["-L", str(work / "lib")]
    else:
        spec = name
    argv = command_line(command, spec, seed) + (extra if command != "parse" else [])
    assume(known_bug(argv, text) is None)           # recorded in test_fuzz_known_bugs.py
    assert_clear(run_in_process(argv, work))
