"""`dyadc inspect`: every pass of the structure stage, as counts and names."""
from __future__ import annotations

from collections import Counter

from compiler.cli.simulate import code_named
from compiler.pipeline import Compilation

_MAX_NAMES = 40


def _names(names: list[str]) -> str:
    shown = ", ".join(names[:_MAX_NAMES])
    return shown + (f", ... ({len(names) - _MAX_NAMES} more)" if len(names) > _MAX_NAMES else "") if names else "-"


def format_switch_log(result) -> str:
    """The state-set switches and events of a run: time, old set, new set, the pivot quality of
    the old set there (its pivot block's smallest singular value against the best choice's), and
    the code the new set runs on ("in C", or "on the VM" and why)."""
    lines = [f"run to t = {result.time[-1]:.6g}: {len(result.switches)} state-set switches, "
             f"{len(result.events)} events, {result.stats.get('steps', 0)} IDAS steps"]
    for switch in result.switches:
        lines.append(f"  t = {switch['time']:<14.10g} ({', '.join(switch['from'])}) -> "
                     f"({', '.join(switch['to'])})  pivot quality {switch.get('quality', float('nan')):.3g}"
                     f"  degraded: {switch['degraded']}  {code_named(switch)}")
    for event in result.events:
        lines.append(f"  t = {event['time']:<14.10g} event {event['event']}")
    return "\n".join(lines)


def format_report(compilation: Compilation) -> str:
    report = compilation.report
    lines = [f"model {compilation.model.name}", "", "counts:"]
    width = max(len(k) for k in report.counts) if report.counts else 0
    lines += [f"  {k:<{width}}  {v}" for k, v in report.counts.items()]
    lines += ["", f"structural index: {report.structural_index}",
              f"states ({len(report.states)}): {_names(report.states)}",
              f"dummy derivatives ({len(report.dummy_derivatives)}): {_names(report.dummy_derivatives)}"]
    for k, level in enumerate(compilation.model.state_sets):
        chosen = [level["candidates"][j] for j in level["chosen"]]
        lines.append(f"monitored state-set level {k}: {level['rows']} of {len(level['candidates'])} "
                     f"candidates ({_names(level['candidates'])}) are dummy derivatives; now: {_names(chosen)}")
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
