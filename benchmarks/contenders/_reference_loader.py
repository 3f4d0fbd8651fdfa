"""Load the independent reference models of tests/reference by file path.

The contenders are plain scripts of the benchmark suite; the reference models live in the
test tree. Loading by path (under a private module name) avoids making `tests` or
`reference` an importable top-level package and cannot pick up an unrelated installed
package of the same name (there is a PyPI `pendulum`, for instance).
"""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

REFERENCE_DIR = Path(__file__).resolve().parents[2] / "tests" / "reference"


def load_reference(name: str) -> ModuleType:
    """The module tests/reference/<name>.py, loaded once and cached."""
    module_name = f"_dyadc_reference_{name}"
    if module_name in sys.modules:
        return sys.modules[module_name]
    path = REFERENCE_DIR / f"{name}.py"
    spec = importlib.util.spec_from_file_location(module_name, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"no reference model at {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    spec.loader.exec_module(module)
    return module
