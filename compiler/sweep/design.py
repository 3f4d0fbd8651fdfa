"""What a sweep runs: the parameter values of every sample (a grid, or random / Latin-hypercube draws).

An axis is written after `NAME=` on the command line (and accepted as text from Python too):
  `1e5:1e6:10`        10 values from 1e5 to 1e6 (both included): a grid axis
  `[800, 1200]`       the listed values: a grid axis; with --samples, one of them drawn uniformly
  `1e5:1e6`           a range: with --samples, drawn uniformly in it
  `uniform(a, b)`, `loguniform(a, b)`, `normal(mean, std)`: distributions for --samples
  `3.5`               a fixed value for every sample (not a swept column)
A grid is the product of its axes (the first axis varies slowest). Samples draw every axis at once
from a unit hypercube, by plain random numbers or by Latin-hypercube sampling (scipy.stats.qmc).
"""
from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from compiler.errors import DyadError

DISTRIBUTIONS = ("uniform", "loguniform", "normal")
METHODS = ("lhs", "random")


@dataclass(frozen=True)
class Axis:
    """One parameter's values: `values` for a grid or list axis, or a distribution `kind(a, b)`."""
    name: str
    kind: str                          # 'values' | 'fixed' | 'uniform' | 'loguniform' | 'normal'
    values: tuple[float, ...] = ()
    a: float = math.nan
    b: float = math.nan

    @property
    def is_grid(self) -> bool:
        return self.kind == "values"


@dataclass(frozen=True)
class Design:
    """The samples of a sweep: `values[i, j]` is parameter `names[j]` in sample i. `fixed` holds
    overrides shared by every sample."""
    names: tuple[str, ...]
    values: np.ndarray
    method: str = "grid"               # 'grid' | 'lhs' | 'random' | 'list'
    fixed: Mapping[str, float] = field(default_factory=dict)
    seed: int | None = None

    def __len__(self) -> int:
        return int(self.values.shape[0])

    def sample(self, i: int) -> dict[str, float]:
        point = dict(self.fixed)
        point.update({n: float(v) for n, v in zip(self.names, self.values[i])})
        return point


# ------------------------------------------------------------------------------------------ parsing

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_CALL = re.compile(rf"^(\w+)\(\s*({_NUMBER})\s*,\s*({_NUMBER})\s*\)$")


def parse_assignment(text: str) -> Axis:
    """`NAME=SPEC` as given to `-p`."""
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise DyadError(f"bad sweep parameter `{text}`",
                        hint="write -p NAME=START:STOP:COUNT, -p NAME=[V1,V2], or -p NAME=VALUE")
    return parse_axis(name, spec)


def parse_axis(name: str, spec: str | float | Sequence[float] | Axis) -> Axis:
    if isinstance(spec, Axis):
        return spec
    if isinstance(spec, (int, float)) and not isinstance(spec, bool):
        return Axis(name, "fixed", (float(spec),))
    if not isinstance(spec, str):
        values = tuple(_number(name, v) for v in spec)
        if not values:
            raise DyadError(f"sweep parameter `{name}` has an empty list of values")
        return Axis(name, "values", values)
    text = spec.strip()
    if text.startswith("[") and text.endswith("]"):
        items = [t for t in (s.strip() for s in text[1:-1].split(",")) if t]
        return parse_axis(name, [_number(name, t) for t in items])
    call = _CALL.match(text.replace(" ", ""))
    if call:
        kind, a, b = call.group(1).lower(), float(call.group(2)), float(call.group(3))
        if kind not in DISTRIBUTIONS:
            raise DyadError(f"sweep parameter `{name}`: unknown distribution `{call.group(1)}`",
                            hint=f"use one of {', '.join(DISTRIBUTIONS)}")
        return _distribution(name, kind, a, b)
    if ":" in text:
        parts = [p.strip() for p in text.split(":")]
        if len(parts) == 2:
            return _distribution(name, "uniform", _number(name, parts[0]), _number(name, parts[1]))
        if len(parts) == 3:
            start, stop = _number(name, parts[0]), _number(name, parts[1])
            count = _count(name, parts[2])
            return Axis(name, "values", tuple(float(v) for v in np.linspace(start, stop, count)))
        raise DyadError(f"sweep parameter `{name}`: `{text}` has {len(parts) - 1} colons",
                        hint="write START:STOP:COUNT for a grid axis or START:STOP for a range")
    return Axis(name, "fixed", (_number(name, text),))


def _distribution(name: str, kind: str, a: float, b: float) -> Axis:
    if kind == "normal":
        if not b > 0:
            raise DyadError(f"sweep parameter `{name}`: normal({a:g}, {b:g}) needs a positive "
                            "standard deviation")
    elif not b > a:
        raise DyadError(f"sweep parameter `{name}`: the range {a:g} .. {b:g} is empty",
                        hint="write the lower bound first")
    elif kind == "loguniform" and not a > 0:
        raise DyadError(f"sweep parameter `{name}`: loguniform({a:g}, {b:g}) needs positive bounds")
    return Axis(name, kind, (), a, b)


def _number(name: str, text) -> float:
    try:
        value = float(text)
    except (TypeError, ValueError):
        raise DyadError(f"sweep parameter `{name}`: `{text}` is not a number") from None
    if not math.isfinite(value):
        raise DyadError(f"sweep parameter `{name}`: `{text}` is not a finite number")
    return value


