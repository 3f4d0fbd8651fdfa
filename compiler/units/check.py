"""The unit check of an instance tree (issue 26): every equation, every parameter and variable
binding (declaration defaults and modifiers such as `R = Lm`), the values of `initial`, `guess`,
`start`, `min` and `max`, and every connect (each potential and flow of the two ends), located
at the source before flattening loses it. `check_units(model)` returns the findings; what to do
with them (an error, warnings, nothing) is report.py's.
"""
from __future__ import annotations

from typing import Any

from compiler.errors import DyadError
from compiler.model.expressions import EvalScope, Mode, evaluate, iteration_values, structural_bool, \
    switch_branch
from compiler.model.flatten_connect import DISABLED, SignalElements, resolve_connector
from compiler.syntax import ast
from compiler.units.constraints import DIMENSIONLESS, FREE, Dim, Solver
from compiler.units.expressions import ExpressionUnits
from compiler.units.findings import Finding, declaration_finding, mismatch_finding
from compiler.units.system import UnitError, is_offset_unit, parse_unit

ATTRIBUTE_VALUES = ("initial", "guess", "start", "min", "max")


def check_units(model: Any) -> list[Finding]:
    """The unit findings of an instantiated model (compiler.model.instantiate.Model), sorted by
    source position; one per place, naming every instance that uses it."""
    return UnitCheck(model).run()


class UnitCheck:
    def __init__(self, model: Any):
        self.model = model
        self.solver = Solver()
        self.dims: dict[int, Any] = {}
        self.problems: list[Finding] = []
        self.units = ExpressionUnits(self.declared, self.solver.require)

    def run(self) -> list[Finding]:
        root = self.model.root
        for node in root.walk():
            if node is not root and node.kind == "component" and self.model.is_visual_only(node.resolved):
                continue
            self.units.at(node)
            for variable in node.variables.values():
                self.variable(variable)
            for parameter in node.parameters.values():
                self.parameter(parameter)
            for relation, scope in node.relations:
                self.relation(relation, scope)
        found = self.problems + [mismatch_finding(m) for m in self.solver.solve()]
        return merge(found)

    # ------------------------------------------------------------------------ declarations

    def declared(self, target: Any, ref: Any = None) -> Any:
        """The Dim of a parameter or variable instance: its declared unit, or an inference
        variable of its own when it declares none (`::Real`)."""
        key = id(target)
        found = self.dims.get(key)
        if found is None:
            found = self.dims[key] = self.declaration_dim(target)
        if type(found) is str:              # an offset unit: a value only, never in an equation
            if ref is None:
                return None                 # its own default or attribute value: a value
            self.problems.append(declaration_finding(
                f"`{target.path}` is declared in `{found}`, a unit with an offset, and cannot be "
                f"used in an equation", getattr(ref, "span", None) or target.span, self.units,
                hint=f"declare `{target.name}` in K (type Temperature) and give values in {found} "
                     f"with -p, which converts them as absolute temperatures",
                declared=target.span))
            return None
        return found

    def declaration_dim(self, target: Any) -> Any:
        primitive = target.type.primitive
        if primitive == "String":
            return None
        if primitive == "Boolean":
            return DIMENSIONLESS
        attribute = target.attributes.get("units")
        if attribute is None:
            return self.solver.variable(target.path)
        text = _unit_text(attribute)
        if text is None:
            return None
        if is_offset_unit(text):
            return text
        try:
            return Dim(parse_unit(text), (), text, True)
        except UnitError as err:
            self.problems.append(declaration_finding(
                f"the unit of `{target.path}` cannot be read: {err}",
                getattr(attribute[0], "span", None) or target.span, self.units,
                hint="write units as in the library, e.g. m, N.m, m/s2, kg.m2, 1/min"))
            return None

    def variable(self, variable: Any) -> None:
        own = None
        if variable.binding is not None:
            expr, scope, span = variable.binding
            own = self.declared(variable)
            self.bind(own, expr, scope, variable, "binding")
        for name in ATTRIBUTE_VALUES:
            if name in variable.attributes:
                expr, scope = variable.attributes[name]
                own = self.declared(variable) if own is None else own
                self.bind(own, expr, scope, variable, name)

    def parameter(self, parameter: Any) -> None:
        if parameter.is_string:
            return
        own = None
        if parameter.binding is not None:
            expr, scope = parameter.binding
            own = self.declared(parameter)
            self.bind(own, expr, scope, parameter, "binding")
        for name in ("min", "max"):
            if name in parameter.attributes:
                expr, scope = parameter.attributes[name]
                own = self.declared(parameter) if own is None else own
                self.bind(own, expr, scope, parameter, name)

    def bind(self, own: Any, expr: Any, scope: EvalScope, target: Any, what: str) -> None:
        """`target = expr` (a default, a modifier, an attribute value), located at `expr`."""
        self.units.at(scope.node)
        value = self.units.of(expr, scope)
        label = f"`{target.name}`" if what == "binding" else f"the {what} of `{target.name}`"
        site = self.units.site("binding", expr, None, ("its value", label))
        site.declared = target.span
        site.path, site.instance = target.node.path, target.node.decl_span
        self.solver.require(own, value, site)

    # --------------------------------------------------------------------------- relations

    def relation(self, relation: Any, scope: EvalScope) -> None:
        self.units.at(scope.node)
        kind = type(relation)
        if kind is ast.Equation:
            self.equation(relation, scope)
        elif kind is ast.Connect:
            self.connect(relation, scope)
        elif kind is ast.ForLoop:
            self.for_loop(relation.iterators, relation.body, scope)
        elif kind is ast.IfRelation:
            for branch in relation.branches:
                if structural_bool(evaluate(branch.condition, scope, Mode.STRUCTURAL), branch.span):
                    for inner in branch.body:
                        self.relation(inner, scope)
                    return
            for inner in relation.otherwise:
                self.relation(inner, scope)
        elif kind is ast.Switch:
            chosen, chosen_scope = switch_branch(relation, scope)
            for inner in chosen:
                self.relation(inner, chosen_scope)
        elif kind is ast.Guess:
            target = self.units.of(relation.target, scope)
            value = self.units.of(relation.value, scope)
            self.solver.require(target, value, self.units.site(
                "binding", relation.value, relation.target, ("the guess", "the variable")))

    def for_loop(self, iterators: tuple, body: tuple, scope: EvalScope) -> None:
        if not iterators:
            for inner in body:
                self.relation(inner, scope)
            return
        first = iterators[0]
        for value in iteration_values(first.iterable, scope):
            self.for_loop(iterators[1:], body, scope.bind(**{first.variable: value}))

    def equation(self, equation: ast.Equation, scope: EvalScope) -> None:
        """Every additive term of both sides in one unit; a message names the sides."""
        sides = []
        for side in (equation.lhs, equation.rhs):
            terms = _terms(side)
            sides.append([(term, self.units.of(term, scope)) for term in terms])
        reference = None
        for number, terms in enumerate(sides):
            for term, unit in terms:
                if unit is None or unit is FREE:
                    continue
                if reference is None:
                    reference = (number, term, unit)
                    continue
                labels = ("left side", "right side")
                if reference[0] == number:
                    labels = ("first term", "this term")
                elif number == 0:
                    labels = labels[::-1]
                site = self.units.site("equation", term, reference[1], (labels[1], labels[0]),
                                       statement=equation.span)
                self.solver.require(reference[2], unit, site)

    def connect(self, connect: ast.Connect, scope: EvalScope) -> None:
        ends = []
        for ref in connect.refs:
            try:
                target = resolve_connector(ref, scope)
            except DyadError:
                return                  # flattening reports it
            if target is not DISABLED:
                ends.append((ref, target))
        for ref, target in ends[1:]:
            first_ref, first = ends[0]
            for name, variable in _fields(first).items():
                other = _fields(target).get(name)
                if other is None:
                    continue
                site = self.units.site("connect", ref, first_ref,
                                       (f"`{ref.dotted}{_suffix(name, target)}`",
                                        f"`{first_ref.dotted}{_suffix(name, first)}`"),
                                       statement=connect.span)
                self.solver.require(self.declared(variable, first_ref), self.declared(other, ref), site)


