"""Parse-time benchmark: median time to parse the largest .dyad under components/ and a synthetic
large file. Run: .venv/bin/python benchmarks/bench_parse.py"""
from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from compiler.syntax.format import format_file  # noqa: E402
from compiler.syntax.parser import parse_source  # noqa: E402


def synthetic_source(components: int = 40, size: int = 25) -> str:
    """`components` components, each with `size` parameters, variables and equations."""
    out = []
    for c in range(components):
        out.append(f'"""Synthetic component {c}."""\ncomponent Synthetic{c}')
        out.append("  extends Base(k = 2, color = [0.1, 0.2, 0.3, 1.0])")
        for i in range(size):
            out.append(f'  "Parameter {i}"\n  parameter p{i}::Real = {i}.5e-3')
            out.append(f"  variable x{i}::Real(guess = 1.0, state_priority = {i % 3})")
        out.append('  body = Body(m = p1, phi(initial = 0.3)) {"Dyad": {"x": 1, "tags": []}}')
        out.append("relations")
        for i in range(size):
            out.append(f"  der(x{i}) = -p{i} * x{i} ^ 2 + sin(x{(i + 1) % size}) / (1 + 10k)")
        out.append("  connect(body.frame_a, frame_a, frame_b)")
        out.append("end\n")
    return "\n".join(out)


def median_seconds(text: str, name: str, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        parse_source(text, name)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    start = time.perf_counter()
    parse_source("component Warmup\nend\n", "warmup")        # builds the LALR tables once
    print(f"grammar load: {time.perf_counter() - start:.3f} s")
    files = sorted(REPO.glob("components/**/*.dyad"), key=lambda p: p.stat().st_size)
    if files:
        largest = files[-1]
        text = largest.read_text(encoding="utf-8")
        t = median_seconds(text, str(largest), 15)
        print(f"largest file {largest.relative_to(REPO)} ({len(text.splitlines())} lines): "
              f"median {t * 1e3:.1f} ms")
    text = synthetic_source()
    t = median_seconds(text, "synthetic.dyad", 5)
    lines = len(text.splitlines())
    print(f"synthetic file ({lines} lines, {len(text) // 1024} KiB): median {t * 1e3:.1f} ms "
          f"({lines / t:,.0f} lines/s)")
    parsed = parse_source(text, "synthetic.dyad")
    start = time.perf_counter()
    format_file(parsed)
    print(f"format synthetic file: {(time.perf_counter() - start) * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
