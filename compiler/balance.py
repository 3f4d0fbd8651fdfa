"""Balance check: as many equations as unknowns, globally and per component instance.

Per component (Modelica's "locally balanced" idea): the equations written inside a component's
subtree must equal its unknowns minus what its environment provides, namely one equation per
flow variable of its own connectors (the connect-set flow sums and unconnected-flow equations
live outside) and its input signals. When the model is unbalanced, the error names the innermost
locally unbalanced components and, from a maximum matching on the incidence (der(x) counts as x),
the variables no equation determines and the equations left without an unknown.
"""
from __future__ import annotations

from dataclasses import dataclass

from compiler.errors import DyadError, Note, Span
from compiler.flat import INPUT, FlatSystem
from compiler.structure.graph.matching import maximum_matching

MAX_NOTES = 12


def span_from_text(text: str | None) -> Span | None:
    if not text:
        return None
    try:
        file, line, column = text.rsplit(":", 2)
        return Span(file, int(line), int(column), int(line), int(column))
    except ValueError:
        return None


def unknown_names(flat: FlatSystem) -> list[str]:
    return [v.name for v in flat.variables if v.kind != INPUT]


def incidence(flat: FlatSystem, equations=None) -> tuple[list[str], list[list[int]]]:
    """Unknown names and, per equation, the sorted unknown indices it contains (der(x) -> x)."""
    names = unknown_names(flat)
    index = {name: i for i, name in enumerate(names)}

    def base(name: str) -> str:
        seen = 0
        while name in flat.derivatives and seen < 100:
            name = flat.derivatives[name]
            seen += 1
        return name

    rows = []
    for equation in (flat.equations if equations is None else equations):
        cols = {index[b] for sym in equation.residual.free_symbols
                if (b := base(sym.name)) in index}
        rows.append(sorted(cols))
    return names, rows


@dataclass
class LocalBalance:
    path: str
    type: str
    equations: int
    unknowns: int
    provided: int              # flows of its own connectors + its inputs
    span: Span | None

    @property
    def difference(self) -> int:
        return self.equations - (self.unknowns - self.provided)


def _ancestors(path: str) -> list[str]:
    if not path:
        return [""]
    parts = path.split(".")
    return [""] + [".".join(parts[:k]) for k in range(1, len(parts) + 1)]


def component_balance(flat: FlatSystem) -> list[LocalBalance]:
    """Local balance of every component instance (top model included, path '')."""
    components = flat.metadata.get("components", {})
    eq_count: dict[str, int] = {}
    var_count: dict[str, int] = {}
    for equation in flat.equations:
        for path in _ancestors(equation.origin.path):
            eq_count[path] = eq_count.get(path, 0) + 1
    for variable in flat.variables:
        if variable.kind == INPUT:
            continue
        for path in _ancestors(variable.origin.path):
            var_count[path] = var_count.get(path, 0) + 1
    out = []
    for path, info in components.items():
        provided = 0 if path == "" else len(info["connector_flows"]) + len(info["inputs"])
        out.append(LocalBalance(path, info["type"], eq_count.get(path, 0), var_count.get(path, 0),
                                provided, span_from_text(info.get("span"))))
    return out


def unbalanced_components(flat: FlatSystem) -> list[LocalBalance]:
    """The innermost locally unbalanced component instances (not the top model)."""
    bad = [b for b in component_balance(flat) if b.path and b.difference != 0]
    bad_paths = {b.path for b in bad}
    innermost = [b for b in bad
                 if not any(p != b.path and p.startswith(b.path + ".") for p in bad_paths)]
    return sorted(innermost, key=lambda b: b.path)


def check_balance(flat: FlatSystem, structural: bool = True) -> None:
    """Raise a located DyadError if the model is unbalanced (or, with `structural`, structurally
    singular: no complete matching of equations to unknowns)."""
    names, rows = incidence(flat)
    n_eqs, n_vars = len(rows), len(names)
    if n_eqs == n_vars and not structural:
        return
    eq_to_var, var_to_eq = maximum_matching(n_eqs, n_vars, rows)
    free_vars = [names[v] for v in range(n_vars) if var_to_eq[v] == -1]
    extra_eqs = [e for e in range(n_eqs) if eq_to_var[e] == -1]
    if n_eqs == n_vars and not free_vars:
        return
    if n_eqs != n_vars:
        headline = (f"model `{flat.name}` is unbalanced: {n_eqs} equation(s) for {n_vars} "
                    f"unknown(s)")
    else:
        headline = (f"model `{flat.name}` is structurally singular: {n_eqs} equations and "
                    f"unknowns, but they cannot be matched one to one")
    notes: list[Note] = []
    local = unbalanced_components(flat)
    for b in local[:MAX_NOTES]:
        notes.append(Note(f"component `{b.path}` ({b.type}) has {b.equations} equation(s) for "
                          f"{b.unknowns} unknown(s) ({b.provided} provided by its connectors and "
                          f"inputs)", b.span))
    by_name = {v.name: v for v in flat.variables}
    for name in free_vars[:MAX_NOTES]:
        variable = by_name[name]
        notes.append(Note(f"no equation determines `{name}`", variable.origin.span))
    if len(free_vars) > MAX_NOTES:
        notes.append(Note(f"... and {len(free_vars) - MAX_NOTES} more variable(s) without equation"))
    for e in extra_eqs[:MAX_NOTES]:
        equation = flat.equations[e]
        where = equation.origin.path or "the model"
        notes.append(Note(f"equation `{equation.residual} = 0` in {where} has no unknown left "
                          f"to determine", equation.origin.span))
    if len(extra_eqs) > MAX_NOTES:
        notes.append(Note(f"... and {len(extra_eqs) - MAX_NOTES} more equation(s) without unknown"))
    if local:
        hint = "look at the components listed first: each is unbalanced on its own"
    elif free_vars:
        hint = "add equations for the variables listed, or connect the connectors they belong to"
    else:
        hint = "remove the redundant equations listed"
    raise DyadError(headline, span_from_text(flat.metadata.get("model_span")), hint=hint,
                    notes=notes)


def balance_summary(flat: FlatSystem) -> tuple[int, int]:
    return len(flat.equations), len(unknown_names(flat))
