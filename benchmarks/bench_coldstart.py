"""Cold start of `dyadc simulate` (issue 15 item 4): each run a new process, as a user types it.

  uncached   the first run of a model: an empty cache folder, so the model is compiled (and
             stored); the shipped library's trees made at install are there (as after `pip
             install`: compiler/cache/library_trees.py), so its files are not parsed
  bare       as uncached, without those trees (a package installed without them): every file
             read is parsed
  cached     the second run of the unchanged model: the compiled model comes from the cache
  no-cache   `--no-cache`: compiled, nothing stored (the first run minus the cache write)
  parsed     compiled again with the parsed source files kept (the compiled models removed, as
             when the model's own file was edited: only that file would be parsed again)

Wall time (time.perf_counter around the process) and CPU time (user + sys of the child, from
os.wait4) are both reported: on a loaded machine wall time mostly measures the other processes,
CPU time what dyadc costs. The runs use a copy of the sources taken when the benchmark starts (the
package laid out as a wheel installs it), so that edits made meanwhile in the work tree, which
rightly make the next run compile again, do not mix into the numbers. Medians over --repeat runs, the kinds interleaved, after a warm-up run
that writes Python's bytecode (into a temporary folder) as installing a package does. With --profile, one
more run of each kind under `python -X importtime` gives the import profile (top-level packages,
cumulative, in ms) and a run in process gives the compile stages.

With --codegen the rows are the first (uncached) and the second (cached) run on compiled C, the
default where a C compiler is present, and on CasADi's VM (`--codegen vm`); C's CPU includes the
compiler processes (os.wait4 counts the child's waited-for children).

    .venv/bin/python benchmarks/bench_coldstart.py [--repeat 5] [--profile] [--ref HEAD] [--model M --stop T]
    .venv/bin/python benchmarks/bench_coldstart.py --codegen [--repeat 5] [--model M --stop T]
"""
from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"


SOURCES = ROOT        # replaced by the snapshot in main()


def snapshot(folder: Path, ref: str | None = None) -> Path:
    """A copy of the package as installed: compiler/ with the library in compiler/components/,
    from the work tree, or from the commit `ref` (`git archive`)."""
    source = ROOT
    if ref is not None:
        source = folder / "checkout"
        source.mkdir()
        archive = subprocess.run(["git", "archive", "--format=tar", ref, "compiler", "components"], cwd=ROOT,
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(source)], input=archive, check=True)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", TREES.name)
    shutil.copytree(source / "compiler", folder / "compiler", ignore=ignore)
    shutil.copytree(source / "components", folder / "compiler" / "components", ignore=ignore)
    if (folder / "compiler" / "cache" / "library_trees.py").is_file():       # as setup.py does
        subprocess.run([sys.executable, "-m", "compiler.cache.library_trees", "compiler/components",
                        str(TREES)], cwd=folder, check=True, capture_output=True)
    if (folder / "compiler" / "runtime" / "native_build.py").is_file():      # as setup.py does
        subprocess.run([sys.executable, "-c", BUILD_CSV_LIBRARY], cwd=folder, check=True, capture_output=True)
    return folder


# the C CSV formatter (compiler/runtime/native_build.py), unless the copied work tree holds it
# already or no C compiler is found
BUILD_CSV_LIBRARY = ("from compiler.runtime import native_build as n; "
                     "n.csv_library_path().is_file() or n.find_compiler() is None or n.build_csv_library()")


TREES = Path("compiler/cache/shipped_trees")      # the trees of the shipped library, in a snapshot


