"""The compiled-C cache survives damage, killed runs and concurrent runs (issue 19, item 8).

Before: a truncated library made every `--codegen c` run die with SIGBUS (exit 135) and an empty
one sent every run to the virtual machine. Every "next run" here is a fresh `dyadc` process, so a
crash fails the test instead of killing pytest.
"""
from __future__ import annotations

import hashlib
import json
import os
import signal
import stat
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from compiler.cache import c_libraries as c_cache
from compiler.cache.c_code import compile_c

from compiler.lower import ccodegen
from compiler.lower.to_casadi import lower
from tests.runtime import runtime_systems as systems

pytestmark = pytest.mark.skipif(ccodegen.find_compiler() is None, reason="no C compiler")

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "tests" / "models" / "ComponentTests" / "FallingBody.dyad"
HEIGHT_AT_1S = 10.0 + 3.0 - 9.80665 / 2           # thrown up at 3 m/s from 10 m


def run_dyadc(cache: Path, env_extra: dict | None = None, **popen) -> subprocess.CompletedProcess:
    env = dict(os.environ, DYADC_CACHE=str(cache), **(env_extra or {}))
    return subprocess.run([sys.executable, "-m", "compiler", "simulate", str(MODEL), "--stop", "1",
                           "--codegen", "c", "--vars", "body.r[2]"],
                          capture_output=True, text=True, cwd=ROOT, env=env, timeout=300, **popen)


def check_run(done: subprocess.CompletedProcess) -> None:
    assert done.returncode == 0, f"exit {done.returncode}: {done.stderr}"
    assert "unavailable" not in done.stderr                   # it ran in C, not on the fallback
    final = float(done.stdout.split("body.r[2]")[1].split()[0])
    assert final == pytest.approx(HEIGHT_AT_1S, abs=1e-5)


def entries(cache: Path) -> list[Path]:
    return sorted(cache.glob("dyad_*.so"))


def assert_valid(cache: Path, library: Path) -> None:
    record = json.loads(library.with_suffix(".json").read_text())
    data = library.read_bytes()
    assert record["size"] == len(data) > 0 and record["sha256"] == hashlib.sha256(data).hexdigest()


@pytest.fixture
def built(tmp_path) -> tuple[Path, Path, bytes]:
    """(cache folder, its one library, the library's good bytes) after one real run."""
    cache = tmp_path / "cache"
    check_run(run_dyadc(cache))
    [library] = entries(cache)
    assert_valid(cache, library)
    return cache, library, library.read_bytes()


def _truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _empty(path: Path) -> None:
    path.write_bytes(b"")


def _corrupt(path: Path) -> None:            # same size, different bytes in the code section
    data = bytearray(path.read_bytes())
    middle = len(data) // 2
    data[middle:middle + 64] = b"\xcc" * 64
    path.write_bytes(bytes(data))


def _drop_record(path: Path) -> None:
    path.with_suffix(".json").unlink()


def _garble_record(path: Path) -> None:
    path.with_suffix(".json").write_text("{not json")


@pytest.mark.parametrize("damage", [_truncate, _empty, _corrupt, _drop_record, _garble_record],
                         ids=["truncated", "empty", "corrupted", "no-record", "bad-record"])
def test_a_damaged_entry_is_rebuilt_and_the_run_is_correct(built, damage):
    cache, library, good = built
    damage(library)
    check_run(run_dyadc(cache))
    assert entries(cache) == [library]
    assert library.read_bytes() == good                        # rebuilt: builds are reproducible
    assert_valid(cache, library)


