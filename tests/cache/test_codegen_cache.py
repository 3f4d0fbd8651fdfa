"""`dyadc simulate --codegen c` with the compilation cache: the first run starts on the virtual
machine while a second process builds the C library; the next run takes the library from the
cache and runs in C with the same results."""
from __future__ import annotations

import stat

import pytest

from compiler.cache import native, store
from compiler.lower import ccodegen
from tests.cache.helpers import dyadc, entries, retried_if_the_compiler_changes, small_library

pytestmark = pytest.mark.skipif(ccodegen.find_compiler() is None, reason="no C compiler")

RUN = ("simulate", "CacheLib.Scaled", "--stop", "1", "--rtol", "1e-10", "--atol", "1e-12",
       "--vars", "y", "d.x", "--codegen", "c")
BUILT = "built the model's C library in the background"


@retried_if_the_compiler_changes
def test_the_first_run_builds_in_the_background_and_the_next_runs_in_c(tmp_path, monkeypatch):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    first = dyadc(cache, *RUN, "-L", library)
    assert first.code == 0 and BUILT in first.stderr and "unavailable" not in first.stderr, first.stderr
    [link] = entries(cache, ".link")
    [so] = sorted((cache / "c").glob("dyad_*.so"))
    assert stat.S_IMODE((cache / "c").stat().st_mode) == 0o700
    assert stat.S_IMODE(so.stat().st_mode) == 0o700
    assert stat.S_IMODE(so.with_suffix(".json").stat().st_mode) == 0o600
    assert stat.S_IMODE(link.stat().st_mode) == 0o600

    second = dyadc(cache, *RUN, "-L", library)
    assert second.code == 0 and BUILT not in second.stderr, second.stderr
    assert not second.compiled and second.stdout == first.stdout

    # what the second process did, step by step: the cached model, its cached library
    monkeypatch.setenv("DYADC_CACHE_DIR", str(cache))
    monkeypatch.delenv("DYADC_CACHE", raising=False)
    from compiler.pipeline import compile_or_load
    compilation = compile_or_load("CacheLib.Scaled", [str(library)])
    assert not hasattr(compilation, "flat"), "expected the cached compilation"
    assert native.use_c_code(compilation) is None
    assert compilation.model.native_library == str(so) and compilation.model.metadata["codegen"] == "c"


@retried_if_the_compiler_changes
def test_a_damaged_link_or_library_is_built_again(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    first = dyadc(cache, *RUN, "-L", library)
    [link] = entries(cache, ".link")
    link.write_bytes(link.read_bytes()[:-3])
    again = dyadc(cache, *RUN, "-L", library)
    assert again.code == 0 and BUILT in again.stderr and again.stdout == first.stdout, again.stderr
    assert store.read_sealed(link) is not None
    [so] = sorted((cache / "c").glob("dyad_*.so"))
    so.write_bytes(so.read_bytes()[: so.stat().st_size // 2])
    third = dyadc(cache, *RUN, "-L", library)
    assert third.code == 0 and BUILT in third.stderr and third.stdout == first.stdout, third.stderr


def test_without_the_cache_the_library_is_built_before_the_run(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    run = dyadc(cache, *RUN, "-L", library, "--no-cache")
    assert run.code == 0 and BUILT not in run.stderr and "unavailable" not in run.stderr, run.stderr
    assert not (cache / "models").exists()