def _fields(target: Any) -> dict[str, Any]:
    """name -> variable instance of a connector end (a signal is its own one field; elements of an
    array signal have the units of the whole)."""
    if hasattr(target, "variables"):
        return target.variables
    return {"": target.variable if isinstance(target, SignalElements) else target}


def _suffix(name: str, target: Any) -> str:
    return f".{name}" if name else ""


def _terms(expr: Any) -> list:
    if isinstance(expr, ast.BinaryOp) and expr.op in ("+", "-", ".+", ".-"):
        first, links = ast.left_chain(expr, {"+", "-", ".+", ".-"})
        return _terms(first) + [link.right for link in links]
    if isinstance(expr, ast.UnaryOp) and expr.op in ("-", "+"):
        return _terms(expr.operand)
    return [expr]


def _unit_text(attribute: tuple) -> str | None:
    expr, scope = attribute
    if isinstance(expr, ast.String):
        return expr.value
    try:
        value = evaluate(expr, scope, Mode.NUMERIC)
    except Exception:                  # flattening reports a `units` that is no string
        return None
    if getattr(value, "is_number", False) and value == 1:
        return "1"                      # Dyad writes a dimensionless unit as `units = 1`
    return value if isinstance(value, str) else None


def merge(found: list[Finding]) -> list[Finding]:
    """One finding per place and message, naming every instance that uses it."""
    merged: dict[tuple, Finding] = {}
    for finding in found:
        key = (finding.span, finding.message)
        first = merged.get(key)
        if first is None:
            merged[key] = finding
        elif finding.paths[0] not in first.paths:
            first.paths.append(finding.paths[0])
    return sorted(merged.values(), key=lambda f: (f.span.file, f.span.line, f.span.column)
                  if f.span else ("", 0, 0))
