"""Golden-trajectory tests declared in component metadata (`dyadc test`).

A case (see compiler.testing.golden_cases) is simulated at its production tolerance and compared, signal
by signal, with the golden CSV <golden_dir>/<QualifiedModelName>.<case>.csv inside a tube
|y - y_golden| <= atol_s + rtol_s |y_golden|; the "final" values of the metadata are checked at the
stop time within the same per-signal tube. The golden folder is the caller's (`dyadc test --golden
DIR`, default DEFAULT_GOLDEN_DIR under the current directory). Goldens are only ever written by
`accept=True` (`dyadc test --accept`), from a run at GOLDEN_RTOL with absolute tolerances
GOLDEN_RTOL scaled by the unknowns' nominal sizes; a missing golden is otherwise an error. The metadata's "final" values are never written by the tool: they
are statements made (and independently checked) by a person, and an update whose run disagrees
with them is refused.
"""
from __future__ import annotations

import os
import shlex
import time
from typing import Callable, Sequence

from compiler.errors import DyadError
from compiler.testing.golden_cases import TestCase, cases_from_metadata, discover, parse_span_text
from compiler.testing.golden_compare import (CaseReport, compare_finals, compare_initials,
                                             compare_signals, golden_path, read_golden,
                                             signal_values, write_golden)

GOLDEN_RTOL = 1e-10
# A value checked at Dyad's default tube (relative 1.49e-8) needs a reference run whose own error
# is far below it: at rtol 1e-10 a final value of 0.068 (an RLC circuit) was off by 1.9e-9
# (2.8e-8 relative) from an independent Radau run, at 1e-12 by 2e-11.
STRICT_RTOL = 1e-12
DEFAULT_GOLDEN_DIR = os.path.join("tests", "golden")     # relative: to the current directory


def cases_of_compilation(model: str, compilation) -> list[TestCase]:
    metadata = compilation.flat.metadata
    return cases_from_metadata(model, metadata.get("Dyad", {}),
                               parse_span_text(metadata.get("model_span")))


def integrator_atol(compilation, case: TestCase, base: float) -> dict[str, float]:
    """`base` for every unknown (the runtime scales it by start-value nominals), times the case's
    stated nominal size where it gives one."""
    model = compilation.model
    unknowns = set(model.state_names) | set(model.algebraic_names)
    for name in case.nominal:
        if name not in unknowns:
            raise DyadError(f"test case `{case.name}`: nominal given for `{name}`, which is not a "
                            f"state or algebraic unknown of {case.model}", case.span)
    return {"*": base, **{name: base * size for name, size in case.nominal.items()}}


class PendingCompilation:
    """A flattened model, compiled on first use: a case whose "initial" map fixes unknowns
    compiles a variant of its own, so the model is not compiled (and cannot fail) without that
    map unless a case needs it."""

    def __init__(self, flat, timings: dict[str, float]):
        self.flat = flat
        self.timings = timings
        self._compiled = None

    def get(self):
        if self._compiled is None:
            from compiler.pipeline import compile_flat
            self._compiled = compile_flat(self.flat, self.timings)
        return self._compiled


def _simulate(compilation, case: TestCase, rtol: float | None):
    """The case's run: its "initial" map applied (a compilation of its own when it fixes
    unknowns), `rtol` None meaning the golden's tolerance. `compilation` is a Compilation or a
    PendingCompilation."""
    from compiler import api
    from compiler.pipeline import compile_flat
    from compiler.testing.start_values import with_start_values
    rtol = reference_rtol(case) if rtol is None else rtol
    params: dict[str, float] = {}
    flat = compilation.flat
    if case.initial_values:
        flat, params = with_start_values(compilation.flat, case.initial_values,
                                         f"test case `{case.name}`", case.span)
    if flat is not compilation.flat:
        compilation = compile_flat(flat, compilation.timings)
    elif isinstance(compilation, PendingCompilation):
        compilation = compilation.get()
    result = api.simulate_compiled(compilation, case.stop, start=case.start, rtol=rtol,
                                   atol=integrator_atol(compilation, case, rtol), points=case.points,
                                   params=params or None)
    return result, initialization_notes(compilation)


def initialization_notes(compilation) -> list[str]:
    """The note on start values chosen for an under-determined initialization, if any."""
    from compiler.structure.initialization import describe_chosen
    chosen = compilation.reduced.initial.chosen
    return [describe_chosen(chosen)] if chosen else []


def reference_rtol(case: TestCase) -> float:
    """The golden run's tolerance: STRICT_RTOL when an initial or final value is checked at
    Dyad's default tube, else GOLDEN_RTOL."""
    points = set(case.final) | set(case.expect_initial)
    return STRICT_RTOL if points & set(case.default_tube) else GOLDEN_RTOL


def _compared_names(case: TestCase) -> list[str]:
    return list(dict.fromkeys(list(case.signals) + list(case.expect_initial) + list(case.final)))


def accept_command(spec: str, lib_dirs: Sequence[str], golden_dir: str | os.PathLike) -> str:
    """The `dyadc test ... --accept` command that writes the goldens of `spec`, quoted for a POSIX
    shell, with the user's -L folders: it runs as printed."""
    words = ["dyadc", "test", spec, *[w for folder in lib_dirs for w in ("-L", os.fspath(folder))],
             "--golden", os.fspath(golden_dir), "--accept"]
    return " ".join(shlex.quote(word) for word in words)


