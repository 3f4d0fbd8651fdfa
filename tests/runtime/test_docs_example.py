"""The runnable example of docs/runtime.md runs as written (from the repository root)."""
from __future__ import annotations

import os
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_runtime_docs_example_runs(tmp_path, monkeypatch):
    text = (ROOT / "docs" / "runtime.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    example = next(b for b in blocks if "simulate(model" in b)
    example = example.replace('"tests/models/', f'"{ROOT}/tests/models/')
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    exec(compile(example, "docs/runtime.md", "exec"), namespace)      # noqa: S102 - our own docs
    result = namespace["result"]
    assert result.time[-1] == 2.0 and result.stats["steps"] > 10
    assert os.path.getsize(tmp_path / "pendulum.parquet") > 0
