"""Which folders become which installed packages; everything else is in pyproject.toml.

The Dyad library stays in the top-level `components/` folder, where library authors look for it,
and is installed as the package `compiler.components`: in a wheel it is copied there, in an
editable install setuptools maps the name to the folder. Either way `compiler.model.library` finds it
through importlib.resources, never through a path relative to the source tree. This file exists
only because pyproject.toml cannot combine package discovery with one renamed folder.
"""
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
    parses the library files it reads, as before."""

    def run(self):
        super().run()
        here = Path(__file__).resolve().parent
        sys.path.insert(0, str(here))
        try:
            from compiler.cache.library_trees import write_trees
        except ImportError as err:
            print(f"warning: the shipped library's parsed trees are not made: {err}", file=sys.stderr)
            return
        finally:
            sys.path.remove(str(here))
        package = here / "compiler" if self.editable_mode else Path(self.build_lib) / "compiler"
        write_trees(here / "components", package / "cache" / "shipped_trees")


setup(
    packages=find_packages(include=["compiler", "compiler.*"]) + [LIBRARY_PACKAGE] + LIBRARY_FOLDERS,
    package_dir={LIBRARY_PACKAGE: "components"},
    cmdclass={"build_py": BuildWithLibraryTrees},
)
