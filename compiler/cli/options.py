"""Checks of `dyadc simulate` options before any compiling: numbers finite and in range, output
grids of a bounded size, `-p NAME=VALUE[UNIT]` read and converted to the declared unit.

Every refusal is a DyadError (rendered `error: ...`, exit 1); none of these options has a source
location, so the message names the option and the value instead.
"""
from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from compiler.errors import DyadError
from compiler.runtime.options import SHORTEST_SPAN, SMALLEST_TOLERANCE

# Output values (time points x signals) a run may allocate unless the user raises the limit.
DEFAULT_MAX_OUTPUT_VALUES = 10_000_000
MAX_OUTPUT_VALUES_ENV = "DYADC_MAX_OUTPUT_VALUES"

_NUMBER = re.compile(r"\s*([+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|inf(?:inity)?|nan))\s*(.*?)\s*$",
                     re.IGNORECASE)


def max_output_values(option: int | None) -> int:
    """The limit from `--max-output-values`, else $DYADC_MAX_OUTPUT_VALUES, else the default."""
    if option is not None:
        if option < 1:
            raise DyadError(f"--max-output-values must be at least 1, got {option}")
        return option
    from compiler.model.size_limits import positive_integer_setting
    return positive_integer_setting(MAX_OUTPUT_VALUES_ENV, DEFAULT_MAX_OUTPUT_VALUES)


def check_arguments(argv: list[str]) -> None:
    """No argument holds a NUL byte: no file name, name or number can (a shell cannot even pass
    one; a caller of compiler.cli.main can)."""
    for position, argument in enumerate(argv, 1):
        if "\x00" in argument:
            shown = argument.replace("\x00", "\\0")
            raise DyadError(f"argument {position} `{shown[:80]}` contains a NUL byte (\\0), which no "
                            f"file name, model name or value may contain")


# The longest name of one file or folder (bytes) and of a whole path that Linux and macOS accept.
NAME_MAX = 255
PATH_MAX = 4096


def check_path(option: str, path: str) -> None:
    """`path` can name a file at all: no part longer than NAME_MAX bytes, in all at most PATH_MAX
    (else every use of it fails with ENAMETOOLONG)."""
    encoded = path.encode("utf-8", "surrogatepass")
    if len(encoded) >= PATH_MAX:
        raise DyadError(f"{option} `{path[:60]}...` is {len(encoded):,} bytes long, longer than a path "
                        f"may be ({PATH_MAX - 1:,} bytes)")
    for part in encoded.split(b"/"):
        if len(part) > NAME_MAX:
            name = os.fsdecode(part)
            raise DyadError(f"{option} `{path if len(path) <= 80 else path[:60] + '...'}`: the name "
                            f"`{name[:40]}...` is {len(part)} bytes long, longer than a file or folder "
                            f"name may be ({NAME_MAX} bytes)", hint="use a shorter name")


# The arguments of `dyadc` commands that name files or folders, by attribute.
_PATH_OPTIONS = {"file": "FILE", "output": "--output", "plot": "--plot", "events": "--events",
                 "output_dir": "-o", "golden": "--golden", "lib": "-L"}


def check_paths(args) -> None:
    """Every file or folder named on the command line (MODEL too, when it is a path) can exist."""
    for attribute, option in _PATH_OPTIONS.items():
        value = getattr(args, attribute, None)
        for path in (value if isinstance(value, list) else [value]):
            if isinstance(path, str):
                check_path(option, path)
    model = getattr(args, "model", None)
    if isinstance(model, str) and (os.sep in model or ".dyad" in model):
        check_path("MODEL", model.partition(".dyad:")[0] + ".dyad" if ".dyad:" in model else model)


def check_finite(option: str, value: float) -> None:
    if not math.isfinite(value):
        raise DyadError(f"{option} must be a finite number, got {value}")


def check_positive(option: str, value: float) -> None:
    check_finite(option, value)
    if not value > 0:
        raise DyadError(f"{option} must be positive, got {value:g}",
                        hint="tolerances are relative (--rtol) or absolute (--atol) errors, e.g. 1e-6")
    if value < SMALLEST_TOLERANCE:
        raise DyadError(f"{option} {value:g} is below {SMALLEST_TOLERANCE:g}: no solver resolves it",
                        hint="tolerances are relative (--rtol) or absolute (--atol) errors, e.g. 1e-6")