def run_case(compilation, case: TestCase, golden_dir: str | os.PathLike,
             spec: str | None = None, lib_dirs: Sequence[str] = ()) -> CaseReport:
    """Simulate at the case's tolerance and compare with its golden in `golden_dir`. Never writes
    anything. `spec` and `lib_dirs` are how the user named the model (for the hint on a missing
    golden)."""
    report = CaseReport(case)
    began = time.perf_counter()
    path = golden_path(golden_dir, case)
    try:
        if not os.path.isfile(path):
            raise DyadError(f"no golden file {path}", case.span,
                            hint=f"create it explicitly (after checking the model independently): "
                                 f"{accept_command(spec or case.model, lib_dirs, golden_dir)}")
        golden = read_golden(path)
        result, notes = _simulate(compilation, case, case.rtol)
        report.notes.extend(notes)
    except DyadError as err:
        report.error = err.format()
        report.seconds = time.perf_counter() - began
        return report
    values = signal_values(result, _compared_names(case))
    report.signals, grid_notes = compare_signals(case, result.time, values, golden)
    report.notes.extend(grid_notes)
    report.initials = compare_initials(case, result.time, values)
    report.finals = compare_finals(case, result.time, values)
    report.seconds = time.perf_counter() - began
    return report


def accept_case(compilation, case: TestCase, golden_dir: str | os.PathLike) -> CaseReport:
    """Simulate at reference_rtol(case) and write the golden into `golden_dir` (created if missing),
    unless the run disagrees with the case's "final" values (then nothing is written and the
    report fails)."""
    report = CaseReport(case)
    began = time.perf_counter()
    path = golden_path(golden_dir, case)
    rtol = reference_rtol(case)
    try:
        try:
            result, notes = _simulate(compilation, case, rtol)
        except DyadError as strict:
            if rtol == GOLDEN_RTOL:
                raise
            report.notes.append(f"the run at rtol {rtol:g} failed ({strict.message}); "
                                f"the golden is made at rtol {GOLDEN_RTOL:g}")
            rtol = GOLDEN_RTOL
            result, notes = _simulate(compilation, case, rtol)
        report.notes.extend(notes)
    except DyadError as err:
        report.error = f"golden run at rtol {rtol:g} failed: {err.format()}"
        report.seconds = time.perf_counter() - began
        return report
    run_seconds = time.perf_counter() - began
    missing = [n for n in case.signals if n not in result]
    if missing:
        report.error = (f"golden not written: the model has no signal(s) {', '.join(missing)}")
        report.seconds = run_seconds
        return report
    values = signal_values(result, _compared_names(case))
    report.initials = compare_initials(case, result.time, values)
    report.finals = compare_finals(case, result.time, values)
    if not report.passed:
        report.notes.append(f"golden NOT written to {path}: the golden run disagrees with the "
                            f"metadata's initial or final values")
        report.seconds = run_seconds
        return report
    os.makedirs(golden_dir, exist_ok=True)
    write_golden(path, result.time, {n: result[n] for n in case.signals})
    report.notes.append(f"wrote {path} ({len(case.signals)} signals x {len(result.time)} rows, "
                        f"{os.path.getsize(path) / 1e6:.2f} MB; rtol {rtol:g}, "
                        f"run {run_seconds:.1f} s, {result.stats.get('steps', '?')} steps)")
    report.seconds = time.perf_counter() - began
    return report


def _cases_by_model(lib_dirs: Sequence[str]) -> dict[str, list[TestCase]]:
    """The cases of the libraries the user named (-L, DYADC_PATH), or of the shipped library
    when none is named: a user's goldens live in their folder, the shipped ones in dyadc's."""
    from compiler.model.library import Library
    user_libraries = Library(lib_dirs).user_roots
    by_model: dict[str, list[TestCase]] = {}
    for case in discover(lib_dirs, include_shipped=not user_libraries):
        by_model.setdefault(case.model, []).append(case)
    return by_model


def run_tests(model_spec: str | None, lib_dirs: Sequence[str] = (), *,
              golden_dir: str | os.PathLike = DEFAULT_GOLDEN_DIR, accept: bool = False,
              on_report: Callable[[CaseReport], None] | None = None) -> list[CaseReport]:
    """Run (or with `accept`, write the goldens of) every case of one model, or without a model
    every case of the named libraries (see _cases_by_model). A model named explicitly that fails
    to flatten or declares no cases is an error; during discovery a model that fails to flatten
    fails its cases and the others still run. A model that does not compile fails its cases.
    `on_report` is called with each case's report as soon as it is made."""
    from compiler.pipeline import flatten_spec

    show = on_report or (lambda report: None)
    reports: list[CaseReport] = []
    if model_spec is not None:
        compilation = PendingCompilation(*flatten_spec(model_spec, lib_dirs))
        model = _qualified_name(model_spec, lib_dirs)
        cases = cases_of_compilation(model, compilation)
        if not cases:
            raise DyadError(f'{model} declares no test cases (metadata {{"Dyad": {{"tests": ...}}}})',
                            parse_span_text(compilation.flat.metadata.get("model_span")))
        targets = [(model_spec, compilation, cases)]
    else:
        targets = []
        for model, cases in _cases_by_model(lib_dirs).items():
            try:
                targets.append((model, PendingCompilation(*flatten_spec(model, lib_dirs)),
                                cases))
            except DyadError as err:
                for case in cases:
                    reports.append(CaseReport(case, error=f"cannot compile {model}: {err.format()}"))
                    show(reports[-1])
    for spec, compilation, cases in targets:
        said: set[str] = set()              # a model's notes are printed once, not once per case
        for case in cases:
            if accept:
                report = accept_case(compilation, case, golden_dir)
            else:
                report = run_case(compilation, case, golden_dir, spec, lib_dirs)
            report.notes = [note for note in report.notes if note not in said]
            said.update(report.notes)
            show(report)
            reports.append(report)
    return reports


def _qualified_name(spec: str, lib_dirs: Sequence[str]) -> str:
    from compiler.model.model_spec import load_model
    return load_model(spec, lib_dirs)[2]
