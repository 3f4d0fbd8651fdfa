"""The whole suite runs with a compilation cache of its own (docs/cache.md), a fresh temporary
folder per test process, never the user's: `dyadc simulate` in a test (in process or as a
subprocess, which inherits the variable) reads and writes only there, and a stale or damaged user
cache cannot change a verdict. DYADC_CACHE_DIR=off, when set, is kept (the suite without cache)."""
from __future__ import annotations

import atexit
import os
import shutil
import tempfile

from compiler.cache.store import CACHE_DIR_VARIABLE, OFF_VALUES

if os.environ.get(CACHE_DIR_VARIABLE, "").strip().lower() not in OFF_VALUES:
    _folder = tempfile.mkdtemp(prefix="dyadc-test-cache-")
    os.environ[CACHE_DIR_VARIABLE] = _folder
    atexit.register(shutil.rmtree, _folder, True)
