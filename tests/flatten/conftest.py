"""Helpers: write inline Dyad sources to a temp folder and flatten them."""
from __future__ import annotations

import textwrap
from pathlib import Path

import pytest
import sympy

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model


class Sources:
    def __init__(self, root: Path):
        self.root = root

    def write(self, relative: str, text: str) -> Path:
        path = self.root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text).lstrip("\n"), encoding="utf-8")
        return path

    def flatten(self, text: str, name: str | None = None, lib_dirs=()):
        path = self.write("Model.dyad", text)
        return flatten_model(f"{path}:{name}" if name else str(path), list(lib_dirs))

    def error(self, text: str, name: str | None = None, marker: str | None = None,
              lib_dirs=()) -> DyadError:
        """Flatten expecting a DyadError; if `marker` is given, check the error points at the
        line of the source containing it."""
        with pytest.raises(DyadError) as info:
            self.flatten(text, name, lib_dirs)
        err = info.value
        if marker is not None:
            lines = textwrap.dedent(text).lstrip("\n").splitlines()
            expected = next(i + 1 for i, line in enumerate(lines) if marker in line)
            assert err.span is not None, err.format()
            assert err.span.file.endswith("Model.dyad"), err.format()
            assert err.span.line == expected, err.format()
        return err


@pytest.fixture
def sources(tmp_path: Path) -> Sources:
    return Sources(tmp_path)


def residuals(flat) -> set[str]:
    return {str(e.residual) for e in flat.equations}


def solved_single_unknown(flat) -> float:
    """The value of the one unknown of a model with one equation."""
    (equation,) = [e.residual for e in flat.equations]
    (unknown,) = equation.free_symbols
    return float(sympy.solve(equation, unknown)[0])


def parameter_value(flat, name: str) -> float | None:
    for p in flat.parameters:
        if p.name == name:
            return p.value
    raise KeyError(name)
