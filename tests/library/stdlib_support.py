"""Shared helpers of the standard-library physics tests (tests/library/test_stdlib_*.py): compile
each model of tests/models/Stdlib once per test module and simulate it at tight tolerances, so
that a comparison with a closed form tests the component equations, not the integrator."""
from __future__ import annotations

from pathlib import Path

from compiler.api import compile as compile_model
from compiler.api import simulate_compiled

MODELS = Path(__file__).resolve().parents[1] / "models"
TIGHT = dict(rtol=1e-9, atol=1e-10)


class Compiled:
    """Compiles `Stdlib.<name>` on first use and keeps the compilation for later runs."""

    def __init__(self):
        self._cache = {}

    def run(self, name: str, stop: float, *, points: int = 401, params=None, **options):
        if name not in self._cache:
            self._cache[name] = compile_model(f"Stdlib.{name}", lib_dirs=(str(MODELS),))
        return simulate_compiled(self._cache[name], stop, points=points, params=params,
                                 **{**TIGHT, **options})
