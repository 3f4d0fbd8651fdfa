"""Golden-trajectory test cases declared in component metadata, and where to find them.

A case lives in a component's metadata, the Dyad way:

    metadata {"Dyad": {"tests": {"dig_cycle": {
        "stop": 12, "points": 1201, "rtol": 1e-6,
        "initial": {"c.v": 10},
        "atol": {"a.x": 1e-5, "*": 1e-6}, "signal_rtol": {"a.x": 1e-4},
        "nominal": {"load.m": 100},
        "expect": {"signals": ["a.x"], "initial": {"a.x": 0}, "final": {"a.x": "0.25"}}}}}}

`initial` sets start values (an unknown: its initial condition, replacing the model's own for
it; a parameter: its value), as Dyad's `u0` map does. `atol` / `signal_rtol` are the per-signal
comparison tube (a number, or a dict with an optional "*" default). A signal the case gives no
tolerance for is compared the way Dyad's generated tests compare it, with Julia's `isapprox`
defaults: relative tolerance sqrt(eps) = 1.49e-8 and no absolute part; a stated `atol` alone
makes the tube (Julia's rtol is 0 once atol > 0). `rtol` is the integrator tolerance of the
production run; a case that states none and compares some signal at the default tube runs at
the golden's tolerance (then, like Dyad's snapshots, the check is a reproduction). `nominal` sizes
of unknowns scale the integrator's absolute tolerances (beyond the start-value nominals the
runtime already uses). Numbers may be written as JSON numbers or as strings ("0.31784799"), as
Dyad's libraries do. Malformed cases are DyadErrors located at the case's key in the source.
"""
from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

from compiler.errors import DyadError, Span
from compiler.syntax import ast

DEFAULT_RTOL = 1e-6             # production integrator tolerance when a case states none
DEFAULT_POINTS = 501            # same default as `dyadc simulate`
DEFAULT_SIGNAL_RTOL = 0.0       # the metadata's atol alone makes the tube unless it says more
# Julia's isapprox(x, y) without atol: rtol = sqrt(eps(Float64)), atol = 0. Dyad's generated
# tests compare `sol[x][end] ≈ value` that way when the case gives no atol for x.
DYAD_DEFAULT_RTOL = math.sqrt(2.0 ** -52)
_KNOWN_KEYS = {"stop", "start", "points", "rtol", "atol", "signal_rtol", "nominal", "expect",
               "description", "initial"}
_EXPECT_KEYS = {"signals", "final", "initial"}


@dataclass(frozen=True)
class TestCase:
    model: str                          # qualified name of the component
    name: str
    stop: float
    start: float = 0.0
    points: int = DEFAULT_POINTS
    rtol: float | None = DEFAULT_RTOL   # None: as the golden run (see the module docstring)
    signals: tuple[str, ...] = ()
    atol: dict[str, float] = field(default_factory=dict)         # per signal, "*" resolved
    signal_rtol: dict[str, float] = field(default_factory=dict)  # per signal, "*" resolved
    nominal: dict[str, float] = field(default_factory=dict)
    final: dict[str, float] = field(default_factory=dict)
    span: Span | None = None
    initial_values: dict[str, float] = field(default_factory=dict)   # the case's "initial"
    expect_initial: dict[str, float] = field(default_factory=dict)   # "expect.initial"
    default_tube: tuple[str, ...] = ()      # signals compared at Dyad's default tolerance
    notes: tuple[str, ...] = ()             # what the reader ignored or assumed, for the report

    __test__ = False            # not a pytest class, despite its name

    @property
    def label(self) -> str:
        return f"{self.model}.{self.name}"

    def tube(self, signal: str) -> tuple[float, float]:
        return self.atol[signal], self.signal_rtol[signal]


def parse_span_text(text: str | None) -> Span | None:
    """`file:line:col` (as flattening records the model's span) back into a Span."""
    if not text:
        return None
    match = re.fullmatch(r"(.*):(\d+):(\d+)", text)
    if not match:
        return None
    line, column = int(match.group(2)), int(match.group(3))
    return Span(match.group(1), line, column, line, column)


def case_span(model_span: Span | None, case_name: str) -> Span | None:
    """The span of `"case_name"` in the metadata after the component's header (JSON keeps no
    positions), falling back to the component itself."""
    if model_span is None:
        return None
    try:
        lines = Path(model_span.file).read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return model_span
    key = f'"{case_name}"'
    for number in range(model_span.line, len(lines) + 1):
        column = lines[number - 1].find(key)
        if column >= 0:
            return Span(model_span.file, number, column + 1, number, column + len(key))
    return model_span


