"""Timings of the integer graph algorithms on synthetic chains (N = 10^3, 10^4, 10^5).

Run: .venv/bin/python benchmarks/bench_graph.py [--sizes 1000 10000 100000] [--repeats 3]
Prints the median wall time per algorithm and size; near-linear scaling means the time grows
about 10x per row.
"""
from __future__ import annotations

import argparse
import statistics
import time

from compiler.structure.graph import (
    block_lower_triangular,
    dulmage_mendelsohn,
    maximum_matching,
    pantelides,
    reachable,
    strongly_connected_components,
    tear_block,
)


def chain_incidence(n: int) -> list[list[int]]:
    """eq i uses v_i and v_{i+1} (listed last-first so the greedy start is useless)."""
    return [[i + 1, i] if i + 1 < n else [i] for i in range(n)]


def cyclic_loop(n: int) -> list[list[int]]:
    """One algebraic loop: eq i uses v_i and v_{(i+1) mod n}."""
    return [sorted({i, (i + 1) % n}) for i in range(n)]


def rigid_link_chain(n: int):
    """n point masses on a line joined by rigid links (index 3, constraints coupled in a chain).

    der(x_i) = v_i, der(v_i) = f_i - f_{i-1}, x_{i+1} - x_i = L, and x_0 pinned: 0 = x_0 with
    pin force f_{n-1} acting on mass 0.
    Variables: x_i, v_i, dx_i, dv_i, f_i (n-1 link forces and the pin force).
    """
    x = lambda i: 4 * i  # noqa: E731
    v = lambda i: 4 * i + 1  # noqa: E731
    dx = lambda i: 4 * i + 2  # noqa: E731
    dv = lambda i: 4 * i + 3  # noqa: E731
    f = lambda i: 4 * n + i  # noqa: E731
    n_vars = 5 * n
    var_to_diff = [-1] * n_vars
    incidence = []
    for i in range(n):
        var_to_diff[x(i)] = dx(i)
        var_to_diff[v(i)] = dv(i)
        incidence.append(sorted([dx(i), v(i)]))
        forces = [f(i)] if i < n - 1 else []
        forces += [f(i - 1)] if i > 0 else [f(n - 1)]
        incidence.append(sorted([dv(i)] + forces))
    for i in range(n - 1):
        incidence.append([x(i), x(i + 1)])
    incidence.append([x(0)])
    return len(incidence), n_vars, incidence, var_to_diff


def index_one_chain(n: int):
    """der(x_i) = z_i, z_i = x_i - x_{i+1}: an ODE chain with algebraic couplings."""
    x = lambda i: 3 * i  # noqa: E731
    dx = lambda i: 3 * i + 1  # noqa: E731
    z = lambda i: 3 * i + 2  # noqa: E731
    var_to_diff = [-1] * (3 * n)
    incidence = []
    for i in range(n):
        var_to_diff[x(i)] = dx(i)
        incidence.append(sorted([dx(i), z(i)]))
        incidence.append(sorted([z(i), x(i)] + ([x(i + 1)] if i + 1 < n else [])))
    return len(incidence), 3 * n, incidence, var_to_diff


def cases(n: int):
    chain = chain_incidence(n)
    loop = cyclic_loop(n)
    successors = [[i + 1] for i in range(n - 1)] + [[]]
    lower_triangular = [[i - 1, i] if i else [0] for i in range(n)]
    one_chain = index_one_chain(n)
    rigid = rigid_link_chain(max(2, n // 5))
    return {
        "maximum_matching (chain)": lambda: maximum_matching(n, n, chain),
        "pantelides (index-1 chain, 2N eqs)": lambda: pantelides(*one_chain),
        "pantelides (rigid links, index 3, N eqs)": lambda: pantelides(*rigid),
        "strongly_connected_components (path)": lambda: strongly_connected_components(n, successors),
        "block_lower_triangular (triangular)": lambda: block_lower_triangular(
            n, lower_triangular, list(range(n))),
        "block_lower_triangular (one loop)": lambda: block_lower_triangular(n, loop, list(range(n))),
        "dulmage_mendelsohn (chain)": lambda: dulmage_mendelsohn(n, n + 1, chain_incidence(n + 1)[:n]),
        "tear_block (one loop)": lambda: tear_block(list(range(n)), list(range(n)), loop,
                                                    lambda eq, var: True),
        "reachable (path)": lambda: reachable(n, successors, [0]),
    }


def median_seconds(run, repeats: int) -> float:
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        samples.append(time.perf_counter() - start)
    return statistics.median(samples)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1_000, 10_000, 100_000])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    results: dict[str, list[float]] = {}
    for n in args.sizes:
        for name, run in cases(n).items():
            results.setdefault(name, []).append(median_seconds(run, args.repeats))
    header = f"{'algorithm':44s}" + "".join(f"{'N=' + str(n):>12s}" for n in args.sizes)
    print(header)
    print("-" * len(header))
    for name, seconds in results.items():
        print(f"{name:44s}" + "".join(f"{s * 1e3:10.1f}ms" for s in seconds))


if __name__ == "__main__":
    main()
