"""Issue 32 item 4, events: IDAS steps of the native driver against CasADi's IDAS (both on the
model's C code) on the event tests and the detailed op-amp, with the numbers compared.

The event tests' models and run settings are read from tests/runtime/test_events.py itself (each
test's `model_file(tmp_path, NAME, BODY)` and its first `api.simulate(spec, STOP, ...)`), so the
benchmark runs what the tests run. The detailed op-amp (AmplifierWithOpAmpDetailed, a published
example of ElectricalComponents, clipping a 1 kHz sine of 12 V at +-15 V supplies) needs the
ElectricalComponents and BlockComponents sources of a corpus (`--corpus DIR`, DIR holding
ElectricalComponents/dyad and BlockComponents/dyad); without them it says so.

Same numbers: every signal of the two runs on the same grid, |native - CasADi| at most
AGREEMENT * (atol + rtol * max |signal|), and the same number of events at times within
AGREEMENT * (atol + rtol * t) of each other. Where a signal differs by more, a reference run
(CasADi's IDAS at REFERENCE_TIGHTER times smaller tolerances) decides: the native run's largest
distance from it on that signal is at most REFERENCE_FACTOR times the CasADi run's (both paths
are about as far from the truth: a signal that amplifies a state's error, such as the op-amp's
gain times a state, differs between any two runs at the run's tolerance).
"""
from __future__ import annotations

import ast
import tempfile
import warnings
from pathlib import Path

import numpy as np

import bench_native_idas
from compiler import api
from compiler.runtime.native import make_integrator

ROOT = Path(__file__).resolve().parents[2]
EVENT_TESTS = ROOT / "tests" / "runtime" / "test_events.py"
AGREEMENT = 100.0
REFERENCE_TIGHTER = 1e4
# how much further from the reference the native run may be than CasADi's: two IDAS runs at one
# tolerance with different step sequences scatter by that much (docs/numerics.md, "Tight
# tolerances on both paths": the first step alone moved Andrews' error 20x at rtol 1e-10)
REFERENCE_FACTOR = 10.0
OPAMP = "ElectricalComponents.AmplifierWithOpAmpDetailed"
OPAMP_RUN = {"stop": 0.01, "rtol": 1e-6, "atol": 1e-6, "points": 1001}   # 10 of the test's 100 periods
OPAMP_OUTPUT = "op_amp.outp.v"          # the signal the published test case compares (atol 0.4 V)


def event_test_cases(path: Path = EVENT_TESTS) -> list[dict]:
    """[{"test", "name", "body", "stop", "settings"}] of every test of `path` that writes a model
    with model_file and simulates it with literal arguments (a model written by an f-string, or a
    run with computed arguments, is left out)."""
    cases = []
    for function in ast.parse(path.read_text(encoding="utf-8")).body:
        if not isinstance(function, ast.FunctionDef):
            continue
        calls = [node for node in ast.walk(function) if isinstance(node, ast.Call)]
        written = next((c for c in calls if _called(c) == "model_file"), None)
        run = next((c for c in calls if _called(c) == "api.simulate"), None)
        if written is None or run is None:
            continue
        try:
            settings = {k.arg: ast.literal_eval(k.value) for k in run.keywords}
            cases.append({"test": function.name, "name": ast.literal_eval(written.args[1]),
                          "body": ast.literal_eval(written.args[2]), "stop": ast.literal_eval(run.args[1]),
                          "settings": settings})
        except ValueError:
            continue
    return cases


def _called(call: ast.Call) -> str:
    return ast.unparse(call.func)


def compile_event_case(case: dict, folder: Path):
    path = folder / f"{case['name']}.dyad"
    path.write_text(f"component {case['name']}\n{case['body']}\nend\n", encoding="utf-8")
    return api.compile(str(path))


def opamp_library(corpus: Path, folder: Path) -> list[str] | None:
    """A library folder with the corpus's ElectricalComponents and BlockComponents; None without them."""
    sources = {name: corpus / name / "dyad" for name in ("ElectricalComponents", "BlockComponents")}
    if not all(s.is_dir() for s in sources.values()):
        return None
    for name, source in sources.items():
        (folder / name).symlink_to(source.resolve(), target_is_directory=True)
    return [str(folder)]


def compare(label: str, compilation, stop: float, settings: dict, repeats: int, shown: tuple = ()) -> dict:
    """Both integrators on `compilation`, interleaved; steps, CPU medians, the largest differences
    (and the largest absolute difference of each signal in `shown`)."""
    def run(integrator):
        return lambda: api.simulate_compiled(compilation, stop, progress=False, integrator=integrator, **settings)
    timed = bench_native_idas.cpu_runs({"native": run(make_integrator), "casadi": run("casadi")}, repeats)
    (native_s, native), (casadi_s, casadi) = timed["native"], timed["casadi"]
    rtol, atol = settings.get("rtol", 1e-6), settings.get("atol", 1e-6)
    worst, signal, apart = 0.0, "", []
    for name in casadi.names:
        a, b = np.asarray(native[name], dtype=float), np.asarray(casadi[name], dtype=float)
        share = float(np.max(np.abs(a - b))) / (atol + rtol * float(np.max(np.abs(b))))
        if share > AGREEMENT:
            apart.append(name)
        if share > worst:
            worst, signal = share, name
    events = event_differences(native.events, casadi.events, rtol, atol)
    judged = reference_judgement(compilation, stop, settings, native, casadi, apart) if apart else {}
    signals_agree = not apart or judged["native_no_further"]
    return {**judged,"case": label, "native_steps": native.stats["steps"], "casadi_steps": casadi.stats["steps"],
            "native_time": native_s, "casadi_time": casadi_s, "integrator": native.stats.get("integrator"),
            "native_events": len(native.events), "casadi_events": len(casadi.events),
            "worst": worst, "signal": signal, **events,
            "shown": {name: float(np.max(np.abs(native[name] - casadi[name]))) for name in shown},
            "same": signals_agree and not events["unmatched"] and events["event_share"] <= AGREEMENT}


