"""What a new `dyadc` process does to start quickly (issue 15 item 4, docs/cache.md "How fast"):
the command line is built with the one command asked for, numpy's OpenBLAS is loaded on one
thread unless the user chose a count, and both leave what a run reads and does unchanged."""
from __future__ import annotations

import argparse
import os
import subprocess
import sys

import pytest

from compiler import cli
from tests.cache.helpers import ROOT

SAMPLE_ARGUMENTS = {
    "parse": ["parse", "a.dyad"],
    "fmt": ["fmt", "a.dyad", "-w"],
    "check": ["check", "M", "-L", "lib", "--max-elements", "5"],
    "flatten": ["flatten", "M"],
    "inspect": ["inspect", "M", "--stop", "2", "--rtol", "1e-7"],
    "compile": ["compile", "M", "-o", "out", "--standalone"],
    "simulate": ["simulate", "M", "--stop", "3", "--points", "11", "-p", "a=1", "--vars", "x", "y",
                 "--codegen", "c", "--no-cache"],
    "run": ["run", "A"],
    "sweep": ["sweep", "M", "--stop", "1", "-p", "a=1:2:3", "--serial"],
    "test": ["test", "M", "--accept"],
    "animate": ["animate", "M", "--stop", "1", "--fps", "5"],
    "cache": ["cache", "info"],
    "generate": ["generate", "-o", "g"],
    "linearize": ["linearize", "M", "--inputs", "u", "--outputs", "y", "z", "--at", "1", "--op", "u=1",
                  "-p", "a=1", "--open", "u", "--minimal", "--output", "l.json"],
    "fmu": ["fmu", "M", "-o", "m.fmu", "--fmi", "2", "--kind", "me", "-p", "a=1", "--stop", "2"],
}


def subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def test_the_command_names_are_those_of_the_whole_command_line():
    assert tuple(subcommands(cli.build_parser())) == cli.COMMANDS
    assert sorted(SAMPLE_ARGUMENTS) == sorted(cli.COMMANDS)


@pytest.mark.parametrize("command", cli.COMMANDS)
def test_one_command_reads_its_arguments_and_shows_its_help_as_the_whole_command_line(command):
    alone = cli.build_parser(command)
    assert list(subcommands(alone)) == [command]
    whole = cli.build_parser()
    arguments = SAMPLE_ARGUMENTS[command]
    assert vars(alone.parse_args(arguments)) == vars(whole.parse_args(arguments))
    assert subcommands(alone)[command].format_help() == subcommands(whole)[command].format_help()


def run_python(code: str, **env: str) -> str:
    environment = {k: v for k, v in os.environ.items() if k not in cli.BLAS_THREAD_VARIABLES}
    environment.update(env)
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=environment, capture_output=True,
                          text=True, check=True, timeout=120).stdout.strip()


BLAS_THREADS = """
import os
from compiler import cli
cli.blas_on_one_thread()
import numpy
print(os.environ.get("OPENBLAS_NUM_THREADS"), os.environ.get("OMP_NUM_THREADS"))
"""


def test_openblas_gets_one_thread_unless_the_user_chose():
    assert run_python(BLAS_THREADS) == "1 None"
    assert run_python(BLAS_THREADS, OMP_NUM_THREADS="2") == "None 2"
    assert run_python(BLAS_THREADS, OPENBLAS_NUM_THREADS="3") == "3 None"
    # numpy already loaded (the command line called from Python): too late, left alone
    assert run_python("import numpy\n" + BLAS_THREADS) == "None None"


def test_an_unknown_command_and_help_still_list_every_command():
    done = subprocess.run([sys.executable, "-m", "compiler", "simulat"], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 2 and "invalid choice: 'simulat'" in done.stderr
    assert all(f"'{name}'" in done.stderr for name in cli.COMMANDS)
    helped = subprocess.run([sys.executable, "-m", "compiler", "--help"], cwd=ROOT, capture_output=True,
                            text=True, timeout=120)
    assert helped.returncode == 0 and all(name in helped.stdout for name in cli.COMMANDS)


EXIT = """
import atexit, sys, threading, time
from compiler import cli

class Dropped:                 # freed by Python's teardown only
    def __del__(self):
        print("torn down")

kept = Dropped()
atexit.register(lambda: print("exit handler ran"))
print("output", end=" ")
if sys.argv[1] == "thread":
    threading.Thread(target=lambda: (time.sleep(0.3), print("thread finished"))).start()
cli.exit_without_teardown(3)
print("returned")
"""


def run_exit(mode: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", EXIT, mode], cwd=ROOT, capture_output=True, text=True,
                          timeout=120)


def test_the_program_ends_after_its_output_and_exit_handlers_without_teardown():
    done = run_exit("plain")
    assert done.returncode == 3
    assert done.stdout == "output exit handler ran\n"        # written, handlers run, no teardown


def test_a_running_thread_gets_the_normal_exit():
    done = run_exit("thread")
    assert done.returncode == 0
    assert done.stdout.split() == ["output", "returned", "thread", "finished", "exit", "handler", "ran",
                                   "torn", "down"]


def test_the_command_line_called_from_python_returns():
    assert cli.main(["cache", "info"]) == 0          # a caller's process goes on
