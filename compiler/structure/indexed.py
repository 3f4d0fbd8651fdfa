"""An equation system with integer-indexed unknowns: the bridge between sympy and the graph passes.

Unknown `i` is `names[i]`, its sympy symbol `symbols[i]`; `var_to_diff[i]` is the unknown that is
its time derivative (or -1); `eq_to_diff[e]` is the equation that is the time derivative of
equation `e` (or -1). `incidence[e]` lists the unknowns equation `e` contains, sorted.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy

from compiler.model.flat import TIME, Origin, der_name
from compiler.model.symbols import free_symbols
from compiler.structure.differentiate import partial


@dataclass
class IndexedSystem:
    names: list[str]
    var_to_diff: list[int]
    equations: list[sympy.Expr]
    origins: list[Origin]
    eq_to_diff: list[int]
    incidence: list[list[int]] = field(default_factory=list)
    symbols: list[sympy.Symbol] = field(default_factory=list)
    index_of: dict[sympy.Symbol, int] = field(default_factory=dict)

    def __post_init__(self):
        if not self.symbols:
            self.symbols = [sympy.Symbol(n) for n in self.names]
        self.index_of = {s: i for i, s in enumerate(self.symbols)}
        if not self.incidence:
            self.incidence = [self.incidence_of(e) for e in self.equations]

    @property
    def n_eqs(self) -> int:
        return len(self.equations)

    @property
    def n_vars(self) -> int:
        return len(self.names)

    def incidence_of(self, expr: sympy.Expr) -> list[int]:
        return sorted(self.index_of[s] for s in free_symbols(expr) if s in self.index_of)

    def diff_to_var(self) -> list[int]:
        inverse = [-1] * self.n_vars
        for v, d in enumerate(self.var_to_diff):
            if d >= 0:
                inverse[d] = v
        return inverse

    def diff_to_eq(self) -> list[int]:
        inverse = [-1] * self.n_eqs
        for e, d in enumerate(self.eq_to_diff):
            if d >= 0:
                inverse[d] = e
        return inverse

    def add_variable(self, name: str) -> int:
        index = len(self.names)
        self.names.append(name)
        sym = sympy.Symbol(name)
        self.symbols.append(sym)
        self.index_of[sym] = index
        self.var_to_diff.append(-1)
        return index

    def derivative_of_variable(self, v: int) -> int:
        """The unknown that is der(v), created on first use."""
        if self.var_to_diff[v] < 0:
            self.var_to_diff[v] = self.add_variable(der_name(self.names[v]))
        return self.var_to_diff[v]

    def time_derivative(self, expr: sympy.Expr) -> sympy.Expr:
        """d/dt by the chain rule; parameters are constant, unknowns get their der() unknowns."""
        terms = []
        for s in sorted(free_symbols(expr), key=lambda s: s.name):
            if s == TIME:
                terms.append(partial(expr, s))
            elif s in self.index_of:
                d = self.derivative_of_variable(self.index_of[s])
                coefficient = partial(expr, s)
                if coefficient is sympy.S.One:          # 1 * der(s) is der(s) (Mul drops the 1)
                    terms.append(self.symbols[d])
                elif coefficient != 0:
                    terms.append(coefficient * self.symbols[d])
        return sympy.Add(*terms)


def build_indexed(variable_names: list[str], derivatives: dict[str, str],
                  equations: list[sympy.Expr], origins: list[Origin]) -> IndexedSystem:
    """Unknowns: the variables, then every derivative that occurs (der(der(x)) after der(x))."""
    names = list(variable_names)
    known = set(names)
    pending = sorted(derivatives, key=lambda d: (d.count("der("), d))
    for d in pending:
        if d not in known:
            names.append(d)
            known.add(d)
    index = {n: i for i, n in enumerate(names)}
    var_to_diff = [-1] * len(names)
    for d, base in derivatives.items():
        if base in index:
            var_to_diff[index[base]] = index[d]
    return IndexedSystem(names, var_to_diff, list(equations), list(origins), [-1] * len(equations))
