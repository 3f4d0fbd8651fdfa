"""Whether a compilation is kept in the cache never depends on what ran before in the process.

A warm process (sympy, lark, CasADi already imported by an earlier compile) starts compiling a
model within a millisecond of the test writing it; a store guarded by the sources' modification
times skipped such a compile, so the second model of a process was compiled again at its next run
(tests/units/test_modes.py after tests/cli/test_units.py). The files here are written just before
they are compiled, on purpose (no back-dating as helpers.write does)."""
from __future__ import annotations

from pathlib import Path

from compiler.pipeline import compile_or_load
from compiler.cache.models import CachedCompilation

HEATED = """\
component Heated
  parameter T0::Temperature = 300
  variable T::Temperature
relations
  T = T0
end
"""

DECAYING = """\
component Decaying
  variable x::Real
relations
  initial x = 1
  der(x) = -x
end
"""


def _written(folder: Path, name: str, text: str) -> str:
    path = folder / f"{name}.dyad"
    path.write_text(text, encoding="utf-8")
    return str(path)


def test_the_second_model_compiled_in_a_warm_process_is_found_in_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("DYADC_CACHE_DIR", str(tmp_path / "cache"))
    first = compile_or_load(_written(tmp_path, "Heated", HEATED))
    assert first.cache_key is not None
    second = compile_or_load(_written(tmp_path, "Decaying", DECAYING))    # right after its write
    assert second.cache_key is not None
    found = compile_or_load(str(tmp_path / "Decaying.dyad"))
    assert isinstance(found, CachedCompilation)
    assert found.key == second.cache_key


def test_the_first_model_is_found_after_another_was_compiled(tmp_path, monkeypatch):
    monkeypatch.setenv("DYADC_CACHE_DIR", str(tmp_path / "cache"))
    first = compile_or_load(_written(tmp_path, "Decaying", DECAYING))
    compile_or_load(_written(tmp_path, "Heated", HEATED))
    found = compile_or_load(str(tmp_path / "Decaying.dyad"))
    assert isinstance(found, CachedCompilation)
    assert found.key == first.cache_key