def test_leftovers_of_a_killed_build_are_removed_by_the_next_build(tmp_path):
    cache = tmp_path / "cache"
    slow = tmp_path / "slow-cc"                 # answers --version like gcc, then never finishes
    slow.write_text(f"#!/bin/sh\nif [ \"$1\" = --version ]; then exec {ccodegen.find_compiler()} --version; fi\n"
                    "exec sleep 120\n")
    slow.chmod(0o755)
    env = dict(os.environ, DYADC_CACHE=str(cache), CC=str(slow))
    killed = subprocess.Popen([sys.executable, "-m", "compiler", "simulate", str(MODEL), "--stop", "1",
                               "--codegen", "c"], cwd=ROOT, env=env, start_new_session=True,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        while not list(cache.glob("build-*/*.c")) and time.monotonic() < deadline:
            time.sleep(0.1)
    finally:
        os.killpg(killed.pid, signal.SIGKILL)
        killed.wait()
    leftovers = list(cache.glob("build-*"))
    assert leftovers and entries(cache) == []
    old = time.time() - c_cache.STALE_AFTER - 60      # another entry's leftovers, once stale
    for name, text in ((".dyad_0123.json.999.tmp", "{"), ("dyad_0123.so", "\x7fELF")):
        (cache / name).write_text(text)
        os.utime(cache / name, (old, old))
    (cache / "dyad_4567.so").write_text("\x7fELF")       # another entry's, maybe being built now
    check_run(run_dyadc(cache))
    names = {p.name for p in cache.iterdir()}
    [library] = [e for e in entries(cache) if e.name != "dyad_4567.so"]
    assert names == {".lock", library.with_suffix(".json").name, library.with_suffix(".lock").name,
                     library.name, "dyad_4567.so"}
    assert_valid(cache, library)


def test_two_processes_building_one_entry_build_it_once(tmp_path):
    cache = tmp_path / "cache"
    log = tmp_path / "builds.log"
    counting = tmp_path / "counting-cc"
    counting.write_text(f"#!/bin/sh\n[ \"$1\" = -shared ] && echo build >> {log}\n"     # the link
                        f"exec {ccodegen.find_compiler()} \"$@\"\n")
    counting.chmod(0o755)
    env = dict(os.environ, DYADC_CACHE=str(cache), CC=str(counting))
    command = [sys.executable, "-m", "compiler", "simulate", str(MODEL), "--stop", "1", "--codegen", "c",
               "--vars", "body.r[2]"]
    runs = [subprocess.Popen(command, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True) for _ in range(2)]
    for run in runs:
        out, err = run.communicate(timeout=300)
        check_run(subprocess.CompletedProcess(run.args, run.returncode, out, err))
    assert log.read_text().splitlines() == ["build"]
    [library] = entries(cache)
    assert_valid(cache, library)


def test_the_cache_folder_is_private(tmp_path):
    fresh = c_cache.private_folder(tmp_path / "a" / "cache")
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o700
    shared = tmp_path / "shared"
    shared.mkdir(mode=0o777)
    shared.chmod(0o777)
    assert stat.S_IMODE(c_cache.private_folder(shared).stat().st_mode) == 0o700


def test_a_cache_folder_of_another_user_is_refused(tmp_path, monkeypatch):
    cache = tmp_path / "cache"
    cache.mkdir()
    monkeypatch.setattr(c_cache.os, "getuid", lambda: cache.stat().st_uid + 1)
    with pytest.warns(ccodegen.CodegenWarning, match="belongs to another user"):
        model = compile_c(lower(systems.rc_circuit()), cache)
    assert model.native_library is None and model.metadata["codegen"] == "vm"
    assert list(cache.iterdir()) == []


def test_two_entries_build_at_once_and_one_entry_once(tmp_path):
    """A lock per entry: two threads building different libraries run side by side (each build
    waits for the other to have started: one folder-wide lock would never let them), and a third
    asking for a library being built waits for it and takes it."""
    cache = tmp_path / "cache"
    started = {key: threading.Event() for key in ("aa" * 8, "bb" * 8)}
    builds = []

    def build(key: str, other: str):
        def make(scratch: Path) -> Path:
            builds.append(key)
            started[key].set()
            assert started[other].wait(timeout=60), "the other entry's build never started"
            (scratch / "lib.so").write_bytes(key.encode())
            return scratch / "lib.so"
        return make

    (a, b), again = sorted(started), []
    threads = [threading.Thread(target=lambda k=k, o=o: c_cache.fetch_or_build(cache, k, build(k, o)))
               for k, o in ((a, b), (b, a))]
    threads.append(threading.Thread(target=lambda: again.append(
        c_cache.fetch_or_build(cache, a, lambda scratch: pytest.fail("built twice")))))
    for thread in threads[:2]:
        thread.start()
    started[a].wait(timeout=60)
    threads[2].start()
    for thread in threads:
        thread.join(timeout=120)
    assert sorted(builds) == [a, b]
    assert again == [(c_cache.library_path(cache, a), False)]
    assert c_cache.library_path(cache, b).read_bytes() == b.encode()


def test_a_build_whose_folder_is_removed_under_it_is_built_again_in_a_new_one(tmp_path):
    cache, folders = tmp_path / "cache", []

    def build(scratch: Path) -> Path:
        folders.append(scratch)
        if len(folders) == 1:                      # say, a tmp cleaner took the folder
            scratch.rmdir()
            raise RuntimeError("gcc failed: cannot open output file")
        (scratch / "lib.so").write_bytes(b"built")
        return scratch / "lib.so"

    library, built = c_cache.fetch_or_build(cache, "cc" * 8, build)
    assert built and len(folders) == 2 and folders[0] != folders[1]
    assert library.read_bytes() == b"built" and c_cache.valid_entry(cache, "cc" * 8) == library
    assert not any(p.name.startswith(c_cache.BUILD_PREFIX) for p in cache.iterdir())


def test_a_failing_build_in_a_folder_that_is_still_there_is_not_retried(tmp_path):
    attempts = []

    def build(scratch: Path) -> Path:
        attempts.append(scratch)
        raise RuntimeError("gcc failed: syntax error")

    with pytest.raises(RuntimeError, match="syntax error"):
        c_cache.fetch_or_build(tmp_path / "cache", "dd" * 8, build)
    assert len(attempts) == 1


def test_the_compiler_runs_on_absolute_paths_and_the_library_does_not_depend_on_its_folder(tmp_path, monkeypatch):
    compiler = ccodegen.find_compiler()
    units = {"a.c": "double twice(double x) { return 2 * x; }\n",
             "b.c": "double twice(double x);\ndouble four(double x) { return twice(twice(x)); }\n"}
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)                  # the process's folder is not the build's
    libraries = []
    for name in ("one", "two-with-a-longer-name"):
        (tmp_path / name).mkdir()
        libraries.append(ccodegen.compile_units(units, compiler, tmp_path / name))
    assert [lib.parent for lib in libraries] == [tmp_path / "one", tmp_path / "two-with-a-longer-name"]
    assert libraries[0].read_bytes() == libraries[1].read_bytes()
    assert sorted(p.name for p in elsewhere.iterdir()) == []