def cases_from_metadata(model: str, dyad_metadata: Any, model_span: Span | None) -> list[TestCase]:
    """Every case of `metadata["Dyad"]["tests"]`, validated."""
    if not isinstance(dyad_metadata, dict):
        return []
    tests = dyad_metadata.get("tests")
    if tests is None:
        return []
    if not isinstance(tests, dict):
        raise DyadError(f'metadata "tests" of {model} must be an object of named cases', model_span)
    return [_parse_case(model, name, spec, case_span(model_span, name)) for name, spec in tests.items()]


def _parse_case(model: str, name: str, spec: Any, span: Span | None) -> TestCase:
    where = f"test case `{name}` of {model}"
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise DyadError(f"{where}: a case name must be an identifier (it names the golden file)", span)
    if not isinstance(spec, dict):
        raise DyadError(f"{where} must be a JSON object", span)
    notes = []
    unknown = sorted(set(spec) - _KNOWN_KEYS)
    if unknown:
        # Dyad's test generator ignores keys it does not know; so does dyadc, saying so.
        hints = [f" (did you mean expect.{k}?)" if k in _EXPECT_KEYS else "" for k in unknown]
        notes.append("ignored unknown key(s) " + ", ".join(k + h for k, h in zip(unknown, hints))
                     + " of the case, as Dyad does; known keys: " + ", ".join(sorted(_KNOWN_KEYS)))
    stop, start, points = _time_grid(spec, where, span)
    signals, final, expect_initial = _expectations(spec, where, span)
    if not signals and not final and not expect_initial:
        notes.append("the case expects no values: it checks that the run succeeds (as Dyad's "
                     "generated test does)")
    initial_values = _values(spec.get("initial", {}), f'{where}: "initial"', "initial value", span)
    compared = list(dict.fromkeys(list(signals) + list(final) + list(expect_initial)))
    atol, signal_rtol, defaults = _signal_tolerances(spec, compared, where, span)
    if "rtol" in spec:
        rtol = _positive(spec["rtol"], f'{where}: "rtol" (integrator tolerance)', span)
    else:
        rtol = None if any(signal in defaults for signal in signals) else DEFAULT_RTOL
    nominal = spec.get("nominal", {})
    if not isinstance(nominal, dict):
        raise DyadError(f'{where}: "nominal" must be an object of unknown: size', span)
    nominal = {k: _positive(v, f'{where}: nominal of "{k}"', span) for k, v in nominal.items()}
    return TestCase(model, name, stop, start, points, rtol, tuple(signals), atol, signal_rtol,
                    nominal, final, span, initial_values, expect_initial, defaults, tuple(notes))


def _time_grid(spec: dict, where: str, span: Span | None) -> tuple[float, float, int]:
    """(stop, start, points) of a case."""
    if "stop" not in spec:
        raise DyadError(f'{where} has no "stop" time', span)
    stop = _number(spec["stop"], f'{where}: "stop"', span)
    start = _number(spec.get("start", 0.0), f'{where}: "start"', span)
    if not stop > start:
        raise DyadError(f"{where}: stop {stop} must be greater than start {start}", span)
    points = spec.get("points", DEFAULT_POINTS)
    if not isinstance(points, int) or isinstance(points, bool) or points < 2:
        raise DyadError(f'{where}: "points" must be an integer >= 2', span)
    return stop, start, points


def _expectations(spec: dict, where: str, span: Span | None) -> tuple[list, dict, dict]:
    """(signals compared over time, final values, initial values) of a case's "expect"."""
    expect = spec.get("expect", {})
    if not isinstance(expect, dict):
        raise DyadError(f'{where}: "expect" must be an object', span)
    unknown = sorted(set(expect) - _EXPECT_KEYS)
    if unknown:
        raise DyadError(f'{where}: unknown key(s) expect.{", expect.".join(unknown)}', span,
                        hint="known keys of expect: " + ", ".join(sorted(_EXPECT_KEYS)))
    signals = expect.get("signals", [])
    if not isinstance(signals, list) or not all(isinstance(s, str) for s in signals):
        raise DyadError(f'{where}: "expect.signals" must be a list of signal names', span)
    if len(set(signals)) != len(signals):
        raise DyadError(f'{where}: "expect.signals" names a signal twice', span)
    final = _values(expect.get("final", {}), f'{where}: "expect.final"', "final value", span)
    initial = _values(expect.get("initial", {}), f'{where}: "expect.initial"', "initial value", span)
    return signals, final, initial


