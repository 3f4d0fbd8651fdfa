"""Helpers: write a Dyad source, check its units, read the one finding as the user sees it."""
from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model
from compiler.units.mode import units_mode


class UnitSources:
    def __init__(self, root: Path):
        self.root = root

    def write(self, text: str, name: str = "Model.dyad") -> Path:
        path = self.root / name
        path.write_text(textwrap.dedent(text).lstrip("\n"), encoding="utf-8")
        return path

    def findings(self, text: str):
        """Every finding of the model in `text` (checked under --units warn, so all are listed)."""
        with units_mode("warn"), _quiet():
            flat = flatten_model(str(self.write(text)))
        return flat.unit_findings

    def error(self, text: str) -> str:
        """The rendered error the default mode (--units error) gives for `text`."""
        with pytest.raises(DyadError) as info:
            flatten_model(str(self.write(text)))
        return info.value.format()

    def line_of(self, text: str, marker: str) -> int:
        lines = textwrap.dedent(text).lstrip("\n").splitlines()
        return next(i + 1 for i, line in enumerate(lines) if marker in line)


class _quiet:
    def __enter__(self):
        import warnings
        self.catcher = warnings.catch_warnings()
        self.catcher.__enter__()
        warnings.simplefilter("ignore")

    def __exit__(self, *exc):
        return self.catcher.__exit__(*exc)


@pytest.fixture
def units(tmp_path) -> UnitSources:
    return UnitSources(tmp_path)
