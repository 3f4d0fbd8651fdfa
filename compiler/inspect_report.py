"""`dyadc inspect`: every pass of the structure stage, as counts and names."""
from __future__ import annotations

from collections import Counter

from compiler.pipeline import Compilation

_MAX_NAMES = 40


def _names(names: list[str]) -> str:
    shown = ", ".join(names[:_MAX_NAMES])
    return shown + (f", ... ({len(names) - _MAX_NAMES} more)" if len(names) > _MAX_NAMES else "") if names else "-"


def format_report(compilation: Compilation) -> str:
    report = compilation.report
    lines = [f"model {compilation.model.name}", "", "counts:"]
    width = max(len(k) for k in report.counts) if report.counts else 0
    lines += [f"  {k:<{width}}  {v}" for k, v in report.counts.items()]
    lines += ["", f"structural index: {report.structural_index}",
              f"states ({len(report.states)}): {_names(report.states)}",
              f"dummy derivatives ({len(report.dummy_derivatives)}): {_names(report.dummy_derivatives)}"]
    if report.pivot_conditions:
        lines.append("pivot block condition numbers: " + ", ".join(f"{c:.3g}" for c in report.pivot_conditions))
    sizes = Counter(report.block_sizes)
    lines += [f"BLT blocks: {len(report.block_sizes)} (" +
              ", ".join(f"{n} of size {s}" for s, n in sorted(sizes.items())) + ")",
              f"torn / IDAS algebraic ({len(report.torn)}): {_names(report.torn)}",
              f"pruned to post-solve ({len(report.pruned)}): {_names(report.pruned)}",
              "", "stage times [s]:"]
    lines += [f"  {k:<16} {v:.3f}" for k, v in list(compilation.timings.items()) + list(report.timings.items())]
    return "\n".join(lines)
