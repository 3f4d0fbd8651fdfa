"""docs/api.md stays true: every `python` block of it runs, in order, in an empty folder."""
from __future__ import annotations

import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[2] / "docs" / "api.md"


def test_every_example_of_the_api_page_runs(tmp_path, monkeypatch):
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), re.DOTALL)
    assert len(blocks) >= 6
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for number, block in enumerate(blocks, 1):
        exec(compile(block, f"docs/api.md block {number}", "exec"), namespace)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "Tank.dyad", "events.csv", "sweep.parquet", "sweep.png", "sweep.samples.parquet", "tank.csv",
        "tank.csv.json", "tank.parquet", "tank.png"]
