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
from compiler.model.flat import INPUT, FlatSystem
from compiler.structure.graph.dulmage_mendelsohn import dulmage_mendelsohn

MAX_NOTES = 12


def span_from_text(text: str | None) -> Span | None:
    if not text:
        return None
    try:
        file, line, column = text.rsplit(":", 2)
        return Span(file, int(line), int(column), int(line), int(column))
    except ValueError:
        return None


def unknown_names(flat: FlatSystem, closed: bool = False) -> list[str]:
    """The unknowns the model's equations must determine. A top-level input is given from outside
    when the model is used as a component; a `closed` model (simulated on its own) must determine
    it too."""
    return [v.name for v in flat.variables if closed or v.kind != INPUT]


def incidence(flat: FlatSystem, equations=None, closed: bool = False
              ) -> tuple[list[str], list[list[int]]]:
    """Unknown names and, per equation, the sorted unknown indices it contains (der(x) -> x)."""
    names = unknown_names(flat, closed)
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


def check_balance(flat: FlatSystem, structural: bool = True, closed: bool = False) -> None:
    """Raise a located DyadError if the model is unbalanced (or, with `structural`, structurally
    singular: no complete matching of equations to unknowns). `closed`: top-level inputs are
    unknowns too (the model is simulated on its own, nobody drives them)."""
    names, rows = incidence(flat, closed=closed)
    n_eqs, n_vars = len(rows), len(names)
    if n_eqs == n_vars and not structural:
        return
    dm = dulmage_mendelsohn(n_eqs, n_vars, rows)
    if n_eqs == n_vars and dm.is_square_and_nonsingular:
        return
    raise _imbalance_error(flat, names, dm, n_eqs, n_vars)


def _imbalance_error(flat: FlatSystem, names: list[str], dm, n_eqs: int, n_vars: int) -> DyadError:
    """Lead with the component whose own count is off (Modelica's local balance): the global
    matching can only point at some equation of the whole system, often an unrelated one."""
    if n_eqs != n_vars:
        summary = f"model `{flat.name}` is unbalanced: {n_eqs} equation(s) for {n_vars} unknown(s)"
    else:
        summary = (f"model `{flat.name}` is structurally singular: {n_eqs} equations and "
                   f"unknowns, but they cannot be matched one to one")
    model_span = span_from_text(flat.metadata.get("model_span"))
    local = unbalanced_components(flat)
    notes: list[Note] = []
    open_notes = _open_connector_notes(flat, [names[v] for v in dm.underdetermined_vars])
    if local:
        culprits = ", ".join(f"`{b.path}` ({b.type})" for b in local[:3]) + (", ..." if len(local) > 3 else "")
        headline = f"{summary}: {'component' if len(local) == 1 else 'components'} {culprits} " \
                   f"{'is' if len(local) == 1 else 'are'} unbalanced on {'its' if len(local) == 1 else 'their'} own"
        notes += [Note(f"component `{b.path}` ({b.type}) has {describe(b)}", b.span)
                  for b in local[:MAX_NOTES]]
        inside = [b.path for b in local]
        keep = lambda path: any(path == c or path.startswith(c + ".") for c in inside)  # noqa: E731
    else:
        headline = summary
        if open_notes and n_eqs == n_vars:
            headline += f": {len(open_notes)} connector(s) are left unconnected"
        keep = lambda path: True  # noqa: E731
    notes += _variable_notes(flat, names, dm, keep)
    notes += _equation_notes(flat, dm, keep)
    notes += open_notes
    if local:
        hint = ("add the missing equations to (or remove the extra ones from) the component "
                "named first: it is unbalanced on its own, whatever it is connected to")
    elif dm.unmatched_vars:
        hint = "add equations for the variables listed, or connect the connectors they belong to"
    else:
        hint = "remove the redundant equations listed"
    return DyadError(headline, model_span, hint=hint, notes=notes)


def describe(b: LocalBalance) -> str:
    needed = b.unknowns - b.provided
    given = (f"; {b.provided} more, the flows of its connectors and its inputs, are given by its "
             f"connections" if b.provided else "")
    return f"{b.equations} equation(s) for {needed} unknown(s){given}"


def _variable_notes(flat: FlatSystem, names: list[str], dm, keep) -> list[Note]:
    by_name = {v.name: v for v in flat.variables}
    free = [names[v] for v in dm.unmatched_vars if keep(by_name[names[v]].origin.path)]
    notes = [Note(f"no equation determines `{name}`", by_name[name].origin.span)
             for name in free[:MAX_NOTES]]
    if len(free) > MAX_NOTES:
        notes.append(Note(f"... and {len(free) - MAX_NOTES} more variable(s) without equation"))
    return notes


def _equation_notes(flat: FlatSystem, dm, keep) -> list[Note]:
    extra = [e for e in dm.unmatched_eqs if keep(flat.equations[e].origin.path)]
    notes = []
    for e in extra[:MAX_NOTES]:
        equation = flat.equations[e]
        where = equation.origin.path or "the model"
        notes.append(Note(f"equation `{equation.residual} = 0` in {where} has no unknown left "
                          f"to determine", equation.origin.span))
    if len(extra) > MAX_NOTES:
        notes.append(Note(f"... and {len(extra) - MAX_NOTES} more equation(s) without unknown"))
    return notes


def _open_connector_notes(flat: FlatSystem, undetermined: list[str]) -> list[Note]:
    """An unconnected connector gets zero flows, so nothing determines its potentials: say so."""
    undetermined_set = set(undetermined)
    components = flat.metadata.get("components", {})
    notes = []
    for path, info in flat.metadata.get("connectors", {}).items():
        if info["connected"] or info["owner"] == "":
            continue
        loose = [n for names in info["potentials"].values() for n in names if n in undetermined_set]
        if loose:
            owner_span = components.get(info["owner"], {}).get("span") or info["span"]
            notes.append(Note(f"connector `{path}` ({info['type']}) is not connected: its flows are "
                              f"zero and nothing determines {', '.join(f'`{n}`' for n in loose)}",
                              span_from_text(owner_span)))
    return notes


def balance_summary(flat: FlatSystem) -> tuple[int, int]:
    return len(flat.equations), len(unknown_names(flat))