def check_span(start: float, stop: float) -> None:
    check_finite("--start", start)
    check_finite("--stop", stop)
    if not stop > start:
        raise DyadError(f"--stop {stop:g} must be after --start {start:g}")
    if stop - start <= SHORTEST_SPAN * max(1.0, abs(start), abs(stop)):
        raise DyadError(f"the span from --start {start:g} to --stop {stop:g} is shorter than round-off")


def check_output_size(points: int, signals: int, limit: int, what: str) -> None:
    """Refuse a grid of `points` times carrying `signals` columns besides time beyond `limit`."""
    columns = signals + 1
    estimate = points * columns
    if estimate > limit:
        size = f"{points:,} times x {columns} columns" if signals else "before any signal is counted"
        raise DyadError(f"{what} would store {estimate:,} output values ({size}), more than the limit "
                        f"of {limit:,}",
                        hint=f"use fewer output times (--points, a coarser --saveat), fewer signals, or "
                             f"raise the limit with --max-output-values or ${MAX_OUTPUT_VALUES_ENV}")


def chosen_signals(requested, outputs) -> list[str] | None:
    """`--vars`: the signals named, a name with `*` or `?` expanded as a pattern (None: all)."""
    if not requested:
        return None
    from compiler.runtime import ModelInputError, matching_signals
    try:
        return matching_signals(requested, list(outputs))
    except ModelInputError as err:
        raise DyadError(f"--vars: {err}") from None


def overrides_accepted(model, params: Mapping[str, float]) -> bool:
    """Whether the compiled model takes every `-p` override (a tunable parameter, a finite value);
    when not, the run says why (for a structural parameter at its declaration, compiler/api.py)."""
    from compiler.runtime import ModelInputError
    try:
        model.parameter_vector(params)
    except ModelInputError:
        return False
    return True


def check_points(points: int) -> None:
    if points < 2:
        raise DyadError(f"--points must be at least 2, got {points}")


# ---------------------------------------------------------------------------------------- --saveat

@dataclass(frozen=True)
class SaveAt:
    """Output times: a list, a `start:step:stop` range, or (a single number) every `step` from
    --start, with --stop always included. `count()` is known before anything is allocated."""
    text: str
    times: tuple[float, ...] = ()
    first: float = 0.0
    step: float = 0.0
    last: float = 0.0
    every: bool = False          # a single number: every `step` over the whole span

    def count(self) -> int:
        if self.times:
            return len(self.times)
        steps = self._steps()
        short_of_last = self.first + self.step * steps < self.last
        return steps + 1 + int(self.every and short_of_last)

    def _steps(self) -> int:
        # the relative slack keeps a last point that rounding puts a hair beyond `last`
        return int(math.floor((self.last - self.first) / self.step * (1 + 1e-12)))

    def grid(self) -> np.ndarray:
        if self.times:
            return np.array(sorted(set(self.times)), dtype=float)
        times = np.minimum(self.first + self.step * np.arange(self._steps() + 1), self.last)
        if self.every and times[-1] < self.last:
            times = np.append(times, self.last)
        return np.unique(times)


def parse_saveat(text: str, start: float, stop: float) -> SaveAt:
    """`--saveat DT`, `--saveat T1,T2,...` or `--saveat FIRST:STEP:LAST`, checked against the span."""
    if "," in text:
        times = tuple(_saveat_number(part, text) for part in text.split(",") if part.strip())
        if not times:
            raise DyadError(f"--saveat `{text}` lists no times")
        for t in times:
            _inside(t, start, stop, text)
        return SaveAt(text, times=times)
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise DyadError(f"--saveat `{text}` is not a range",
                            hint="write FIRST:STEP:LAST, e.g. --saveat 0:0.1:2 (or a list 0,0.5,2)")
        first, step, last = (_saveat_number(part, text) for part in parts)
        if not step > 0:
            raise DyadError(f"--saveat `{text}`: the step must be positive, got {step:g}")
        if last < first:
            raise DyadError(f"--saveat `{text}`: the range ends ({last:g}) before it begins ({first:g})")
        _inside(first, start, stop, text)
        _inside(last, start, stop, text)
        return SaveAt(text, first=first, step=step, last=last)
    step = _saveat_number(text, text)
    if not step > 0:
        raise DyadError(f"--saveat interval must be positive, got {step:g}")
    return SaveAt(text, first=start, step=step, last=stop, every=True)


