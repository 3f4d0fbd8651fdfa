"""The parameters a reduced system uses, closed over their bindings, in dependency order."""
from __future__ import annotations

import sympy

from compiler.model.flat import FlatSystem
from compiler.model.parameter_checks import parameter_closure
from compiler.model.symbols import free_symbols
from compiler.structure.reduced import ParameterInfo


def used_parameters(flat: FlatSystem, expressions: list[sympy.Expr]) -> list[ParameterInfo]:
    by_symbol = {sympy.Symbol(p.name): p for p in flat.parameters}
    direct = (s.name for e in expressions for s in free_symbols(e) if s in by_symbol)
    used = {sympy.Symbol(name) for name in parameter_closure(flat, direct)}
    ordered: list[ParameterInfo] = []
    placed: set[sympy.Symbol] = set()

    def place(s: sympy.Symbol) -> None:
        stack = [(s, False)]
        while stack:
            sym, ready = stack.pop()
            if sym in placed:
                continue
            p = by_symbol[sym]
            deps = sorted((d for d in (p.default.free_symbols if p.default is not None else ())
                           if d in by_symbol and d not in placed), key=lambda d: d.name)
            if ready or not deps:
                placed.add(sym)
                binding = p.default if p.default is not None and p.default.free_symbols else None
                # no value (declared without one): NaN until the caller gives one (-p name=VALUE)
                value = float(p.value) if p.value is not None else float("nan")
                ordered.append(ParameterInfo(p.name, value, binding, p.tunable))
            else:
                stack.append((sym, True))
                stack.extend((d, False) for d in deps)

    for s in sorted(used, key=lambda s: s.name):
        place(s)
    return ordered
