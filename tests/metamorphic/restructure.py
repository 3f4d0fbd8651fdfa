"""Rewrites of the model's structure: subexpressions named and inlined, starts and guesses in
their other forms, declarations and equations reordered, variables and components renamed."""
from __future__ import annotations

import dataclasses

from compiler.syntax import ast
from tests.metamorphic import walk
from tests.metamorphic.forms import (PREFIX, Rewrite, declarations_by_name, fresh, is_scalar, pick,
                                     top_level_equations)

# ------------------------------------------------------------- auxiliary variables and inlining

def extract_subexpression(component, rng):
    """A scalar subexpression (a product, a call, a derivative) of an equation named by a new
    variable: `... f(x) ...` -> `mm_aux = f(x)` and `... mm_aux ...`. Not inside an exponent:
    `p ^ (1 / 4)` of a pressure p needs a constant exponent (the unit check), `p ^ mm_aux` is refused."""
    options = []
    for i in top_level_equations(component):
        r = component.relations[i]
        if r.initial:
            continue
        for side in ("lhs", "rhs"):
            nodes = list(walk.nodes(getattr(r, side), walk.arithmetic))
            in_exponents = {id(inner) for node in nodes if isinstance(node, ast.BinaryOp) and node.op == "^"
                            for inner in walk.nodes(node.right, walk.arithmetic)}
            for node in nodes:
                if isinstance(node, (ast.BinaryOp, ast.Call, ast.UnaryOp)) and id(node) not in in_exponents \
                        and is_scalar(node, component):
                    options.append((i, node))
    if not options:
        return None
    relations, declarations = list(component.relations), list(component.declarations)
    chosen = rng.sample(options, min(len(options), rng.choice((1, 1, 2, 3))))
    taken = set()
    for i, node in chosen:
        if i in taken:
            continue
        taken.add(i)
        name = fresh(dataclasses.replace(component, declarations=tuple(declarations)), "aux")
        ref = ast.Ref((ast.RefPart(name),))
        relations[i] = walk.transform(relations[i], lambda n, node=node, ref=ref: ref if n is node else n)
        declarations.append(ast.VariableDecl(name, ast.TypeSpec("Real")))
        relations.append(ast.Equation(ref, node))
    return Rewrite(dataclasses.replace(component, relations=tuple(relations), declarations=tuple(declarations)))


def _definition_of(component, name):
    """The index and expression of the only equation `name = expr` or `expr = name` (not initial)."""
    found = []
    for i in top_level_equations(component):
        r = component.relations[i]
        for this, other in ((r.lhs, r.rhs), (r.rhs, r.lhs)):
            if isinstance(this, ast.Ref) and len(this.parts) == 1 and this.parts[0].name == name \
                    and not this.parts[0].indices and not walk.refs_to(other, name):
                found.append((i, other))
    return found[0] if found else None


def inline_auxiliaries(component, rng):
    """A variable defined by one equation `v = expr` replaced by `(expr)` everywhere, its
    declaration and equation removed. Where `der(v)` appears, only if expr is a reference or a
    derivative (`v = der(x)`: der(v) becomes der(der(x)), a derivative written inline)."""
    declared = declarations_by_name(component)
    options = []
    for name, d in declared.items():
        if not isinstance(d, ast.VariableDecl) or d.type.dims or d.binding is not None or d.initial is not None \
                or d.causality is not None or d.type.modifications or d.condition is not None:
            continue
        if any(walk.refs_to(r, name) for r in component.relations
               if not isinstance(r, ast.Equation) or r.initial):
            continue                                  # in an initial equation, a guess, a loop
        found = _definition_of(component, name)
        if found is None:
            continue
        index, expr = found
        derived = any(isinstance(n, ast.Call) and n.function == "der" and walk.refs_to(n, name)
                      for r in component.relations for n in walk.nodes(r))
        if derived and not (isinstance(expr, ast.Ref) or (isinstance(expr, ast.Call) and expr.function == "der")):
            continue
        options.append((name, index, expr))
    if not options:
        return None
    name, index, expr = rng.choice(options)
    relations = [walk.replace_ref(r, name, expr) for i, r in enumerate(component.relations) if i != index]
    declarations = [d for d in component.declarations if d.name != name]
    return Rewrite(dataclasses.replace(component, relations=tuple(relations), declarations=tuple(declarations)))


# ------------------------------------------------------------------------- starts and guesses

