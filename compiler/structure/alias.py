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
    variables = {v.name: v for v in flat.variables}
    var_symbols = {sympy.Symbol(n): n for n in variables}
    der_of = dict(flat.derivatives)                                  # der name -> var name
    has_der = {name: False for name in variables}
    for var in der_of.values():
        has_der[var] = True
    parameter_symbols = {sympy.Symbol(p.name) for p in flat.parameters}

    mapping: dict[sympy.Symbol, sympy.Expr] = {}     # eliminated symbol -> expr (may chain)
    equations = list(flat.equations)
    residuals = [eq.residual for eq in equations]
    alive = [True] * len(equations)
    rejected = [False] * len(equations)

    def is_constant(expr: sympy.Expr) -> bool:
        return all(s in parameter_symbols for s in free_symbols(expr))

    def classify(residual: sympy.Expr):
        """Return (var_symbol, expression) if residual says var = expression with no other unknowns
        than (at most) one aliased variable; else None."""
        symbols = free_symbols(residual)
        if TIME in symbols:
            return None
        unknowns = [s for s in symbols if s not in parameter_symbols]
        if not unknowns or len(unknowns) > 2 or any(s not in var_symbols for s in unknowns):
            return None
        if not residual.is_Add and len(unknowns) == 1 and residual == unknowns[0]:
            return unknowns[0], sympy.Integer(0)
        found = _linear_terms(residual, unknowns)
        if found is not None:
            coefficients, rest = found
        else:
            coefficients = {}
            rest = residual
            for s in unknowns:
                c = residual.coeff(s)
                if not c.is_number or c == 0:
                    return None
                coefficients[s] = c
                rest = rest - c * s
            rest = sympy.expand(rest) if free_symbols(rest) & set(unknowns) else rest
        if free_symbols(rest) & set(unknowns) or not is_constant(rest):
            return None
        if len(unknowns) == 1:
            s = unknowns[0]
            return s, _divide(-rest, coefficients[s])
        a, b = unknowns
        if abs(coefficients[a]) != abs(coefficients[b]):
            return None
        # pick which one to eliminate: the worse representative
        key_a = _preference(variables[var_symbols[a]], has_der[var_symbols[a]])
        key_b = _preference(variables[var_symbols[b]], has_der[var_symbols[b]])
        elim, keep = (a, b) if key_a > key_b else (b, a)
        return elim, _divide(-_add(_multiply(coefficients[keep], keep), rest), coefficients[elim])

    derivative_mapping: dict[sympy.Symbol, sympy.Expr] = {}
    new_derivatives: dict[str, str] = {}

    def eliminate(sym: sympy.Symbol, expr: sympy.Expr) -> None:
        mapping[sym] = expr
        name = var_symbols[sym]
        if has_der[name]:
            dsym = sympy.Symbol(der_name(name))
            keep_vars = [s for s in free_symbols(expr) if s in var_symbols]
            if not keep_vars:
                derivative_mapping[dsym] = sympy.Integer(0)
            else:
                (keep,) = keep_vars
                keep_name = var_symbols[keep]
                keep_der = sympy.Symbol(der_name(keep_name))
                if not has_der[keep_name]:
                    has_der[keep_name] = True
                    new_derivatives[der_name(keep_name)] = keep_name
                derivative_mapping[dsym] = (sympy.S.One if expr is keep else expr.coeff(keep)) * keep_der

    passes = 0
    changed = True
    while changed:
        changed = False
        passes += 1
        for i, residual in enumerate(residuals):
            if not alive[i]:
                continue
            symbols = free_symbols(residual)
            if symbols & mapping.keys() or symbols & derivative_mapping.keys():
                residual = _resolve(residual, mapping, derivative_mapping)
                residuals[i] = residual
            elif rejected[i]:
                continue            # unchanged since classify said no: it says no again
            found = classify(residual)
            if found is None:
                rejected[i] = True
                continue
            sym, expr = found
            eliminate(sym, expr)
            alive[i] = False
            changed = True

    resolved = {var_symbols[s]: _resolve(e, mapping, {}) for s, e in mapping.items()}
    kept_equations = []
    for i, eq in enumerate(equations):
        if alive[i]:
            kept_equations.append(Equation(_resolve(residuals[i], mapping, derivative_mapping),
                                           eq.origin, eq.kind, eq.description))
    eliminated_names = set(resolved)
    kept = [v.name for v in flat.variables if v.name not in eliminated_names]
    derivatives = {d: v for d, v in der_of.items() if v not in eliminated_names}
    derivatives.update({d: v for d, v in new_derivatives.items() if v not in eliminated_names})
    return AliasResult(kept_equations, kept, resolved, derivatives, derivative_mapping,
                       removed_equations=len(equations) - len(kept_equations), passes=passes)


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
