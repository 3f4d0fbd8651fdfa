"""Which folders become which installed packages; everything else is in pyproject.toml.

The Dyad library stays in the top-level `components/` folder, where library authors look for it,
and is installed as the package `compiler.components`: in a wheel it is copied there, in an
editable install setuptools maps the name to the folder. Either way `compiler.model.library` finds it
through importlib.resources, never through a path relative to the source tree. This file exists
only because pyproject.toml cannot combine package discovery with one renamed folder.
"""
from setuptools import find_namespace_packages, find_packages, setup

LIBRARY_PACKAGE = "compiler.components"
# Every library folder is listed (as a data-only namespace package) so that setuptools copies its
# .dyad files and does not warn that the folder looks importable but is not configured.
LIBRARY_FOLDERS = [f"{LIBRARY_PACKAGE}.{name}" for name in find_namespace_packages(where="components", exclude=["*__pycache__*"])]

setup(
    packages=find_packages(include=["compiler", "compiler.*"]) + [LIBRARY_PACKAGE] + LIBRARY_FOLDERS,
    package_dir={LIBRARY_PACKAGE: "components"},
)