def start_forms(component, rng):
    """A start given as `initial x = c` <-> as the declaration's `variable x::Real = initial c`."""
    declared = declarations_by_name(component)
    to_declaration = []
    for i in top_level_equations(component):
        r = component.relations[i]
        if r.initial and isinstance(r.lhs, ast.Ref) and len(r.lhs.parts) == 1 and not r.lhs.parts[0].indices:
            d = declared.get(r.lhs.parts[0].name)
            if isinstance(d, ast.VariableDecl) and d.initial is None and d.binding is None and not d.type.dims \
                    and all(isinstance(n, (ast.Number, ast.UnaryOp)) for n in walk.nodes(r.rhs)):
                to_declaration.append(i)
    to_equation = [d.name for d in component.declarations
                   if isinstance(d, ast.VariableDecl) and d.initial is not None and d.binding is None]
    if not to_declaration and not to_equation:
        return None
    relations, declarations = list(component.relations), {d.name: d for d in component.declarations}
    for i in pick(rng, to_declaration):
        r = relations[i]
        name = r.lhs.parts[0].name
        declarations[name] = dataclasses.replace(declarations[name], initial=r.rhs)
        relations[i] = None
    for name in pick(rng, to_equation):
        d = declarations[name]
        if d.initial is None:
            continue
        relations.append(ast.Equation(ast.Ref((ast.RefPart(name),)), d.initial, initial=True))
        declarations[name] = dataclasses.replace(d, initial=None)
    order = [d.name for d in component.declarations]
    return Rewrite(dataclasses.replace(component, relations=tuple(r for r in relations if r is not None),
                                       declarations=tuple(declarations[n] for n in order)))


def guess_forms(component, rng):
    """A guess given in the declaration `Real(guess = c)` <-> as a relation `guess x = c`."""
    moved = False
    relations, declarations = list(component.relations), list(component.declarations)
    for k, d in enumerate(declarations):
        if not isinstance(d, ast.VariableDecl) or d.type.dims or rng.random() < 0.5:
            continue
        guesses = [m for m in d.type.modifications if m.name == "guess" and m.value is not None]
        if len(guesses) == 1 and not guesses[0].nested:
            kept = tuple(m for m in d.type.modifications if m is not guesses[0])
            declarations[k] = dataclasses.replace(d, type=dataclasses.replace(d.type, modifications=kept))
            relations.append(ast.Guess(ast.Ref((ast.RefPart(d.name),)), guesses[0].value))
            moved = True
    by_name = {d.name: k for k, d in enumerate(declarations)}
    for i, r in enumerate(relations):
        if isinstance(r, ast.Guess) and len(r.target.parts) == 1 and not r.target.parts[0].indices \
                and r.target.parts[0].name in by_name and rng.random() < 0.5:
            k = by_name[r.target.parts[0].name]
            d = declarations[k]
            if isinstance(d, ast.VariableDecl) and not any(m.name == "guess" for m in d.type.modifications):
                spec = dataclasses.replace(d.type, modifications=d.type.modifications + (ast.Modification("guess", r.value),))
                declarations[k] = dataclasses.replace(d, type=spec)
                relations[i] = None
                moved = True
    if not moved:
        return None
    return Rewrite(dataclasses.replace(component, relations=tuple(r for r in relations if r is not None),
                                       declarations=tuple(declarations)))


# ------------------------------------------------------------------------- order and names

def reorder(component, rng):
    """Equations, declarations and components in another order (docs travel with their item)."""
    relations, declarations = list(component.relations), list(component.declarations)
    rng.shuffle(relations)
    rng.shuffle(declarations)
    new = dataclasses.replace(component, relations=tuple(relations), declarations=tuple(declarations))
    return Rewrite(new) if new != component else None


def rename(component, rng):
    """Variables and components the component declares renamed (`x` -> `mm_x`) in every
    expression of the definition; the runs are compared through the renaming."""
    candidates = [d.name for d in component.declarations if isinstance(d, (ast.VariableDecl, ast.ComponentDecl))]
    chosen = pick(rng, candidates, share=0.3)
    if not chosen:
        return None
    renamed = {}
    taken = {d.name for d in component.declarations}
    for old in chosen:
        new = PREFIX + old
        while new in taken:
            new = PREFIX + new
        taken.add(new)
        renamed[new] = old
        declarations = tuple(dataclasses.replace(d, name=new) if d.name == old else d for d in component.declarations)
        component = dataclasses.replace(component, declarations=declarations)
        component = dataclasses.replace(
            component,
            declarations=tuple(_rename_in_declaration(d, old, new) for d in component.declarations),
            relations=walk.rename_ref(component.relations, old, new))
    return Rewrite(component, renamed)


def _rename_in_declaration(d, old, new):
    """Values inside a declaration that may refer to `old` (defaults, bindings, modification
    values), never the names of the modifications themselves."""
    changes = {}
    for key in ("default", "binding", "initial", "condition", "value"):
        value = getattr(d, key, None)
        if value is not None:
            changes[key] = walk.rename_ref(value, old, new)
    if isinstance(d, ast.ComponentDecl):
        changes["modifications"] = tuple(_rename_modification(m, old, new) for m in d.modifications)
    return dataclasses.replace(d, **changes) if changes else d


def _rename_modification(m, old, new):
    value = walk.rename_ref(m.value, old, new) if m.value is not None else None
    return dataclasses.replace(m, value=value, nested=tuple(_rename_modification(n, old, new) for n in m.nested))
