"""Compatibility of dyadc with published Dyad code (issue 17): runs dyadc, as a command, on every
.dyad file of a corpus and writes docs/compatibility.md.

    python benchmarks/compat.py CORPUS [--output docs/compatibility.md] [--json FILE] [--jobs 2]

CORPUS is a folder of Dyad repositories (one subfolder each, e.g. clones of DyadLang's
BlockComponents, ElectricalComponents, ...), or one repository. Per file: parsed (`dyadc parse`);
per component: checked (`dyadc check FILE:Name`); per test case of a component's "tests" metadata
and per analysis: simulated and, for test cases, matching the published values. See the Method
section of the generated report. Nothing is written into the corpus or the project except the
report: every dyadc call runs in a temporary folder.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import compat_corpus as corpus_scan          # noqa: E402  (benchmarks/ is not a package)
from compat_report import markdown           # noqa: E402

TIMEOUTS = {"parse": 60.0, "check": 120.0, "run": 240.0}
# Unit mismatches of published code are reported in their own column (issue 26), not counted
# against the check and simulate rates: every model command runs with the check as warnings.
UNITS = ["--units", "warn"]
_LOCATED_WARNING = re.compile(r"^(?P<file>\S+?\.dyad):(?P<line>\d+):(?P<column>\d+): warning: (?P<message>.+)$")
DEFAULT_TOLERANCE = 1e-3


def dyadc_command() -> list[str]:
    """The dyadc installed beside this Python, else `python -m compiler`."""
    script = Path(sys.executable).parent / "dyadc"
    return [str(script)] if script.is_file() else [sys.executable, "-m", "compiler"]


def call(args: list[str], timeout: float, cwd: str) -> tuple[int | None, str, str]:
    """Run one command in its own process group; on timeout kill that group. rc None = timeout."""
    proc = subprocess.Popen(args, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
        return proc.returncode, out, err
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        return None, out, err


def first_error(rc: int | None, out: str, err: str, timeout: float) -> str:
    if rc is None:
        return f"timeout after {timeout:g} s"
    if "Traceback (most recent call last)" in err:
        last = [line for line in err.strip().splitlines() if line.strip()][-1]
        return f"internal error (traceback): {last}"
    for text in (err, out):
        for line in text.splitlines():
            if "error:" in line:
                return line.strip()
    lines = [line for line in (err + "\n" + out).splitlines() if line.strip()]
    return lines[0].strip() if lines else f"exit status {rc} without a message"


class Runner:
    def __init__(self, libraries: list, workdir: Path):
        self.command = dyadc_command()
        self.libraries = libraries
        self.workdir = workdir
        self.libdir = workdir / "lib"
        self.libdir.mkdir()
        for lib in libraries:
            link = self.libdir / lib.package
            if not link.exists():
                link.symlink_to(lib.sources.resolve(), target_is_directory=True)
        help_rc, help_out, _ = call(self.command + ["--help"], TIMEOUTS["parse"], str(workdir))
        self.has_run_command = help_rc == 0 and "\n    run " in help_out

    def dyadc(self, args: list[str], stage: str, cwd: Path | None = None):
        timeout = TIMEOUTS[stage]
        rc, out, err = call(self.command + args, timeout, str(cwd or self.workdir))
        return rc, out, err, first_error(rc, out, err, timeout)

    def lib_args(self) -> list[str]:
        return ["-L", str(self.libdir), *UNITS]

    def unit_findings(self, err: str) -> list[dict]:
        """The located warnings of `--units warn` in `err`, each at its place in the corpus
        (`Repository/dyad/File.dyad:LINE`) or in dyadc's shipped library (`dyadc:...`)."""
        found = []
        for line in err.splitlines():
            match = _LOCATED_WARNING.match(line.strip())
            if match:
                found.append({"place": f"{self.published_path(match['file'])}:{match['line']}",
                              "message": match["message"]})
        return found

    def published_path(self, path: str) -> str:
        resolved = Path(path).resolve()
        for lib in self.libraries:
            sources = lib.sources.resolve()
            if resolved.is_relative_to(sources):
                return f"{lib.root.name}/{lib.sources.relative_to(lib.root) / resolved.relative_to(sources)}" \
                    if lib.sources != lib.root else f"{lib.root.name}/{resolved.relative_to(sources)}"
        marker = "/components/"
        return f"dyadc:components/{path.split(marker, 1)[1]}" if marker in path else path

    # ---------------------------------------------------------------------------- per file

    def measure(self, lib, path: Path) -> dict:
        text = path.read_text(encoding="utf-8", errors="replace")
        defs = corpus_scan.definitions(text)
        rc, _out, _err, error = self.dyadc(["parse", str(path)], "parse")
        parsed = rc == 0
        result = {"file": f"{lib.root.name}/{path.relative_to(lib.root)}",
                  "library": lib.package, "parsed": parsed,
                  "parse_error": "" if parsed else error,
                  "components": [], "runs": [], "not_runnable": []}
        for d in defs:
            if d.kind == "component":
                result["components"].append(self.check(path, d, parsed))
        with tempfile.TemporaryDirectory(dir=self.workdir) as scratch:
            for d in defs:
                if d.kind == "component" and corpus_scan.test_cases(d):
                    result["runs"] += self.test_runs(path, d, parsed, Path(scratch))
                elif d.kind == "analysis" and d.prefix != "partial":
                    self.analysis_run(path, d, defs, parsed, result)
        return result

    def check(self, path: Path, d, parsed: bool) -> dict:
        entry = {"name": d.name, "kind": f"{d.prefix} {d.kind}".strip()}
        if not parsed:
            return {**entry, "verdict": "fail", "reason": "the file does not parse"}
        rc, out, err, error = self.dyadc(["check", f"{path}:{d.name}", *self.lib_args()], "check")
        entry["unit_findings"] = self.unit_findings(err)
        if rc != 0:
            return {**entry, "verdict": "fail", "reason": error}
        status = {line.strip().split(":", 1)[0] for line in out.splitlines()}
        verdict = "external" if "external" in status else "partial" if "partial" in status else "ok"
        # a call with a Julia object dyadc keeps opaque (a medium it cannot build, a dataset)
        opaque = "kept opaque for these checks" in out     # compiler/model/model_check.py
        return {**entry, "verdict": verdict, "reason": "", "julia_objects": opaque}

    # ---------------------------------------------------------------------------- test cases

    def test_runs(self, path: Path, d, parsed: bool, scratch: Path) -> list[dict]:
        cases = corpus_scan.test_cases(d)
        runs = {name: {"name": f"{d.name}.{name}", "kind": "test", "simulated": False,
                       "matched": False, "reason": "the file does not parse", "test_refused": ""}
                for name in cases}
        if not parsed:
            return list(runs.values())
        golden = scratch / f"golden_{d.name}"
        rc, out, err, error = self.dyadc(["test", f"{path}:{d.name}", *self.lib_args(),
                                          "--golden", str(golden), "--accept"], "run")
        verdicts = _case_verdicts(out)
        for index, (name, case) in enumerate(cases.items()):
            verdict = verdicts.get(name)
            if verdict and verdict["compared"]:
                runs[name].update(simulated=True, matched=verdict["passed"],
                                  reason=verdict["detail"])
                continue
            refused = verdict["detail"] if verdict else error
            csv_path = scratch / f"{d.name}_case{index}.csv"
            runs[name].update(self.simulate_case(path, d.name, case, csv_path))
            runs[name]["test_refused"] = refused if runs[name]["simulated"] else ""
            if runs[name]["simulated"] and not runs[name]["matched"] and not runs[name]["reason"]:
                runs[name]["reason"] = refused
        return list(runs.values())

    def simulate_case(self, path: Path, name: str, case: dict, output: Path) -> dict:
        stop = corpus_scan.number(case.get("stop"))
        if stop is None:
            return {"simulated": False, "matched": False,
                    "reason": "the case gives no numeric stop time"}
        expect = case.get("expect", {}) if isinstance(case.get("expect"), dict) else {}
        expected = {"initial": expect.get("initial") or {}, "final": expect.get("final") or {}}
        signals = sorted({s for values in expected.values() for s in values})
        args = ["simulate", f"{path}:{name}", *self.lib_args(), "--stop", repr(stop),
                "--output", str(output)]
        start = corpus_scan.number(case.get("start"))
        if start is not None:
            args += ["--start", repr(start)]
        for key, value in (case.get("initial") or {}).items():
            args += ["-p", f"{key}={value}"]
        if signals:
            args += ["--vars", *signals]
        rc, _out, _err, error = self.dyadc(args, "run")
        if rc != 0:
            return {"simulated": False, "matched": False, "reason": error}
        mismatch = _compare(output, expected, case.get("atol"))
        return {"simulated": True, "matched": mismatch is None, "reason": mismatch or ""}

    # ---------------------------------------------------------------------------- analyses

    def analysis_run(self, path: Path, d, defs: list, parsed: bool, result: dict) -> None:
        spec = corpus_scan.analysis(d)
        if spec.base != "TransientAnalysis":
            result["not_runnable"].append(
                {"name": d.name, "reason": f"analysis kind `{spec.base}`: dyadc runs transient "
                                           f"analyses only"})
            return
        run = {"name": d.name, "kind": "analysis", "simulated": False, "matched": None,
               "reason": "the file does not parse", "test_refused": ""}
        result["runs"].append(run)
        if not parsed:
            return
        if self.has_run_command:
            rc, _out, _err, error = self.dyadc(["run", f"{path}:{d.name}", *self.lib_args()],
                                               "run", cwd=self.workdir)
            run.update(simulated=rc == 0, reason="" if rc == 0 else error)
            return
        if spec.problem:
            run["reason"] = spec.problem
            return
        local = any(x.name == spec.model and x.kind == "component" for x in defs)
        model = f"{path}:{spec.model}" if local else spec.model
        args = ["simulate", model, *self.lib_args(), "--stop", repr(spec.stop), "--points", "101"]
        for key, value in spec.overrides.items():
            if corpus_scan.number(value) is None:
                run["reason"] = (f"the analysis overrides `{key}` with a non-numeric value that "
                                 f"compat.py cannot pass to `dyadc simulate`")
                return
            args += ["-p", f"{key}={value}"]
        rc, _out, _err, error = self.dyadc(args, "run")
        run.update(simulated=rc == 0, reason="" if rc == 0 else error)


