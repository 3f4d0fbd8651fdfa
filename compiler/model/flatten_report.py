"""Human-readable views of a FlatSystem: `summarize` (for `dyadc check`) and `format_flat`
(for `dyadc flatten`)."""
from __future__ import annotations

from collections import Counter

from compiler.model.flat import INPUT, FlatSystem


def summarize(flat: FlatSystem, verdict=None) -> str:
    """`verdict` (compiler.model.verdict.Verdict), when given, replaces the bare count comparison:
    it says whether the model runs on its own or is partial, and why."""
    from compiler.model.balance import balance_summary, unbalanced_components
    kinds = Counter(v.kind for v in flat.variables)
    n_eqs, n_unknowns = balance_summary(flat)
    tunable = sum(1 for p in flat.parameters if p.tunable)
    lines = [f"model {flat.name}"]
    lines.append("  variables: " + ", ".join(f"{kinds[k]} {k}" for k in sorted(kinds))
                 + f" ({len(flat.variables)} total)")
    lines.append(f"  derivatives: {len(flat.derivatives)}")
    lines.append(f"  parameters: {len(flat.parameters)} ({tunable} tunable)")
    equation_kinds = Counter(e.kind for e in flat.equations)
    lines.append(f"  equations: {n_eqs} (" + ", ".join(f"{equation_kinds[k]} {k}"
                                                       for k in sorted(equation_kinds)) + ")")
    lines.append(f"  initial equations: {len(flat.initial_equations)}, guesses: "
                 f"{len(flat.guesses)}")
    if flat.visual:
        lines.append(f"  visual-only instances: {len(flat.visual)}")
    if verdict is not None:
        lines.append(f"  {verdict.describe()}")
        if verdict.is_partial:
            lines.append(f"    closed as it stands: {verdict.reason.message}")
    else:
        status = "balanced" if n_eqs == n_unknowns else "UNBALANCED"
        lines.append(f"  balance: {n_eqs} equations, {n_unknowns} unknowns: {status}")
    for local in unbalanced_components(flat):
        lines.append(f"  warning: component {local.path} ({local.type}) is locally unbalanced: "
                     f"{local.equations} equations for {local.unknowns} unknowns, "
                     f"{local.provided} provided by its connectors and inputs")
    for warning in flat.warnings + list(filter(None, [open_connector_warning(flat)])):
        lines.append(f"  warning: {warning}")
    return "\n".join(lines)


_MAX_LISTED = 12


def open_connector_warning(flat: FlatSystem) -> str | None:
    """The connectors inside the model that nothing connects, whose flows are therefore zero
    (a free end, or a forgotten `connect`: an open circuit runs with no current), by name with
    their flow fields; None when there are none. The model's own open connectors are not listed
    (they make it partial, see model_check)."""
    top = {path for path, info in (flat.metadata.get("connectors") or {}).items() if info["owner"] == ""}
    flows: dict[str, list[str]] = {}
    for equation in flat.equations:
        if equation.kind == "unconnected_flow" and equation.residual.is_Symbol:
            connector, _, field = equation.residual.name.rpartition(".")
            if connector and connector not in top:
                flows.setdefault(connector, []).append(field)
    if not flows:
        return None
    listed = [f"{name} ({', '.join(fields)})" for name, fields in list(flows.items())[:_MAX_LISTED]]
    more = f" and {len(flows) - _MAX_LISTED} more" if len(flows) > _MAX_LISTED else ""
    count = f"{len(flows)} connector{'s are' if len(flows) > 1 else ' is'}"
    return (f"{count} connected to nothing, so {'their' if len(flows) > 1 else 'its'} flows are "
            f"zero (a free end, or a missing connect: an open circuit carries no current): "
            f"{', '.join(listed)}{more}")


def format_flat(flat: FlatSystem) -> str:
    lines = [f"model {flat.name}", "", "variables:"]
    for v in flat.variables:
        extras = []
        if v.units:
            extras.append(f"[{v.units}]")
        if v.start is not None:
            extras.append(f"start={v.start:g}")
        if v.guess is not None:
            extras.append(f"guess={v.guess:g}")
        if v.state_priority:
            extras.append(f"state_priority={v.state_priority}")
        lines.append(f"  {v.kind:15s} {v.name} {' '.join(extras)}".rstrip())
    lines += ["", "parameters:"]
    for p in flat.parameters:
        value = "?" if p.value is None else f"{p.value:g}"
        symbolic = p.default is not None and getattr(p.default, "free_symbols", None)
        default = f" = {p.default}" if symbolic else ""
        flag = "" if p.tunable else f" ({p.variability}, fixed)"
        lines.append(f"  {p.name} = {value}{default}{flag}")
    lines += ["", "equations:"]
    for e in flat.equations:
        lines.append(f"  0 = {e.residual}    # {e.kind} {e.origin.describe()}")
    if flat.initial_equations:
        lines += ["", "initial equations:"]
        for e in flat.initial_equations:
            lines.append(f"  0 = {e.residual}    # {e.origin.describe()}")
    if flat.guesses:
        lines += ["", "guesses:"]
        lines += [f"  {name} ~ {value:g}" for name, value in sorted(flat.guesses.items())]
    if flat.visual:
        lines += ["", "visual-only instances:"]
        lines += [f"  {path or '<model>'}: {info['type']}" for path, info in sorted(flat.visual.items())]
    unknowns = sum(1 for v in flat.variables if v.kind != INPUT)
    lines += ["", f"{len(flat.equations)} equations, {unknowns} unknowns"]
    return "\n".join(lines)
