"""The compilation cache (issue 15 item 4, docs/cache.md): a second `dyadc simulate` of an unchanged
model in a new process reuses the compiled model without importing sympy or lark and gives the
same results; any edited source, a damaged entry or a concurrent compile never gives a wrong or
failed run. Every run is a fresh process with its own cache folder under tmp_path."""
from __future__ import annotations

import math
import os
import stat
import subprocess
import time

import pytest

from compiler.cache import store
from tests.cache.helpers import (EXCAVATOR, ROOT, command, dyadc, entries, environment,
                                 retried_if_the_compiler_changes, small_library, write)

SCALED_RUN = ("simulate", "CacheLib.Scaled", "--stop", "1", "--rtol", "1e-10", "--atol", "1e-12",
              "--vars", "y", "d.x")


def scaled(cache, library, *extra, **env):
    return dyadc(cache, *SCALED_RUN, "-L", library, *extra, **env)


@retried_if_the_compiler_changes
def test_a_hit_gives_the_excavator_of_a_miss_without_importing_sympy_or_lark(tmp_path):
    cache = tmp_path / "cache"
    run = ("simulate", EXCAVATOR, "--stop", "0.5", "--points", "51")
    first = dyadc(cache, *run, "--output", tmp_path / "first.csv")
    second = dyadc(cache, *run, "--output", tmp_path / "second.csv")
    assert first.code == 0 and second.code == 0, first.stderr + second.stderr
    assert first.compiled            # lark too, unless every file read has a tree made at install
    assert second.imported == [], f"a cache hit imported {second.imported}"
    assert (tmp_path / "second.csv").read_bytes() == (tmp_path / "first.csv").read_bytes()
    uncached = dyadc(cache, *run, "--output", tmp_path / "uncached.csv", "--no-cache")
    assert uncached.compiled
    assert (tmp_path / "uncached.csv").read_bytes() == (tmp_path / "first.csv").read_bytes()