def timed_run(command: list[str], env: dict) -> tuple[float, float]:
    """(wall s, CPU s) of one process running `command`, its output discarded."""
    began = time.perf_counter()
    process = subprocess.Popen(command, cwd=SOURCES, env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - began
    errors = process.stderr.read().decode()
    process.stderr.close()
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed:\n{errors}")
    return wall, usage.ru_utime + usage.ru_stime


def dyadc(*args: str) -> list[str]:
    return [sys.executable, "-m", "compiler", *args]


def environment(cache: Path, bytecode: Path | None = None) -> dict:
    """dyadc's cache in `cache`; Python's bytecode kept in `bytecode` (as for an installed package,
    whose .pyc files pip writes: without them every run compiles dyadc's modules again, 0.1-0.25 s)."""
    # as a user's shell: no BLAS thread count (dyadc picks one), bytecode written
    skipped = ("DYADC_CACHE", "PYTHONDONTWRITEBYTECODE", "OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS",
               "OMP_NUM_THREADS")
    env = {k: v for k, v in os.environ.items() if k not in skipped}
    env["DYADC_CACHE_DIR"] = str(cache)
    if bytecode is not None:
        env["PYTHONPYCACHEPREFIX"] = str(bytecode)
    return env


def measure(model: str, stop: float, repeat: int) -> dict[str, list[tuple[float, float]]]:
    run = ["simulate", model, "--stop", str(stop)]
    samples: dict[str, list[tuple[float, float]]] = {"uncached": [], "cached": [], "no-cache": [],
                                                      "parsed": [], "bare": []}
    trees, hidden = SOURCES / TREES, SOURCES / f"{TREES}.hidden"
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-cache-") as scratch:
        bytecode = Path(scratch) / "bytecode"
        timed_run(dyadc(*run), environment(Path(scratch) / "warm-up", bytecode))
        for attempt in range(repeat):
            cache = Path(scratch) / f"cache{attempt}"
            env = environment(cache, bytecode)
            samples["uncached"].append(timed_run(dyadc(*run), env))
            samples["cached"].append(timed_run(dyadc(*run), env))
            samples["no-cache"].append(timed_run(dyadc(*run, "--no-cache"), env))
            shutil.rmtree(cache / "models")
            samples["parsed"].append(timed_run(dyadc(*run), env))
            shutil.rmtree(cache, ignore_errors=True)
            if trees.is_dir():
                trees.rename(hidden)
            try:
                samples["bare"].append(timed_run(dyadc(*run), env))
            finally:
                if hidden.is_dir():
                    hidden.rename(trees)
            shutil.rmtree(cache, ignore_errors=True)
    return samples


def measure_codegen(model: str, stop: float, repeat: int) -> dict[str, list[tuple[float, float]]]:
    """First and second runs on C and on the VM, interleaved, each first run with an empty cache."""
    run = ["simulate", model, "--stop", str(stop)]
    samples: dict[str, list[tuple[float, float]]] = {"uncached, C": [], "uncached, VM": [],
                                                      "cached, C": [], "cached, VM": []}
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-cache-") as scratch:
        bytecode = Path(scratch) / "bytecode"
        timed_run(dyadc(*run), environment(Path(scratch) / "warm-up", bytecode))
        for attempt in range(repeat):
            for code, extra in (("C", []), ("VM", ["--codegen", "vm"])):
                cache = Path(scratch) / f"cache-{code}-{attempt}"
                env = environment(cache, bytecode)
                samples[f"uncached, {code}"].append(timed_run(dyadc(*run, *extra), env))
                samples[f"cached, {code}"].append(timed_run(dyadc(*run, *extra), env))
                shutil.rmtree(cache, ignore_errors=True)
    return samples


def import_profile(model: str, stop: float, cached: bool) -> list[tuple[str, float]]:
    """Top-level imports of one run, (name, cumulative ms), largest first."""
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-cache-") as scratch:
        env = environment(Path(scratch) / "cache", Path(scratch) / "bytecode")
        command = [sys.executable, "-X", "importtime", "-m", "compiler", "simulate", model, "--stop", str(stop)]
        timed_run(command[:1] + command[3:], env)               # bytecode written, cache filled
        if not cached:
            shutil.rmtree(Path(scratch) / "cache")
        done = subprocess.run(command, cwd=SOURCES, env=env, capture_output=True, text=True)
    rows = []
    for line in done.stderr.splitlines():
        match = re.match(r"import time:\s+\d+ \|\s+(\d+) \| (\S.*)$", line)
        if match:                                          # no indentation: imported by dyadc itself
            rows.append((match.group(2), int(match.group(1)) / 1000))
    return sorted(rows, key=lambda row: -row[1])


def stage_profile(model: str, stop: float) -> dict[str, float]:
    """The compile stages of one uncached run, in a new process (CPU-bound, wall seconds)."""
    code = f"""
import json, time
began = time.perf_counter()
from compiler.pipeline import compile_or_load
from compiler.api import simulate_compiled
imported = time.perf_counter()
compilation = compile_or_load({model!r})
compiled = time.perf_counter()
simulate_compiled(compilation, {stop!r})
ran = time.perf_counter()
stages = dict(compilation.timings)
stages["imports of the compiler stages"] = compiled - imported - sum(stages.values())
print(json.dumps({{"imports before compiling": imported - began, **stages, "simulation": ran - compiled}}))
"""
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-cache-") as scratch:
        env = environment(Path(scratch) / "cache", Path(scratch) / "bytecode")
        timed_run([sys.executable, "-c", code], env)               # bytecode written
        shutil.rmtree(Path(scratch) / "cache")
        done = subprocess.run([sys.executable, "-c", code], cwd=SOURCES, env=env, capture_output=True,
                              text=True, check=True)
    return json.loads(done.stdout)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", default=EXCAVATOR)
    parser.add_argument("--stop", type=float, default=12.0)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--profile", action="store_true", help="also the import and stage profiles")
    parser.add_argument("--codegen", action="store_true", help="first and second runs on C and on the VM")
    parser.add_argument("--ref", metavar="COMMIT", help="measure this commit (e.g. HEAD) instead of the "
                                                       "work tree with its uncommitted edits")
    args = parser.parse_args()
    global SOURCES
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-sources-") as copy:
        SOURCES = snapshot(Path(copy), args.ref)
        used = subprocess.run([sys.executable, "-c", "import compiler; print(compiler.__file__)"], cwd=SOURCES,
                              capture_output=True, text=True, check=True).stdout.strip()
        if not Path(used).is_relative_to(SOURCES):
            raise SystemExit(f"the runs would import {used}, not the snapshot in {SOURCES}")
        return report(args)


def report(args) -> int:
    samples = (measure_codegen if args.codegen else measure)(args.model, args.stop, args.repeat)
    print(f"dyadc simulate {args.model} --stop {args.stop:g}: medians of {args.repeat} new processes "
          f"(load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)\n")
    print("| run | wall s | CPU s | wall, each run | CPU, each run |")
    print("|---|---|---|---|---|")
    for kind, runs in samples.items():
        walls, cpus = [w for w, _ in runs], [c for _, c in runs]
        print(f"| {kind} | {statistics.median(walls):.2f} | {statistics.median(cpus):.2f} | "
              f"{' '.join(f'{w:.2f}' for w in walls)} | {' '.join(f'{c:.2f}' for c in cpus)} |")
    if args.profile:
        for cached in (False, True):
            rows = import_profile(args.model, args.stop, cached)
            print(f"\nimports of a {'cached' if cached else 'uncached'} run (cumulative ms, top level): "
                  + ", ".join(f"{name} {ms:.0f}" for name, ms in rows[:10]))
        stages = stage_profile(args.model, args.stop)
        print("\nstages of an uncached run (s): " + ", ".join(f"{k} {v:.3f}" for k, v in stages.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
