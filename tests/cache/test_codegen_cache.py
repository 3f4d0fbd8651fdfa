"""`dyadc simulate` runs a model on compiled C by default, built before the first run and kept in
the compilation cache: every run of a model takes the same path (the same numbers, the first run
as the next), a cached run takes its library through the model's link, and the choice is
reported on the summary line."""
from __future__ import annotations

import stat

import pytest

from compiler.cache import native, store
from compiler.lower import ccodegen
from tests.cache.helpers import dyadc, entries, retried_if_the_compiler_changes, small_library

pytestmark = pytest.mark.skipif(ccodegen.find_compiler() is None, reason="no C compiler")

RUN = ("simulate", "CacheLib.Scaled", "--stop", "1", "--rtol", "1e-10", "--atol", "1e-12",
       "--vars", "y", "d.x")


@retried_if_the_compiler_changes
def test_the_first_run_is_in_c_and_the_next_takes_the_library_from_the_cache(tmp_path, monkeypatch):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    first = dyadc(cache, *RUN, "-L", library)
    assert first.code == 0 and first.compiled and "s in C\n" in first.stderr, first.stderr
    [link] = entries(cache, ".link")
    [so] = sorted((cache / "c").glob("dyad_*.so"))
    assert stat.S_IMODE((cache / "c").stat().st_mode) == 0o700
    assert stat.S_IMODE(so.stat().st_mode) == 0o700
    assert stat.S_IMODE(so.with_suffix(".json").stat().st_mode) == 0o600
    assert stat.S_IMODE(link.stat().st_mode) == 0o600

    second = dyadc(cache, *RUN, "-L", library)
    assert second.code == 0 and "s in C\n" in second.stderr, second.stderr
    assert not second.compiled and second.stdout == first.stdout

    # what the second process did, step by step: the cached model, on its cached library
    monkeypatch.setenv("DYADC_CACHE_DIR", str(cache))
    monkeypatch.delenv("DYADC_CACHE", raising=False)
    from compiler.pipeline import compile_or_load
    compilation = compile_or_load("CacheLib.Scaled", [str(library)], for_runs=True)
    assert not hasattr(compilation, "flat"), "expected the cached compilation"
    assert compilation.model.native_library == str(so) and compilation.model.metadata["codegen"] == "c"


@retried_if_the_compiler_changes
def test_a_damaged_link_or_library_is_built_again_before_the_run(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    first = dyadc(cache, *RUN, "-L", library)
    [link] = entries(cache, ".link")
    link.write_bytes(link.read_bytes()[:-3])
    again = dyadc(cache, *RUN, "-L", library)
    assert again.code == 0 and "s in C\n" in again.stderr and again.stdout == first.stdout, again.stderr
    assert store.read_sealed(link) is not None                  # linked again
    [so] = sorted((cache / "c").glob("dyad_*.so"))
    good = so.read_bytes()
    so.write_bytes(good[: so.stat().st_size // 2])
    third = dyadc(cache, *RUN, "-L", library)
    assert third.code == 0 and "s in C\n" in third.stderr and third.stdout == first.stdout, third.stderr
    assert so.read_bytes() == good                               # rebuilt: builds are reproducible


def test_without_the_cache_the_library_is_built_before_the_run_and_kept_nowhere(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    run = dyadc(cache, *RUN, "-L", library, "--no-cache")
    assert run.code == 0 and "s in C\n" in run.stderr and "unavailable" not in run.stderr, run.stderr
    assert not cache.exists()


@retried_if_the_compiler_changes
def test_the_vm_when_asked_gives_the_numbers_of_c(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    # on CasADi's IDAS, which the VM runs on (the native driver, C's default, gives its own numbers)
    in_c = dyadc(cache, *RUN, "-L", library, "--integrator", "casadi")
    on_vm = dyadc(cache, *RUN, "-L", library, "--codegen", "vm")
    assert on_vm.code == 0 and "s on the VM\n" in on_vm.stderr, on_vm.stderr
    assert not on_vm.compiled and on_vm.stdout == in_c.stdout
    by_variable = dyadc(cache, *RUN, "-L", library, DYADC_CODEGEN="vm")
    assert "s on the VM\n" in by_variable.stderr and by_variable.stdout == in_c.stdout


def test_without_a_c_compiler_the_run_is_on_the_vm_and_says_why(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    run = dyadc(cache, *RUN, "-L", library, PATH="/nonexistent", CC="")
    assert run.code == 0, run.stderr
    assert "s on the VM (no C compiler (gcc, cc or clang) found)\n" in run.stderr
    assert "warning" not in run.stderr                            # the VM is the expected path there
    assert not list((cache / "c").glob("dyad_*.so")) and entries(cache, ".link") == []


def test_a_cached_model_links_every_state_set_library(tmp_path, monkeypatch):
    monkeypatch.setenv("DYADC_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("DYADC_CACHE", raising=False)
    from compiler.pipeline import compile_or_load
    from tests.cache.helpers import ROOT
    spec, lib = "StructureModels.CartesianPendulumHigh", [str(ROOT / "tests" / "structure" / "models")]
    built = compile_or_load(spec, lib, for_runs=True)
    assert built.model.variants and built.model.metadata["codegen"] == "c"
    cached = compile_or_load(spec, lib, for_runs=True)
    assert not hasattr(cached, "flat")
    assert {k: v.native_library for k, v in cached.model.variants.items()} == \
        {k: v.native_library for k, v in built.model.variants.items()}
    assert all(v.metadata["codegen"] == "c" for v in cached.model.variants.values())
    assert native.linked_model(cached.model, cached.key, ccodegen.find_compiler()) is not None


def test_the_choice_comes_from_the_caller_then_the_variable(monkeypatch):
    from compiler.cache.codegen_choice import requested
    monkeypatch.setenv("DYADC_CODEGEN", "VM ")
    assert (requested(), requested("c")) == ("vm", "c")
    monkeypatch.setenv("DYADC_CODEGEN", "fast")
    with pytest.warns(ccodegen.CodegenWarning, match="DYADC_CODEGEN='fast' is neither 'c' nor 'vm'"):
        assert requested() is None
    monkeypatch.delenv("DYADC_CODEGEN")
    assert requested() is None
