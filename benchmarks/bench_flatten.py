"""Flattening time of a chain of N planar links (the library's Revolute + BodyShape per link, the
same chain as the structure and compile-time benchmarks: benchmarks/suite/chain_model.py).

Prints the median of a few runs for N = 10, 100, 1000 and the time per link, which should stay
roughly constant (near-linear scaling). Usage: python benchmarks/bench_flatten.py [--quick]
"""
from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from compiler.model.flatten import flatten_model  # noqa: E402
from suite.chain_model import write_chain  # noqa: E402

def bench(n: int, repeats: int, folder: Path) -> float:
    spec = write_chain(n, folder)
    times = []
    for _ in range(repeats):
        began = time.perf_counter()
        flat = flatten_model(spec)
        times.append(time.perf_counter() - began)
    assert len(flat.equations) == sum(1 for v in flat.variables)
    return statistics.median(times)


def main() -> None:
    quick = "--quick" in sys.argv
    sizes = (10, 100) if quick else (10, 100, 1000)
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            repeats = 5 if n <= 100 else 3
            median = bench(n, repeats, Path(tmp))
            print(f"flatten chain N={n:5d}: median {median * 1e3:9.1f} ms   "
                  f"({median / n * 1e3:6.2f} ms per link)")


if __name__ == "__main__":
    main()
