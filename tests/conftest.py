"""The whole suite runs with a compilation cache of its own (docs/cache.md), a fresh temporary
folder per test process, never the user's: `dyadc simulate` in a test (in process or as a
subprocess, which inherits the variable) reads and writes only there, and a stale or damaged user
cache cannot change a verdict. DYADC_CACHE_DIR=off, when set, is kept (the suite without cache).

The C libraries that models run on by default (docs/cache.md, "C code") are content keyed, so one
folder is shared by every test process of a session (made by the first, which pytest-xdist's
workers inherit through DYADC_CACHE): a model compiled by several tests is built by gcc once.
A test that needs a C cache of its own sets DYADC_CACHE (or clears it, as tests/cache/helpers.py)."""
from __future__ import annotations

import atexit
import os
import shutil
import tempfile

import pytest

from compiler.cache.c_libraries import C_CACHE_VARIABLE
from compiler.cache.codegen_choice import CODEGEN_VARIABLE
from compiler.cache.store import CACHE_DIR_VARIABLE, OFF_VALUES

SESSION_C_CACHE = "DYADC_TEST_SESSION_C_CACHE"      # set by the process that made the shared folder

if os.environ.get(CACHE_DIR_VARIABLE, "").strip().lower() not in OFF_VALUES:
    _folder = tempfile.mkdtemp(prefix="dyadc-test-cache-")
    os.environ[CACHE_DIR_VARIABLE] = _folder
    atexit.register(shutil.rmtree, _folder, True)

if os.environ.get(SESSION_C_CACHE) is None:
    _c_folder = tempfile.mkdtemp(prefix="dyadc-test-c-")
    os.environ[SESSION_C_CACHE] = os.environ[C_CACHE_VARIABLE] = _c_folder
    atexit.register(shutil.rmtree, _c_folder, True)


# the integrator each code runs on in `each_codegen`: the default path, and the fallback
INTEGRATOR_OF = {"c": "native", "vm": "casadi"}


@pytest.fixture(scope="module", params=["c", "vm"], ids=["c+native", "vm+casadi"])
def each_codegen(request):
    """Run on compiled C with the native IDAS driver (the default path) and again on CasADi's
    virtual machine with CasADi's IDAS (the fallback where no C compiler, or no driver library,
    exists): DYADC_CODEGEN and DYADC_INTEGRATOR set for the module's tests, and for the
    module-scoped fixtures that take this one. A representative set uses it (events, state sets,
    the golden excavator, the Test Set problems); every other numerical test runs on the default
    path alone. The value is the code ("c", "vm"); INTEGRATOR_OF names its integrator."""
    from compiler.lower.ccodegen import find_compiler
    from compiler.runtime.native import INTEGRATOR_VARIABLE, library
    if request.param == "c" and find_compiler() is None:
        pytest.skip("no C compiler")
    if request.param == "c" and library.driver_library()[0] is None:
        pytest.skip("native IDAS driver not built (make install builds it)")
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv(CODEGEN_VARIABLE, request.param)
        patch.setenv(INTEGRATOR_VARIABLE, INTEGRATOR_OF[request.param])
        yield request.param
