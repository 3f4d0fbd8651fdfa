"""Build the native IDAS driver library at install time (`make install` runs
`python -m compiler.native.build`): SUNDIALS's sources from a pinned source package on PyPI
(AMICI's sdist carries SUNDIALS 7.1.1, BSD-3, under ThirdParty/sundials), checked against its
sha256, only the C files IDAS needs (IDAS, the serial vector, the dense matrix and solver, the
Newton solver, the core) compiled with the C compiler directly, with a configuration header of
ours instead of cmake's, and linked with our driver (dyad_idas.c, dyad_idas_model.c) into one
shared library.
Without a compiler or the archive the build says why and the runs stay on CasADi's IDAS.
"""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import tarfile
import tempfile
import urllib.request
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from compiler.runtime.native_build import find_compiler

from compiler.runtime.native.library import LIBRARY_PATH

ARCHIVE_URL = ("https://files.pythonhosted.org/packages/b0/ab/"
               "aeebac08b65fa7110934ed0938d48f1e3cdfed00361a09ca10d70e2ccf92/amici-1.1.0.tar.gz")
ARCHIVE_SHA256 = "63d51cbbf1f989f2f852bb98c9b5a59501f4d3697883221737ff0188eec6870f"
SUNDIALS_ROOT = "amici-1.1.0/amici/_installation/ThirdParty/sundials/"
SUNDIALS_VERSION = (7, 1, 1)
# the source folders compiled (every .c file in them but the ones below)
SOURCE_FOLDERS = ("src/sundials", "src/idas", "src/nvector/serial", "src/sunmatrix/dense",
                  "src/sunmatrix/band", "src/sunmatrix/sparse", "src/sunlinsol/dense",
                  "src/sunnonlinsol/newton", "src/sunmemory/system")
LEFT_OUT = {"sundials_profiler.c",     # built without profiling
            "idas_bbdpre.c"}           # the parallel band-block preconditioner
FLAGS = ["-O2", "-fPIC", "-fvisibility=hidden"]
DRIVER_SOURCES = [Path(__file__).with_name(name) for name in ("dyad_idas.c", "dyad_idas_model.c", "dyad_idas_floors.c")]
DOWNLOAD_TIMEOUT = 120


def fetch_archive(folder: Path, archive: Path | None = None) -> Path:
    """The source archive in `folder`, downloaded from ARCHIVE_URL unless given; its sha256 checked."""
    if archive is None:
        archive = folder / ARCHIVE_URL.rsplit("/", 1)[1]
        with urllib.request.urlopen(ARCHIVE_URL, timeout=DOWNLOAD_TIMEOUT) as response:
            archive.write_bytes(response.read())
    digest = hashlib.sha256(Path(archive).read_bytes()).hexdigest()
    if digest != ARCHIVE_SHA256:
        raise RuntimeError(f"{archive} has sha256 {digest}, expected {ARCHIVE_SHA256}")
    return Path(archive)


def extract_sundials(archive: Path, folder: Path) -> Path:
    """Only SUNDIALS's include/ and the SOURCE_FOLDERS into `folder`; returns the SUNDIALS root."""
    wanted = [SUNDIALS_ROOT + "include/", SUNDIALS_ROOT + "LICENSE"] + \
             [SUNDIALS_ROOT + f + "/" for f in SOURCE_FOLDERS]
    with tarfile.open(archive, "r:gz") as tar:
        members = [m for m in tar.getmembers() if m.isfile() and not m.issym() and not m.islnk()
                   and any(m.name.startswith(w) for w in wanted) and ".." not in m.name.split("/")]
        tar.extractall(folder, members=members)
    return folder / SUNDIALS_ROOT