_TUBE = re.compile(r"\((?P<when>final|initial) value\): signal (?P<signal>\S+) leaves its tube at t = \S+: "
                   r"got (?P<got>\S+), golden (?P<want>\S+), .* tolerance (?P<tol>\S+)")


def _case_verdicts(out: str) -> dict[str, dict]:
    """Per case of `dyadc test` output: passed, whether values were compared, first detail."""
    verdicts: dict[str, dict] = {}
    current = None
    for line in out.splitlines():
        head = line.split(" ", 2)
        if len(head) >= 2 and head[0] in ("PASS", "FAIL") and not line.startswith(" "):
            current = head[1].rsplit(".", 1)[-1]
            verdicts[current] = {"passed": head[0] == "PASS", "compared": head[0] == "PASS",
                                 "detail": ""}
        elif current and line.startswith("  ") and not line.startswith("  note:"):
            body = line.strip()
            tube = _TUBE.search(body)
            if tube:
                verdicts[current]["compared"] = True
                body = (f"{tube['when']} value of `{tube['signal']}` differs from the published value: "
                        f"got {tube['got']}, published {tube['want']}, tolerance {tube['tol']}")
            if not verdicts[current]["detail"] and body and not body.startswith("signal "):
                verdicts[current]["detail"] = body.removeprefix("error: ")
    return verdicts