@retried_if_the_compiler_changes
def test_an_edited_library_file_is_compiled_again(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    before = scaled(cache, library)
    assert before.code == 0 and before.compiled, before.stderr
    assert before.final("d.x") == pytest.approx(math.exp(-2.0), rel=1e-8)
    write(library / "CacheLib" / "Decay.dyad", (library / "CacheLib" / "Decay.dyad").read_text()
          .replace("k::Real = 2.0", "k::Real = 3.0"))
    after = scaled(cache, library)
    assert after.code == 0 and after.compiled
    assert after.final("d.x") == pytest.approx(math.exp(-3.0), rel=1e-8)
    again = scaled(cache, library)
    assert not again.compiled and again.stdout == after.stdout
    assert len(entries(cache)) == 2           # both versions are kept: reverting is a hit


def test_an_edited_function_plugin_is_compiled_again(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    before = scaled(cache, library)
    plugin = library / "CacheLib" / "dyad_functions.py"
    write(plugin, plugin.read_text().replace("3 * x", "4 * x"))
    after = scaled(cache, library)
    assert before.code == after.code == 0 and after.compiled
    assert after.final("y") == pytest.approx(4 / 3 * before.final("y"), rel=1e-9)    # 10 digits printed


def test_a_file_added_where_the_library_looked_is_compiled_again(tmp_path):
    """-L first -L second: package CacheLib comes from `second` until `first` holds one (a package
    is found in one folder, so `first`'s CacheLib then provides all of it)."""
    cache, second = tmp_path / "cache", small_library(tmp_path / "second")
    first = tmp_path / "first"
    first.mkdir()
    run = ("-L", first, "-L", second)
    before = dyadc(cache, *SCALED_RUN, *run)
    small_library(first)
    write(first / "CacheLib" / "Decay.dyad", (second / "CacheLib" / "Decay.dyad").read_text()
          .replace("k::Real = 2.0", "k::Real = 0.5"))
    after = dyadc(cache, *SCALED_RUN, *run)
    assert before.code == after.code == 0 and after.compiled
    assert before.final("d.x") == pytest.approx(math.exp(-2.0), rel=1e-8)
    assert after.final("d.x") == pytest.approx(math.exp(-0.5), rel=1e-8)


def test_a_subpackage_added_beside_an_alias_is_compiled_again(tmp_path):
    """`Lib.Decay` resolves as the flat alias of `Lib.Fast.Decay`; once a second subpackage also
    defines `Decay`, the flat path is ambiguous: the cached compile is not reused, the run fails."""
    cache, library = tmp_path / "cache", tmp_path / "lib"
    decay = """
        component Decay
          parameter k::Real = 2.0
          variable x::Real
        relations
          initial x = 1
          der(x) = -k * x
        end
        """
    write(library / "Lib" / "Fast" / "Decay.dyad", decay)
    write(library / "Use" / "Use.dyad", """
        component Use
          d = Lib.Decay()
        end
        """)
    spec = ("simulate", "Use.Use", "--stop", "1", "--vars", "d.x", "-L", library)
    before = dyadc(cache, *spec)
    assert before.code == 0, before.stderr
    assert before.final("d.x") == pytest.approx(math.exp(-2.0), rel=1e-4)
    write(library / "Lib" / "Slow" / "Decay.dyad", decay.replace("2.0", "0.5"))
    after = dyadc(cache, *spec)
    assert after.code != 0
    assert "`Lib.Decay` is defined in more than one subpackage of `Lib`" in after.stderr


def test_a_package_that_replaces_a_shipped_one_is_compiled_again(tmp_path):
    """A model compiled with the shipped TranslationalComponents is not served from the cache once
    a folder on its path holds a TranslationalComponents of the user's (which replaces it)."""
    cache, library = tmp_path / "cache", tmp_path / "lib"
    write(library / "Pushed" / "Pushed.dyad", """
        component Pushed
          anchor = TranslationalComponents.Fixed(s0 = 2)
          variable x::Real
        relations
          initial x = 0
          der(x) = anchor.flange.s
        end
        """)
    spec = ("simulate", "Pushed.Pushed", "--stop", "1", "--vars", "x", "-L", library)
    before = dyadc(cache, *spec)
    write(library / "TranslationalComponents" / "Fixed.dyad", """
        component Fixed
          flange = Flange()
          parameter s0::Position = 0
        relations
          flange.s = 3 * s0
        end
        """)
    after = dyadc(cache, *spec)
    assert before.code == after.code == 0 and after.compiled, after.stderr
    assert before.final("x") == pytest.approx(2.0, rel=1e-6)
    assert after.final("x") == pytest.approx(6.0, rel=1e-6)
    assert "note: package `TranslationalComponents` from" in after.stderr


def _truncate(path):
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _flip_bytes(path):                        # same size, different bytes in the middle
    data = bytearray(path.read_bytes())
    middle = len(data) // 2
    data[middle:middle + 16] = bytes(b ^ 0x5A for b in data[middle:middle + 16])
    path.write_bytes(bytes(data))


def _empty(path):
    path.write_bytes(b"")


@pytest.mark.parametrize("suffix", [".model", ".manifest"])
@pytest.mark.parametrize("damage", [_truncate, _flip_bytes, _empty], ids=["truncated", "flipped", "empty"])
@retried_if_the_compiler_changes
def test_a_damaged_entry_is_rebuilt_without_an_error(tmp_path, damage, suffix):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    first = scaled(cache, library)
    [path] = entries(cache, suffix)
    good = path.read_bytes()
    damage(path)
    rebuilt = scaled(cache, library)
    assert rebuilt.code == 0 and rebuilt.stderr.count("error") == 0, rebuilt.stderr
    assert rebuilt.compiled and rebuilt.stdout == first.stdout
    assert store.read_sealed(path) is not None
    assert len(path.read_bytes()) == len(good)
    hit = scaled(cache, library)
    assert not hit.compiled and hit.stdout == first.stdout


@retried_if_the_compiler_changes
def test_two_processes_compiling_at_once_both_succeed(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    env = environment(cache)
    runs = [subprocess.Popen(command(tmp_path / f"imports{i}.json", *SCALED_RUN, "-L", library), cwd=ROOT,
                             env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            for i in range(2)]
    outputs = [run.communicate(timeout=600) for run in runs]
    assert [run.returncode for run in runs] == [0, 0], [err for _, err in outputs]
    assert outputs[0][0] == outputs[1][0]
    [entry] = entries(cache)
    assert store.read_sealed(entry) is not None
    assert not list((cache / "models").glob(".*tmp*"))        # no temporary file left behind
    hit = scaled(cache, library)
    assert not hit.compiled and hit.stdout == outputs[0][0]


@pytest.mark.skipif(not hasattr(os, "getuid"), reason="POSIX permissions")
def test_the_cache_is_private(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    assert scaled(cache, library).code == 0
    for folder in (cache, cache / "models"):
        assert stat.S_IMODE(folder.stat().st_mode) == 0o700, folder
    files = list((cache / "models").iterdir())
    assert files and all(stat.S_IMODE(p.stat().st_mode) == 0o600 for p in files)


def test_a_shared_cache_folder_is_made_private_and_one_of_another_user_refused(tmp_path, monkeypatch):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)
    assert stat.S_IMODE(store.private_folder(shared).stat().st_mode) == 0o700
    monkeypatch.setattr(store.os, "getuid", lambda: shared.stat().st_uid + 1)
    with pytest.raises(store.CacheError, match="belongs to another user"):
        store.private_folder(shared)


@retried_if_the_compiler_changes
def test_no_cache_and_cache_off_read_and_write_nothing(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    assert scaled(cache, library, "--no-cache").code == 0
    assert not cache.exists()
    off = scaled("off", library, log=tmp_path / "imports.json")
    assert off.code == 0 and off.compiled
    assert scaled(cache, library).code == 0                  # fills the cache ...
    again = scaled(cache, library, "--no-cache")             # ... which --no-cache does not read
    assert again.code == 0 and again.compiled


@retried_if_the_compiler_changes
def test_cache_info_and_clear(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    assert scaled(cache, library).code == 0
    info = dyadc(cache, "cache", "info")
    assert info.code == 0 and str(cache) in info.stdout and "compiled models: 1 " in info.stdout
    cleared = dyadc(cache, "cache", "clear")
    assert cleared.code == 0 and entries(cache) == []
    assert scaled(cache, library).compiled
    off = dyadc("off", "cache", "info", log=tmp_path / "imports.json")
    assert off.code == 0 and "off" in off.stdout


@retried_if_the_compiler_changes
def test_a_missing_parameter_value_is_the_same_located_error_from_a_hit(tmp_path):
    cache, library = tmp_path / "cache", small_library(tmp_path / "lib")
    decay = library / "CacheLib" / "Decay.dyad"
    write(decay, decay.read_text().replace("k::Real = 2.0", "k::Real"))
    given = scaled(cache, library, "-p", "d.k=2")
    assert given.code == 0, given.stderr
    from_cache = scaled(cache, library)
    from_source = scaled(cache, library, "--no-cache")
    assert from_cache.code == from_source.code == 1
    assert "has no value" in from_cache.stderr and "Decay.dyad:2:" in from_cache.stderr
    assert from_cache.stderr == from_source.stderr


def test_the_python_api_uses_the_cache_when_asked(tmp_path, monkeypatch):
    import numpy as np

    from compiler.api import simulate
    monkeypatch.setenv("DYADC_CACHE_DIR", str(tmp_path / "cache"))
    library = small_library(tmp_path / "lib")
    runs = [simulate("CacheLib.Scaled", 1.0, lib_dirs=[str(library)], points=11, cache=True)
            for _ in range(2)]
    assert "cache" not in runs[0].stats["compile_timings"]
    assert "cache" in runs[1].stats["compile_timings"]        # read from the cache
    for name in ("y", "d.x"):
        assert np.array_equal(runs[0][name], runs[1][name])
    assert simulate("CacheLib.Scaled", 1.0, lib_dirs=[str(library)], points=11)["y"][-1] == runs[0]["y"][-1]


@retried_if_the_compiler_changes
def test_a_failure_during_a_run_from_the_cache_is_located_as_without_it(tmp_path):
    cache = tmp_path / "cache"
    write(tmp_path / "lib" / "BoundLib" / "Rise.dyad", """
        component Rise
          variable x::Real(max = 1.5)
        relations
          initial x = 1.0
          der(x) = 1.0
        end
        """)
    run = ("simulate", "BoundLib.Rise", "-L", tmp_path / "lib", "--stop", "2", "--strict-bounds")
    first, from_cache, from_source = (dyadc(cache, *run), dyadc(cache, *run), dyadc(cache, *run, "--no-cache"))
    assert first.code == from_cache.code == from_source.code == 1
    assert not from_cache.compiled                     # located without compiling
    assert "Rise.dyad:2:3: note: `x` is declared here" in from_cache.stderr
    assert from_cache.stderr == from_source.stderr == first.stderr


def test_the_models_folder_is_pruned_least_recently_used_first(tmp_path):
    from compiler.cache import models
    folder = tmp_path / "models"
    folder.mkdir()
    now = time.time()
    for age, name in enumerate(["newest.model", "middle.model", "oldest.model", "old.manifest"]):
        path = folder / name
        path.write_bytes(b"x" * 100)
        os.utime(path, (now - 10 * age, now - 10 * age))
    killed = folder / ".abc.model.x1y2.tmp.model"
    killed.write_bytes(b"half")
    os.utime(killed, (now - 2 * models.STALE_TEMPORARY_SECONDS,) * 2)
    assert models.prune(folder, limit=1000) == [killed]          # under the limit: only the leftover
    removed = models.prune(folder, limit=300)
    assert sorted(p.name for p in removed) == ["old.manifest", "oldest.model"]
    assert sorted(p.name for p in folder.iterdir()) == ["middle.model", "newest.model"]


def test_a_source_changed_while_it_was_compiled_is_not_stored(tmp_path, monkeypatch):
    from compiler import pipeline
    monkeypatch.setenv("DYADC_CACHE_DIR", str(tmp_path / "cache"))
    library = small_library(tmp_path / "lib")
    decay = library / "CacheLib" / "Decay.dyad"
    compile_spec = pipeline.compile_spec

    def edited_while_compiling(*args, **kwargs):
        compilation = compile_spec(*args, **kwargs)
        decay.write_text(decay.read_text() + "\n")           # saved after the compile read it
        return compilation
    monkeypatch.setattr(pipeline, "compile_spec", edited_while_compiling)
    assert pipeline.compile_or_load("CacheLib.Scaled", [str(library)]).cache_key is None
    assert entries(tmp_path / "cache") == []
    monkeypatch.setattr(pipeline, "compile_spec", compile_spec)
    assert pipeline.compile_or_load("CacheLib.Scaled", [str(library)]).cache_key is not None