def write_config(folder: Path) -> Path:
    """sundials_config.h and sundials_export.h for a serial double-precision, 64-bit-index build
    without MPI, logging, profiling or third-party libraries; returns the include folder."""
    include = folder / "config"
    (include / "sundials").mkdir(parents=True, exist_ok=True)
    major, minor, patch = SUNDIALS_VERSION
    empty = ["SUNDIALS_VERSION_LABEL", "SUNDIALS_GIT_VERSION", "SUN_C_COMPILER_VERSION",
             "SUN_C_COMPILER_FLAGS", "SUN_CXX_COMPILER", "SUN_CXX_COMPILER_VERSION",
             "SUN_CXX_COMPILER_FLAGS", "SUN_FORTRAN_COMPILER", "SUN_FORTRAN_COMPILER_VERSION",
             "SUN_FORTRAN_COMPILER_FLAGS", "SUN_JOB_ID", "SUN_JOB_START_TIME", "SUN_TPL_LIST",
             "SUN_TPL_LIST_SIZE", "SUNDIALS_SPACK_VERSION"]
    lines = ["#ifndef _SUNDIALS_CONFIG_H", "#define _SUNDIALS_CONFIG_H",
             '#include "sundials/sundials_export.h"', "#define SUNDIALS_NOEXCEPT",
             "#define SUNDIALS_DEPRECATED_MSG(msg) __attribute__((__deprecated__(msg)))",
             "#define SUNDIALS_DEPRECATED_EXPORT_MSG(msg) SUNDIALS_EXPORT SUNDIALS_DEPRECATED_MSG(msg)",
             "#define SUNDIALS_DEPRECATED_NO_EXPORT_MSG(msg) SUNDIALS_NO_EXPORT SUNDIALS_DEPRECATED_MSG(msg)",
             f'#define SUNDIALS_VERSION "{major}.{minor}.{patch}"',
             f"#define SUNDIALS_VERSION_MAJOR {major}", f"#define SUNDIALS_VERSION_MINOR {minor}",
             f"#define SUNDIALS_VERSION_PATCH {patch}",
             *[f'#define {name} ""' for name in empty],
             '#define SUN_C_COMPILER "cc"', '#define SUN_BUILD_TYPE "Release"',
             "#define SUNDIALS_C_COMPILER_HAS_BUILTIN_EXPECT", "#define SUNDIALS_DOUBLE_PRECISION 1",
             "#define SUNDIALS_INT64_T 1", "#define SUNDIALS_INDEX_TYPE int64_t",
             "#define SUNDIALS_LOGGING_LEVEL 0", "#define SUNDIALS_MPI_ENABLED 0",
             "#define SUNDIALS_IDAS 1", "#define SUNDIALS_NVECTOR_SERIAL 1",
             "#define SUNDIALS_SUNMATRIX_DENSE 1", "#define SUNDIALS_SUNLINSOL_DENSE 1",
             "#define SUNDIALS_SUNNONLINSOL_NEWTON 1", "#endif", ""]
    (include / "sundials" / "sundials_config.h").write_text("\n".join(lines))
    export = ["#ifndef SUNDIALS_EXPORT_H", "#define SUNDIALS_EXPORT_H",
              '#define SUNDIALS_EXPORT __attribute__((visibility("default")))',
              '#define SUNDIALS_NO_EXPORT __attribute__((visibility("hidden")))',
              "#define SUNDIALS_DEPRECATED __attribute__((__deprecated__))",
              "#define SUNDIALS_DEPRECATED_EXPORT SUNDIALS_EXPORT SUNDIALS_DEPRECATED",
              "#define SUNDIALS_DEPRECATED_NO_EXPORT SUNDIALS_NO_EXPORT SUNDIALS_DEPRECATED",
              "#endif", ""]
    (include / "sundials" / "sundials_export.h").write_text("\n".join(export))
    return include


def compile_library(compiler: str, root: Path, config: Path, folder: Path, target: Path) -> Path:
    """Every source into an object file (two at a time), linked with the driver into `target`."""
    sources = [s for f in SOURCE_FOLDERS for s in sorted((root / f).glob("*.c")) if s.name not in LEFT_OUT]
    sources += DRIVER_SOURCES
    includes = [f"-I{config}", f"-I{DRIVER_SOURCES[0].parent}", f"-I{root / 'include'}",
                f"-I{root / 'src' / 'sundials'}", f"-I{root / 'src' / 'idas'}"]

    def compile_one(index_source):
        index, source = index_source
        obj = folder / f"{index:03d}_{source.stem}.o"
        done = subprocess.run([compiler, *FLAGS, *includes, "-c", str(source), "-o", str(obj)],
                              capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"{source.name}: {done.stderr.strip()[-1500:]}")
        return obj

    with ThreadPoolExecutor(max_workers=max(1, min(4, os.cpu_count() or 1))) as pool:
        objects = list(pool.map(compile_one, enumerate(sources)))
    target.parent.mkdir(parents=True, exist_ok=True)
    scratch = target.with_name(target.name + f".{os.getpid()}.tmp")
    done = subprocess.run([compiler, "-shared", "-o", str(scratch), *map(str, objects), "-ldl", "-lm"],
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"linking failed: {done.stderr.strip()[-1500:]}")
    os.replace(scratch, target)          # atomic: a process loading it sees the old or the new one
    return target


def build(target: Path = LIBRARY_PATH, archive: Path | None = None) -> Path:
    """Fetch, check, extract, configure and compile: the driver library at `target`."""
    compiler = find_compiler()
    if compiler is None:
        raise RuntimeError("no C compiler (gcc, cc or clang; or $CC) found")
    with tempfile.TemporaryDirectory(prefix="dyadc-sundials-") as tmp:
        folder = Path(tmp)
        root = extract_sundials(fetch_archive(folder, archive), folder / "src")
        config = write_config(folder)
        return compile_library(compiler, root, config, folder, Path(target))


if __name__ == "__main__":
    import argparse
    parser = argparse.ArgumentParser(prog="python -m compiler.native.build",
                                     description="build the native IDAS driver library")
    parser.add_argument("--archive", type=Path, help="the AMICI 1.1.0 sdist, already downloaded")
    parser.add_argument("--output", type=Path, default=LIBRARY_PATH, help="the library to write")
    arguments = parser.parse_args()
    try:
        built = build(arguments.output, arguments.archive)
    except (RuntimeError, OSError, tarfile.TarError, subprocess.SubprocessError) as err:
        print(f"native IDAS driver not built ({err}); runs use CasADi's IDAS", file=sys.stderr)
        sys.exit(1)
    print(f"native IDAS driver built: {built}")
