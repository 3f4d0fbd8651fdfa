"""Alias and constant elimination: `a = b`, `a = -b`, `a = c`, `a = b + c` (c constant or parameter
expression) leave the system; one representative per alias set stays.

Runs to a fixpoint, because substituting constants creates new aliases
(`r0 = R(0) * r` becomes `r0 = r`). Derivatives follow their variables: eliminating `a = s*b + c`
maps `der(a)` to `s*der(b)`, and `a = c` maps `der(a)` to 0.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy

from compiler.model.flat import TIME, Equation, FlatSystem, der_name
from compiler.model.symbols import free_symbols


@dataclass
class AliasResult:
    equations: list[Equation]                   # what is left, substituted
    kept: list[str]                             # variables still unknown
    eliminated: dict[str, sympy.Expr]           # variable -> expression in kept variables/parameters
    derivatives: dict[str, str]                 # der name -> variable name, for the kept variables
    derivative_mapping: dict[sympy.Symbol, sympy.Expr] = field(default_factory=dict)  # der(eliminated) -> expr
    removed_equations: int = 0
    passes: int = 0


def _preference(var, has_der: bool):
    """Sort key: the best representative first (state candidate, hinted, short user-visible name)."""
    return (0 if has_der else 1, -var.state_priority, var.name.count("."), len(var.name), var.name)


def eliminate_aliases(flat: FlatSystem) -> AliasResult:
    state = _Aliasing.of(flat)
    equations = list(flat.equations)
    residuals = [eq.residual for eq in equations]
    alive, passes = state.run(residuals)
    resolved = {state.var_symbols[s]: _resolve(e, state.mapping, {}) for s, e in state.mapping.items()}
    kept_equations = [Equation(_resolve(residuals[i], state.mapping, state.derivative_mapping),
                               eq.origin, eq.kind, eq.description)
                      for i, eq in enumerate(equations) if alive[i]]
    eliminated_names = set(resolved)
    kept = [v.name for v in flat.variables if v.name not in eliminated_names]
    derivatives = {d: v for d, v in dict(flat.derivatives).items() if v not in eliminated_names}
    derivatives.update({d: v for d, v in state.new_derivatives.items() if v not in eliminated_names})
    return AliasResult(kept_equations, kept, resolved, derivatives, state.derivative_mapping,
                       removed_equations=len(equations) - len(kept_equations), passes=passes)


@dataclass
class _Aliasing:
    """What the elimination knows while it runs: the model's variables and parameters, which
    variables have derivatives, and what has been eliminated so far (symbol -> expression, which
    may name other eliminated symbols until resolved)."""
    variables: dict
    var_symbols: dict[sympy.Symbol, str]
    has_der: dict[str, bool]
    parameter_symbols: set
    mapping: dict[sympy.Symbol, sympy.Expr] = field(default_factory=dict)
    derivative_mapping: dict[sympy.Symbol, sympy.Expr] = field(default_factory=dict)
    new_derivatives: dict[str, str] = field(default_factory=dict)

    @classmethod
    def of(cls, flat: FlatSystem) -> "_Aliasing":
        variables = {v.name: v for v in flat.variables}
        has_der = {name: False for name in variables}
        for var in dict(flat.derivatives).values():
            has_der[var] = True
        return cls(variables, {sympy.Symbol(n): n for n in variables}, has_der,
                   {sympy.Symbol(p.name) for p in flat.parameters})

    def run(self, residuals: list) -> tuple[list[bool], int]:
        """Eliminate until a pass finds nothing (substituting creates new aliases); `residuals` are
        updated in place. Returns which equations are left and the number of passes."""
        alive = [True] * len(residuals)
        rejected = [False] * len(residuals)
        passes, changed = 0, True
        while changed:
            changed = False
            passes += 1
            for i, residual in enumerate(residuals):
                if not alive[i]:
                    continue
                symbols = free_symbols(residual)
                if symbols & self.mapping.keys() or symbols & self.derivative_mapping.keys():
                    residual = _resolve(residual, self.mapping, self.derivative_mapping)
                    residuals[i] = residual
                elif rejected[i]:
                    continue            # unchanged since classify said no: it says no again
                found = self.classify(residual)
                if found is None:
                    rejected[i] = True
                    continue
                self.eliminate(*found)
                alive[i] = False
                changed = True
        return alive, passes

    def classify(self, residual: sympy.Expr):
        """(var_symbol, expression) if `residual` says var = expression with no other unknowns
        than (at most) one aliased variable; else None."""
        symbols = free_symbols(residual)
        if TIME in symbols:
            return None
        unknowns = [s for s in symbols if s not in self.parameter_symbols]
        if not unknowns or len(unknowns) > 2 or any(s not in self.var_symbols for s in unknowns):
            return None
        if not residual.is_Add and len(unknowns) == 1 and residual == unknowns[0]:
            return unknowns[0], sympy.Integer(0)
        found = _linear_terms(residual, unknowns) or _number_coefficients(residual, unknowns)
        if found is None:
            return None
        coefficients, rest = found
        if free_symbols(rest) & set(unknowns) or not free_symbols(rest) <= self.parameter_symbols:
            return None
        if len(unknowns) == 1:
            s = unknowns[0]
            return s, _divide(-rest, coefficients[s])
        a, b = unknowns
        if abs(coefficients[a]) != abs(coefficients[b]):
            return None
        # pick which one to eliminate: the worse representative
        key_a = _preference(self.variables[self.var_symbols[a]], self.has_der[self.var_symbols[a]])
        key_b = _preference(self.variables[self.var_symbols[b]], self.has_der[self.var_symbols[b]])
        elim, keep = (a, b) if key_a > key_b else (b, a)
        return elim, _divide(-_add(_multiply(coefficients[keep], keep), rest), coefficients[elim])

    def eliminate(self, sym: sympy.Symbol, expr: sympy.Expr) -> None:
        """`sym` := `expr`; its derivative follows: der(sym) is 0, or s * der(kept variable)."""
        self.mapping[sym] = expr
        name = self.var_symbols[sym]
        if not self.has_der[name]:
            return
        dsym = sympy.Symbol(der_name(name))
        keep_vars = [s for s in free_symbols(expr) if s in self.var_symbols]
        if not keep_vars:
            self.derivative_mapping[dsym] = sympy.Integer(0)
            return
        (keep,) = keep_vars
        keep_name = self.var_symbols[keep]
        if not self.has_der[keep_name]:
            self.has_der[keep_name] = True
            self.new_derivatives[der_name(keep_name)] = keep_name
        self.derivative_mapping[dsym] = (sympy.S.One if expr is keep else expr.coeff(keep)) \
            * sympy.Symbol(der_name(keep_name))


def _number_coefficients(residual: sympy.Expr, unknowns: list[sympy.Symbol]):
    """(coefficients, rest) where each unknown's coefficient in `residual` is a nonzero number
    (the general path of classify, through `coeff`); None otherwise."""
    coefficients = {}
    rest = residual
    for s in unknowns:
        c = residual.coeff(s)
        if not c.is_number or c == 0:
            return None
        coefficients[s] = c
        rest = rest - c * s
    rest = sympy.expand(rest) if free_symbols(rest) & set(unknowns) else rest
    return coefficients, rest


def _resolve(expr: sympy.Expr, mapping: dict, derivative_mapping: dict) -> sympy.Expr:
    """Substitute eliminated symbols until none is left (chains are short)."""
    for _ in range(1000):
        symbols = free_symbols(expr)
        hit = {s: mapping[s] for s in symbols if s in mapping}
        hit.update({s: derivative_mapping[s] for s in symbols if s in derivative_mapping})
        if not hit:
            return expr
        expr = expr.xreplace(hit)
    raise RuntimeError("alias chain does not terminate")


# a * b, a + b and a / b where sympy would drop the identity (Mul and Add leave out every argument
# that is S.One or S.Zero, and a one-argument Mul or Add is that argument): the same objects,
# without the constructor calls.
def _multiply(a, b):
    return b if a is sympy.S.One else a * b


def _add(a, b):
    return a if b is sympy.S.Zero else a + b


def _divide(a, b):
    return a if b is sympy.S.One else a / b


def _linear_terms(residual: sympy.Expr, unknowns: list[sympy.Symbol]):
    """The common case of classify without `coeff`: `residual` is an Add in which every unknown
    is one whole term `s` or `number * s` and occurs nowhere else. Returns (coefficients, rest)
    equal to what the general path computes (`rest` is the Add of the other terms: the same
    canonical sum as `residual - c * s`), or None for anything else."""
    if not residual.is_Add:
        return None
    coefficients = {}
    others = []
    for term in residual.args:
        if term.is_Symbol and term in unknowns:
            coefficient, symbol = sympy.S.One, term
        elif term.is_Mul and len(term.args) == 2 and term.args[0].is_Number and term.args[1] in unknowns:
            coefficient, symbol = term.args
        else:
            if not free_symbols(term).isdisjoint(unknowns):
                return None
            others.append(term)
            continue
        if symbol in coefficients or coefficient == 0:
            return None
        coefficients[symbol] = coefficient
    if len(coefficients) != len(unknowns):
        return None
    return coefficients, sympy.Add(*others)
