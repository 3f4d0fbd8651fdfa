"""A cache entry whose seal is whole but whose model does not rebuild is a miss that is logged,
not an error and not a silent one (compiler/cache/models.py read_entry)."""
from __future__ import annotations

import json
import logging

from compiler.cache import models
from compiler.cache.store import write_sealed


def test_an_entry_that_does_not_rebuild_is_a_logged_miss(tmp_path, caplog):
    entry = {"format": models.ENTRY_FORMAT, "model": {"name": "Broken"}, "declarations": {},
             "needs_values": [], "notes": []}
    write_sealed(tmp_path / f"0123abcd{models.ENTRY_SUFFIX}", json.dumps(entry).encode())
    with caplog.at_level(logging.WARNING, logger="compiler.cache.models"):
        assert models.read_entry("0123abcd", tmp_path) is None
    [record] = caplog.records
    assert record.levelno == logging.WARNING
    assert record.getMessage().startswith("the cached model 0123abcd does not load (")
    assert record.getMessage().endswith("); compiling it again")