def reference_judgement(compilation, stop: float, settings: dict, native, casadi, signals: list) -> dict:
    """For each of `signals`, each run's largest distance from a run at REFERENCE_TIGHTER times
    smaller tolerances (CasADi's IDAS) as {signal: (native, CasADi)}; whether the native run is
    nowhere further than REFERENCE_FACTOR times CasADi's, and (for the report) the signal where
    it comes closest to that bound."""
    tight = dict(settings, rtol=settings.get("rtol", 1e-6) / REFERENCE_TIGHTER,
                 atol=settings.get("atol", 1e-6) / REFERENCE_TIGHTER)
    reference = api.simulate_compiled(compilation, stop, progress=False, integrator="casadi", **tight)
    offs = {}
    for name in signals:
        truth = np.asarray(reference[name], dtype=float)
        offs[name] = tuple(float(np.max(np.abs(np.asarray(run[name], dtype=float) - truth)))
                           for run in (native, casadi))
    closest = max(offs, key=lambda name: offs[name][0] / max(offs[name][1], 1e-300))
    return {"judged_signal": closest, "native_off": offs[closest][0], "casadi_off": offs[closest][1],
            "offs": offs, "native_no_further": all(n <= REFERENCE_FACTOR * c for n, c in offs.values())}


def event_differences(native: list, casadi: list, rtol: float, atol: float) -> dict:
    """Events compared label by label, in time order: the largest time difference (as a multiple
    of atol + rtol t) where both runs have the same number of a label's events, and the labels
    whose counts differ ({"unmatched": [(label, native count, CasADi count)]})."""
    share, unmatched = 0.0, []
    for label in sorted({e["event"] for e in native + casadi}):
        a = [e["time"] for e in native if e["event"] == label]
        b = [e["time"] for e in casadi if e["event"] == label]
        if len(a) != len(b):
            unmatched.append((label, len(a), len(b)))
            continue
        share = max([share] + [abs(x - y) / (atol + rtol * abs(y)) for x, y in zip(a, b)])
    return {"event_share": share, "unmatched": unmatched}


def measure(repeats: int, log, corpus: Path | None = None, only: set[str] | None = None) -> dict:
    """{"rows": [compare(...)], "notes": [...]}: the op-amp first, then every event test (those
    whose model is named in `only`, where given)."""
    rows, notes = [], []
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-events-") as scratch, warnings.catch_warnings():
        warnings.simplefilter("ignore")              # the corpus's packages replace the shipped ones
        folder = Path(scratch)
        lib_dirs = opamp_library(corpus, folder) if corpus is not None else None
        if lib_dirs is None:
            notes.append(f"the detailed op-amp was not run: no ElectricalComponents and BlockComponents "
                         f"sources under {corpus} (--corpus DIR)" if corpus else
                         "the detailed op-amp was not run: no corpus given (--corpus DIR)")
        else:
            run = dict(OPAMP_RUN)
            stop = run.pop("stop")
            rows.append(compare(f"{OPAMP}, {stop:g} s, rtol {run['rtol']:g}", api.compile(OPAMP, lib_dirs),
                                stop, run, repeats, shown=(OPAMP_OUTPUT,)))
            log(f"  {rows[-1]['case']}: {rows[-1]['native_steps']} native steps, {rows[-1]['casadi_steps']} CasADi")
        for case in event_test_cases():
            if only is not None and case["name"] not in only:
                continue
            rows.append(compare(case["test"], compile_event_case(case, folder), case["stop"], case["settings"],
                                repeats))
            log(f"  {case['test']}: {rows[-1]['native_steps']} native steps, {rows[-1]['casadi_steps']} CasADi")
    return {"rows": rows, "notes": notes}


def render(data: dict) -> list[str]:
    lines = [f"Same numbers: every signal within {AGREEMENT:g} (atol + rtol max|signal|) of the other "
             "run's, the same number of events, their times within the same multiple of (atol + rtol t); "
             "'differences' gives the largest of each as that multiple.", "",
             "| case | IDAS steps native | CasADi | CPU native | CasADi | events native | CasADi "
             "| differences: signals (worst) | event times (same labels) | same numbers |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in data["rows"]:
        lines.append(f"| {r['case']} | {r['native_steps']} | {r['casadi_steps']} | {r['native_time'] * 1e3:.1f} ms "
                     f"| {r['casadi_time'] * 1e3:.1f} ms | {r['native_events']} | {r['casadi_events']} "
                     f"| {r['worst']:.2g} (`{r['signal']}`) | {r['event_share']:.2g} | {'yes' if r['same'] else 'no'} |")
    lines.append("")
    for r in data["rows"]:
        lines += [f"- {r['case']}: `{label}` {a} times natively, {b} times on CasADi's IDAS"
                  for label, a, b in r["unmatched"]]
        lines += [f"- {r['case']}: `{name}` differs by at most {value:.2g} between the two runs"
                  for name, value in r["shown"].items()]
    return lines + [f"- {note}" for note in data["notes"]] + [""]