def _signal_tolerances(spec: dict, compared: list, where: str, span: Span | None):
    """(atol, rtol of each compared signal, the signals on Dyad's default comparison)."""
    atol = _per_signal(spec.get("atol"), compared, None, f'{where}: "atol"', span)
    defaults = tuple(signal for signal in compared if atol[signal] is None)
    signal_rtol = _per_signal(spec.get("signal_rtol"), compared, None, f'{where}: "signal_rtol"', span)
    for signal in compared:
        if atol[signal] is None:             # Dyad's default comparison (isapprox, no atol)
            atol[signal] = 0.0
            if signal_rtol[signal] is None:
                signal_rtol[signal] = DYAD_DEFAULT_RTOL
        elif signal_rtol[signal] is None:
            signal_rtol[signal] = DEFAULT_SIGNAL_RTOL
    return atol, signal_rtol, defaults


def _values(value: Any, what: str, kind: str, span: Span | None) -> dict[str, float]:
    """An object of name: number (a JSON number or a string holding one)."""
    if not isinstance(value, dict):
        raise DyadError(f"{what} must be an object of name: value", span)
    return {k: _number(v, f'{what}: {kind} of "{k}"', span) for k, v in value.items()}


def _per_signal(value: Any, signals: Sequence[str], default: float | None, what: str,
                span: Span | None) -> dict[str, float | None]:
    """Per compared signal: the stated tolerance, else the "*" one, else `default` (None: not
    stated, the caller applies Dyad's default)."""
    if value is None:
        value = {}
    if not isinstance(value, dict):
        value = {"*": value}
    fallback = value.get("*", default)
    out: dict[str, float | None] = {}
    for signal in signals:
        raw = value.get(signal, fallback)
        out[signal] = None if raw is None else _non_negative(raw, f"{what} of `{signal}`", span)
    stray = sorted(set(value) - set(signals) - {"*"})
    if stray:
        raise DyadError(f"{what} names signal(s) the case does not compare: {', '.join(stray)}", span)
    return out


def _number(value: Any, what: str, span: Span | None) -> float:
    """A JSON number, or a string holding one (Dyad's libraries write both: "0.31784799")."""
    number = None
    if isinstance(value, str):
        try:
            number = float(value.strip())
        except ValueError:
            number = None
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        number = float(value)
    if number is None or not math.isfinite(number):
        raise DyadError(f"{what} must be a finite number (or a string holding one), got {value!r}",
                        span)
    return number


def _positive(value: Any, what: str, span: Span | None) -> float:
    number = _number(value, what, span)
    if number <= 0:
        raise DyadError(f"{what} must be positive, got {value!r}", span)
    return number


def _non_negative(value: Any, what: str, span: Span | None) -> float:
    number = _number(value, what, span)
    if number < 0:
        raise DyadError(f"{what} must not be negative, got {value!r}", span)
    return number


# ------------------------------------------------------------------------------- discovery

def discover(lib_dirs: Sequence[str | os.PathLike] = (), *, include_shipped: bool = True,
             use_env: bool = True) -> list[TestCase]:
    """Every case of every component on the library path: the shipped library (unless
    `include_shipped` is false), the lib dirs and (if `use_env`) the DYADC_PATH folders. Parses
    only files whose text mentions "tests" (a cheap filter; the parse decides)."""
    from compiler.model.library import Library
    from compiler.syntax.parser import parse_file

    library = Library(lib_dirs, use_env=use_env)
    searched = library.roots if include_shipped else library.user_roots
    cases: list[TestCase] = []
    seen: set[Path] = set()
    for root in searched:
        for path in sorted(root.rglob("*.dyad")):
            path = path.resolve()
            if path in seen:
                continue
            seen.add(path)
            try:
                text = path.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                continue
            if '"tests"' not in text:
                continue
            package = library.package_of_file(path) or ""
            for definition in parse_file(str(path)).definitions:
                if not isinstance(definition, ast.ComponentDef):
                    continue
                qualified = f"{package}.{definition.name}" if package else definition.name
                dyad = ast.metadata_dict(definition.metadata).get("Dyad")
                cases.extend(cases_from_metadata(qualified, dyad, definition.span))
    return cases
