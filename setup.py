"""Which folders become which installed packages; everything else is in pyproject.toml.

The Dyad library stays in the top-level `components/` folder, where library authors look for it,
and is installed as the package `compiler.components`: in a wheel it is copied there, in an
editable install setuptools maps the name to the folder. Either way `compiler.model.library` finds it
through importlib.resources, never through a path relative to the source tree. This file exists
only because pyproject.toml cannot combine package discovery with one renamed folder.
"""
import importlib.util
import subprocess
import sys
from pathlib import Path

from setuptools import find_namespace_packages, find_packages, setup
from setuptools.command.build_py import build_py

LIBRARY_PACKAGE = "compiler.components"
# Every library folder is listed (as a data-only namespace package) so that setuptools copies its
# .dyad files and does not warn that the folder looks importable but is not configured.
LIBRARY_FOLDERS = [f"{LIBRARY_PACKAGE}.{name}" for name in find_namespace_packages(where="components", exclude=["*__pycache__*"])]



class BuildWithLibraryTrees(build_py):
    """Also parses the shipped library once and keeps its trees in the package, so that a user's
    first compile does not parse it (compiler/cache/library_trees.py; an editable install keeps
    them in the source folder). Without lark in the build environment the package has none and
    parses the library files it reads, as before. And builds the CSV row formatter
    (compiler/runtime/native_build.py) where a C compiler is found; without one, CSV files are
    formatted in Python (the same text, slower)."""

    def run(self):
        super().run()
        here = Path(__file__).resolve().parent
        package = here / "compiler" if self.editable_mode else Path(self.build_lib) / "compiler"
        build_csv_formatter(here, package / "runtime")
        sys.path.insert(0, str(here))
        try:
            from compiler.cache.library_trees import write_trees
        except ImportError as err:
            print(f"warning: the shipped library's parsed trees are not made: {err}", file=sys.stderr)
            return
        finally:
            sys.path.remove(str(here))
        write_trees(here / "components", package / "cache" / "shipped_trees")


def build_csv_formatter(here: Path, folder: Path) -> None:
    """native_build.py is loaded from its file: importing compiler.runtime would need numpy."""
    spec = importlib.util.spec_from_file_location("dyadc_native_build", here / "compiler" / "runtime" / "native_build.py")
    native_build = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(native_build)
    try:
        native_build.build_csv_library(folder)
    except (OSError, RuntimeError, subprocess.SubprocessError) as err:
        print(f"warning: the C CSV formatter is not built ({err}); CSV files are formatted in Python",
              file=sys.stderr)


setup(
    packages=find_packages(include=["compiler", "compiler.*"]) + [LIBRARY_PACKAGE] + LIBRARY_FOLDERS,
    package_dir={LIBRARY_PACKAGE: "components"},
    cmdclass={"build_py": BuildWithLibraryTrees},
)
