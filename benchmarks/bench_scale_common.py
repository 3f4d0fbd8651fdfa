"""What the scaling benchmarks (bench_scale.py and its bench_scale_*.py modes) share: the paths,
saved JSON lines, growth-exponent fits and the sections of docs/scaling.md."""
from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
for _path in (ROOT, ROOT / "benchmarks"):
    if str(_path) not in sys.path:
        sys.path.insert(0, str(_path))
SCALING_DOC = ROOT / "docs" / "scaling.md"


def read_rows(path: str) -> list[dict]:
    return [json.loads(line) for line in Path(path).read_text().splitlines() if line.startswith("{")]


def median_rows(paths: str) -> list[dict]:
    """Rows of several runs (comma-separated JSON-line files), each number the median per N."""
    runs = [read_rows(path) for path in paths.split(",")]
    rows = []
    for same_n in zip(*runs):
        row = dict(same_n[0])
        for key, value in row.items():
            if isinstance(value, float):
                row[key] = statistics.median(r.get(key, 0.0) for r in same_n)
        rows.append(row)
    return rows


def fit(rows: list[dict], key, lo: int = 8) -> float | None:
    """The least-squares exponent of key(row) against N over the rows with N >= lo."""
    import numpy as np
    points = [(r["n"], key(r)) for r in rows if r["n"] >= lo and key(r)]
    if len(points) < 2:
        return None
    n, t = zip(*points)
    return float(np.polyfit(np.log(n), np.log(t), 1)[0])


def local_exponent(rows: list[dict], key) -> float | None:
    """The exponent between the two largest N."""
    import math
    if len(rows) < 2 or not key(rows[-1]) or not key(rows[-2]):
        return None
    return math.log(key(rows[-1]) / key(rows[-2])) / math.log(rows[-1]["n"] / rows[-2]["n"])


def sections(text: str) -> list[tuple[str, list[str]]]:
    """The document as (heading, lines) per `## ` section; the part before the first has heading ''."""
    out: list[tuple[str, list[str]]] = [("", [])]
    for line in text.splitlines():
        if line.startswith("## "):
            out.append((line, []))
        out[-1][1].append(line)
    return out


def replace_section(heading: str, lines: list[str], out: Path = SCALING_DOC) -> None:
    """Rewrite the section `heading` of `out` (up to the next `## ` heading) with `lines`, which
    begin with the heading; a section the document does not have yet is appended."""
    parts = sections(out.read_text(encoding="utf-8")) if out.exists() else [("", [])]
    if not any(name == heading for name, _ in parts):
        parts.append((heading, []))
    text = [line for name, body in parts for line in (lines if name == heading else body)]
    out.write_text("\n".join(text).rstrip("\n") + "\n", encoding="utf-8")