def _count(name: str, text: str) -> int:
    try:
        count = int(text)
    except ValueError:
        raise DyadError(f"sweep parameter `{name}`: the count `{text}` is not a whole number",
                        hint="START:STOP:COUNT, e.g. 1e5:1e6:10") from None
    if count < 1:
        raise DyadError(f"sweep parameter `{name}`: the count must be at least 1, got {count}")
    return count


# ------------------------------------------------------------------------------------------ designs

def _split(axes: Sequence[Axis]) -> tuple[list[Axis], dict[str, float]]:
    seen: set[str] = set()
    for axis in axes:
        if axis.name in seen:
            raise DyadError(f"sweep parameter `{axis.name}` is given twice")
        seen.add(axis.name)
    return ([a for a in axes if a.kind != "fixed"],
            {a.name: a.values[0] for a in axes if a.kind == "fixed"})


def grid_design(axes: Sequence[Axis]) -> Design:
    swept, fixed = _split(axes)
    ranges = [a for a in swept if not a.is_grid]
    if ranges:
        raise DyadError(f"sweep parameter `{ranges[0].name}` is a range or distribution, which "
                        "needs --samples N", hint="give a grid axis START:STOP:COUNT or [V1,V2], "
                        "or draw N samples with --samples N")
    if not swept:
        raise DyadError("nothing to sweep: give at least one parameter with several values",
                        hint="-p NAME=START:STOP:COUNT or -p NAME=[V1,V2]")
    values = np.array(list(itertools.product(*(a.values for a in swept))), dtype=float)
    return Design(tuple(a.name for a in swept), values.reshape(-1, len(swept)), "grid", fixed)


def sampled_design(axes: Sequence[Axis], count: int, method: str = "lhs",
                   seed: int | None = None) -> Design:
    swept, fixed = _split(axes)
    if method not in METHODS:
        raise DyadError(f"unknown sampling method `{method}`", hint=f"use one of {', '.join(METHODS)}")
    if count < 1:
        raise DyadError(f"--samples must be at least 1, got {count}")
    if not swept:
        raise DyadError("nothing to sample: give at least one range, list or distribution",
                        hint="-p NAME=LOW:HIGH, -p NAME=normal(MEAN,STD) or -p NAME=[V1,V2]")
    unit = unit_hypercube(count, len(swept), method, seed)
    columns = [_transform(axis, unit[:, j]) for j, axis in enumerate(swept)]
    return Design(tuple(a.name for a in swept), np.column_stack(columns), method, fixed, seed)


def unit_hypercube(count: int, dims: int, method: str, seed: int | None) -> np.ndarray:
    """`count` points in [0, 1)^dims; reproducible for a given seed."""
    rng = np.random.default_rng(seed)
    if method == "random":
        return rng.random((count, dims))
    from scipy.stats import qmc
    try:
        sampler = qmc.LatinHypercube(d=dims, rng=rng)
    except TypeError:                           # scipy < 1.15 calls it seed
        sampler = qmc.LatinHypercube(d=dims, seed=rng)
    return sampler.random(count)


def _transform(axis: Axis, u: np.ndarray) -> np.ndarray:
    # the ends of [0, 1) would be infinite for a normal distribution
    u = np.clip(u, 1e-12, 1.0 - 1e-12)
    if axis.kind == "values":
        index = np.minimum((u * len(axis.values)).astype(int), len(axis.values) - 1)
        return np.asarray(axis.values, dtype=float)[index]
    if axis.kind == "uniform":
        return axis.a + (axis.b - axis.a) * u
    if axis.kind == "loguniform":
        return np.exp(math.log(axis.a) + (math.log(axis.b) - math.log(axis.a)) * u)
    from scipy.stats import norm
    return norm.ppf(u, loc=axis.a, scale=axis.b)


def explicit_design(samples: Sequence[Mapping[str, float]]) -> Design:
    """Samples given one by one (a list of {name: value}); every sample names the same parameters."""
    if not samples:
        raise DyadError("nothing to sweep: the list of samples is empty")
    names = tuple(samples[0])
    for i, point in enumerate(samples):
        if set(point) != set(names):
            raise DyadError(f"sample {i} sets {sorted(point)}, sample 0 sets {sorted(names)}",
                            hint="every sample must set the same parameters")
    values = np.array([[_number(n, point[n]) for n in names] for point in samples], dtype=float)
    return Design(names, values.reshape(len(samples), len(names)), "list", {})


def as_design(spec, samples: int | None = None, method: str = "lhs", seed: int | None = None) -> Design:
    """What the Python API accepts: a Design, a list of {name: value} samples, or a mapping
    name -> axis (a list of values, an Axis, or axis text as on the command line), which is a grid
    unless `samples` is given."""
    if isinstance(spec, Design):
        return spec
    if isinstance(spec, Mapping):
        axes = [parse_axis(name, value) for name, value in spec.items()]
        return sampled_design(axes, samples, method, seed) if samples else grid_design(axes)
    if isinstance(spec, Sequence) and not isinstance(spec, str) and all(isinstance(s, Axis) for s in spec):
        return sampled_design(spec, samples, method, seed) if samples else grid_design(spec)
    if isinstance(spec, Sequence) and not isinstance(spec, str):
        return explicit_design(list(spec))
    raise DyadError(f"cannot make sweep samples from a {type(spec).__name__}",
                    hint="pass {name: [values]} for a grid, a list of {name: value} samples, or a Design")