def _saveat_number(part: str, text: str) -> float:
    try:
        value = float(part)
    except ValueError:
        raise DyadError(f"--saveat `{text}`: `{part.strip()}` is not a number",
                        hint="--saveat DT (every DT), --saveat 0,0.5,1.25 (a list) or "
                             "--saveat 0:0.25:2 (FIRST:STEP:LAST)") from None
    if not math.isfinite(value):
        raise DyadError(f"--saveat `{text}`: {value} is not a finite time")
    return value


def _inside(t: float, start: float, stop: float, text: str) -> None:
    if not start <= t <= stop:
        raise DyadError(f"--saveat `{text}`: time {t:g} lies outside the simulated span "
                        f"[{start:g}, {stop:g}]")


# --------------------------------------------------------------------------------------------- -p

@dataclass(frozen=True)
class Override:
    """`-p NAME=VALUE[UNIT]` as typed: the unit (or None) is converted once units are known."""
    name: str
    value: float
    unit: str | None
    text: str


def parse_override(text: str) -> Override:
    name, sep, value = text.partition("=")
    if not sep or not name.strip():
        raise DyadError(f"bad parameter override `{text}`", hint="write -p NAME=VALUE, e.g. -p boom.m=200")
    match = _NUMBER.fullmatch(value)
    if match is None or not value.strip():
        raise DyadError(f"bad parameter override `{text}`: `{value}` is not a number",
                        hint="write -p NAME=VALUE or -p NAME=VALUE UNIT, e.g. -p L=0.1 or -p L=100mm")
    number = float(match.group(1))
    if not math.isfinite(number):
        raise DyadError(f"parameter override `{text}`: the value must be a finite number, got {number}")
    unit = match.group(2) or None
    if unit is not None:
        from compiler.units.system import UnitError, is_offset_unit, parse_unit
        try:
            if not is_offset_unit(unit):
                parse_unit(unit)       # readable now; whether it fits the parameter is known after flattening
        except UnitError as err:
            raise DyadError(f"-p {text}: {err}", hint="units are written as in the library, e.g. mm, kN/m, "
                                                      "kg.m2, m/s2, 1/min (docs/cli.md)") from None
    return Override(name.strip(), number, unit, text)


def convert_overrides(overrides: list[Override], parameters: Mapping[str, float],
                      declared: Mapping[str, str]) -> dict[str, float]:
    """NAME -> value in the declared unit of NAME. A name that is no parameter keeps its value so
    that the runtime's unknown-parameter error (with its did-you-mean) reports it."""
    from compiler.units.system import UnitError, convert_value, describe_kind

    values: dict[str, float] = {}
    for override in overrides:
        value = override.value
        unit = declared.get(override.name)
        if override.unit is not None and override.name in parameters and override.unit != unit:
            if not unit:
                raise DyadError(f"parameter '{override.name}' declares no unit, so `{override.text}` "
                                f"cannot be converted", hint=f"give a plain number: -p {override.name}="
                                                             f"{override.value:g}")
            try:
                describe_kind(unit)
            except UnitError as err:
                raise DyadError(f"parameter '{override.name}' declares the unit `{unit}`, which dyadc "
                                f"cannot read ({err})", hint="give a plain number in that unit") from None
            try:
                value = convert_value(override.value, override.unit, unit)
            except UnitError:
                raise DyadError(f"-p {override.text}: parameter '{override.name}' is declared in `{unit}` "
                                f"({describe_kind(unit)}), and the given unit `{override.unit}` "
                                f"({describe_kind(override.unit)}) does not convert to it",
                                hint=f"give the value in `{unit}` or a unit of the same kind") from None
        values[override.name] = value
    return values