def test_a_build_whose_whole_cache_folder_is_removed_under_it_is_built_again(tmp_path):
    import shutil
    cache, attempts = tmp_path / "cache", []

    def build(scratch: Path) -> Path:
        attempts.append(scratch)
        if len(attempts) == 1:                     # the cache folder itself goes, lock files and all
            shutil.rmtree(cache)
            raise FileNotFoundError(2, "No such file or directory", str(scratch / "dyad.o"))
        (scratch / "lib.so").write_bytes(b"again")
        return scratch / "lib.so"

    library, built = c_cache.fetch_or_build(cache, "ee" * 8, build)
    assert built and len(attempts) == 2
    assert library.read_bytes() == b"again" and c_cache.valid_entry(cache, "ee" * 8) == library


def test_another_entrys_build_folder_that_goes_while_the_folder_is_listed_is_passed_over(tmp_path, monkeypatch):
    """Another process finishes its own entry's build and removes that build folder between this
    build's listing of the shared folder and its look at the folder's age: the build goes on (the
    suite's processes share one C folder; this fell back to the VM now and then)."""
    cache = tmp_path / "cache"
    cache.mkdir()
    other = cache / f"{c_cache.BUILD_PREFIX}{'ab' * 16}-x1y2z3"
    other.mkdir()
    listed = type(cache).iterdir

    def listing_then_the_other_build_finishes(folder):
        entries_now = list(listed(folder))
        if folder == cache and other.exists():
            other.rmdir()                           # its owner removes it after the listing
        return iter(entries_now)

    monkeypatch.setattr(type(cache), "iterdir", listing_then_the_other_build_finishes)
    assert c_cache.remove_leftovers(cache, "cd" * 16) == []

    def build(scratch: Path) -> Path:
        (scratch / "lib.so").write_bytes(b"built")
        return scratch / "lib.so"

    other.mkdir()
    library, built = c_cache.fetch_or_build(cache, "cd" * 16, build)
    assert built and library.read_bytes() == b"built"
    assert not other.exists() and c_cache.valid_entry(cache, "cd" * 16) == library