def _tolerance(atol, signal: str, value: float) -> float:
    if isinstance(atol, dict):
        atol = atol.get(signal, atol.get("*"))
    given = corpus_scan.number(atol) if atol is not None else None
    return given if given is not None else DEFAULT_TOLERANCE * max(1.0, abs(value))


def _compare(output: Path, expected: dict, atol) -> str | None:
    """None if every expected initial/final value matches the CSV, else the first mismatch."""
    with open(output, newline="") as handle:
        rows = list(csv.reader(handle))
    header, first, last = rows[0], rows[1], rows[-1]
    for when, row in (("initial", first), ("final", last)):
        for signal, raw in expected[when].items():
            want = corpus_scan.number(raw)
            if signal not in header:
                return f"the result has no signal `{signal}`"
            got = float(row[header.index(signal)])
            if want is None:
                return f"expected {when} value of `{signal}` is not a number"
            tolerance = _tolerance(atol, signal, want)
            if not math.isfinite(got) or abs(got - want) > tolerance:
                return (f"{when} value of `{signal}` differs from the published value: "
                        f"got {got:.10g}, published {want:.10g}, tolerance {tolerance:g}")
    return None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("corpus", type=Path)
    parser.add_argument("--output", type=Path, default=Path("docs/compatibility.md"))
    parser.add_argument("--json", type=Path, help="also write the per-file results as JSON")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--render", type=Path, metavar="JSON",
                        help="write the report from the results of an earlier run (its --json "
                             "file) instead of running dyadc")
    options = parser.parse_args(argv)
    corpus = options.corpus.resolve()
    found = corpus_scan.discover_libraries(corpus)
    libraries = [lib for lib in found if corpus_scan.is_openly_licensed(lib)]
    skipped = [lib for lib in found if not corpus_scan.is_openly_licensed(lib)]
    for lib in skipped:
        print(f"skipped {lib.root.name}: license {lib.license!r} is not an open-source license",
              file=sys.stderr)
    if not libraries:
        print(f"error: no .dyad files under {corpus}", file=sys.stderr)
        return 2
    if options.render:
        saved = json.loads(options.render.read_text(encoding="utf-8"))
        results, seconds = saved["results"], saved["seconds"]
        return _write(options, results, libraries, seconds, skipped)
    began = time.perf_counter()
    workdir = Path(tempfile.mkdtemp(prefix="dyadc-compat-"))
    try:
        runner = Runner(libraries, workdir)
        jobs = [(lib, path) for lib in libraries for path in lib.files()]
        results = []
        with ThreadPoolExecutor(max_workers=options.jobs) as pool:
            for i, result in enumerate(pool.map(lambda job: runner.measure(*job), jobs)):
                results.append(result)
                print(f"[{i + 1}/{len(jobs)}] {result['file']}: "
                      f"{'parsed' if result['parsed'] else 'PARSE FAILED'}", flush=True)
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    seconds = time.perf_counter() - began
    if options.json:
        options.json.write_text(json.dumps({"seconds": seconds, "results": results}, indent=1),
                                encoding="utf-8")
    return _write(options, results, libraries, seconds, skipped)


def _write(options, results: list[dict], libraries: list, seconds: float, skipped: list) -> int:
    command = f"make compat CORPUS={options.corpus}"
    report = markdown(results, libraries, command, seconds, TIMEOUTS, skipped)
    options.output.parent.mkdir(parents=True, exist_ok=True)
    options.output.write_text(report, encoding="utf-8")
    print(f"wrote {options.output} ({seconds / 60:.1f} min)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
