"""Flattening: the instance tree -> FlatSystem (scalar variables, parameters, sympy residuals).

Public API (used by the CLI): flatten_model, check_balance, summarize, format_flat,
check_library. See docs/flattening.md for the semantic choices.
"""
from __future__ import annotations

from typing import Any, Sequence

import sympy

from compiler.model.balance import check_balance, component_balance  # noqa: F401  (public API)
from compiler.errors import DyadError, Note, Span
from compiler.model.expressions import EvalScope, MissingValue, Mode, evaluate, is_array, \
    iteration_values, shape_of, structural_bool, structural_int, switch_branch, _num
from compiler.model.flat import ALGEBRAIC, INPUT, OUTPUT, STATE_CANDIDATE, Equation, FlatSystem, \
    Origin, Parameter, Variable
from compiler.model.flatten_connect import ConnectionGraph, connection_equations
from compiler.model.flatten_report import format_flat, summarize  # noqa: F401  (public API)
from compiler.model.instantiate import Instance, Model, ParameterInstance, VariableInstance, instantiate
from compiler.model.size_limits import check_elements
from compiler.model.library import Library, Resolved, load_model, resolve_model  # noqa: F401
from compiler.structure.collection import fewer_collections
from compiler.structure.differentiate import free_symbols
from compiler.syntax import ast


def flatten_model(spec: str, lib_dirs: Sequence[str] = ()) -> FlatSystem:
    """Flatten the component named by `spec` (a .dyad path, `path.dyad:Name` or a qualified
    name on the library path)."""
    library = Library(lib_dirs)
    return flatten_resolved(resolve_model(spec, library), library)


@fewer_collections()
def flatten_resolved(resolved: Resolved, library: Library) -> FlatSystem:
    return Flattener(instantiate(resolved, library)).run()


def span_text(span: Span | None) -> str | None:
    return f"{span.file}:{span.line}:{span.column}" if span else None


def _scalars(value: Any) -> list[Any]:
    return value.ravel().tolist() if is_array(value) else [value]


def _float(value: Any) -> float | None:
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def _plain(value: Any) -> Any:
    """A parameter value as plain Python data (floats, lists, str) for visual/metadata."""
    if is_array(value):
        return [_plain(v) for v in value]
    if isinstance(value, str) or value is None:
        return value
    return _float(value)


def _owner(variable: VariableInstance) -> Instance:
    node = variable.node
    return node.parent if node.kind == "connector" and node.parent is not None else node


class Flattener:
    def __init__(self, model: Model):
        self.model = model
        self.root: Instance = model.root
        self.equations: list[Equation] = []
        self.initial: list[Equation] = []
        self.guesses: dict[str, float] = {}
        self.starts: dict[str, float] = {}
        self.priorities: dict[str, int] = {}
        self.units: dict[str, str] = {}
        self.bounds: dict[str, dict[str, float]] = {}
        self.graph = ConnectionGraph()
        self.visual: dict[str, dict] = {}
        self.warnings: list[str] = []

    # ------------------------------------------------------------------------------- driver

    def run(self) -> FlatSystem:
        nodes = list(self.root.walk())
        visual_nodes = {n.path for n in nodes if n.kind == "component" and n is not self.root
                        and self.model.is_visual_only(n.resolved)}
        for node in nodes:
            if node.path in visual_nodes:
                continue
            for variable in node.variables.values():
                self._variable_equations(variable)
            for relation, scope in node.relations:
                self._relation(relation, scope)
        connect_equations, driven = connection_equations(self.graph)
        self.equations.extend(connect_equations)
        self._unconnected_flows(nodes)
        self._check_inputs(nodes, driven)
        variables = self._variables(nodes)
        parameters = self._parameters(nodes, visual_nodes)
        flat = FlatSystem(
            name=self.root.qualified_name, variables=variables, parameters=parameters,
            equations=self.equations, initial_equations=self.initial,
            derivatives=dict(sorted(self.model.derivatives.items())), guesses=self.guesses,
            metadata=self._metadata(nodes, visual_nodes), visual=self.visual,
            warnings=self.warnings)
        return flat

    # ---------------------------------------------------------------------------- relations

    def _relation(self, relation: ast.Relation, scope: EvalScope) -> None:
        if isinstance(relation, ast.Equation):
            self._equation(relation, scope)
        elif isinstance(relation, ast.Connect):
            self.graph.add(relation, scope)
        elif isinstance(relation, ast.Guess):
            self._guess(relation, scope)
        elif isinstance(relation, ast.ForLoop):
            self._for_loop(relation.iterators, relation.body, scope)
        elif isinstance(relation, ast.IfRelation):
            for branch in relation.branches:
                condition = evaluate(branch.condition, scope, Mode.STRUCTURAL)
                if structural_bool(condition, branch.span or relation.span):
                    for inner in branch.body:
                        self._relation(inner, scope)
                    return
            for inner in relation.otherwise:
                self._relation(inner, scope)
        elif isinstance(relation, ast.Switch):
            for inner in switch_branch(relation, scope):
                self._relation(inner, scope)
        elif isinstance(relation, ast.Continuity):
            pass        # relates `path` fields (a medium along a fluid path); implies no equation
        else:
            raise DyadError(f"unsupported relation {type(relation).__name__}",
                            getattr(relation, "span", None))

    def _for_loop(self, iterators: tuple[ast.Iterator, ...], body: tuple[ast.Relation, ...],
                  scope: EvalScope, outer: int = 1) -> None:
        if not iterators:
            for inner in body:
                self._relation(inner, scope)
            return
        first, rest = iterators[0], iterators[1:]
        values = iteration_values(first.iterable, scope)
        # nested loops multiply: each range may be small, the unrolled body not
        check_elements(outer * len(values) * len(body), first.span, "this `for` loop")
        for value in values:
            self._for_loop(rest, body, scope.bind(**{first.variable: value}), outer * len(values))

    def _equation(self, relation: ast.Equation, scope: EvalScope) -> None:
        span = relation.span
        lhs = _num(evaluate(relation.lhs, scope, Mode.SYMBOLIC), span)
        rhs = _num(evaluate(relation.rhs, scope, Mode.SYMBOLIC), span)
        if shape_of(lhs) != shape_of(rhs):
            raise DyadError(f"array size mismatch in equation: left side has size "
                            f"{shape_of(lhs) or 'scalar'}, right side {shape_of(rhs) or 'scalar'}",
                            span)
        origin = Origin(scope.node.path, span)
        target = self.initial if relation.initial else self.equations
        for left, right in zip(_scalars(lhs), _scalars(rhs)):
            target.append(Equation(left - right, origin, "equation", relation.doc))
            if relation.initial and isinstance(left, sympy.Symbol) and \
                    self.model.is_unknown(left.name) and left.name not in self.model.derivatives:
                value = self._numeric_or_none(right)
                if value is not None:
                    self.starts.setdefault(left.name, value)

    def _numeric_or_none(self, value: Any) -> float | None:
        """A start value from a symbolic expression in parameters, if every one has a value."""
        if not getattr(value, "free_symbols", None):
            return _float(value)
        substitutions = {}
        for sym in value.free_symbols:
            number = self._parameter_by_name(sym.name)
            if number is None:
                return None
            substitutions[sym] = number
        return _float(value.xreplace(substitutions))

    def _parameter_by_name(self, name: str) -> Any:
        if not hasattr(self, "_parameter_values"):
            self._parameter_values: dict[str, Any] = {}
            for node in self.root.walk():
                for parameter in node.parameters.values():
                    if parameter.is_string or parameter.fixed_at_compile_time:
                        continue
                    try:
                        value = parameter.value()
                    except DyadError:
                        continue
                    if value is None:
                        continue
                    for flat_name, number in zip(parameter.flat_names(), _scalars(value)):
                        self._parameter_values[flat_name] = number
        return self._parameter_values.get(name)

    def _guess(self, relation: ast.Guess, scope: EvalScope) -> None:
        target = evaluate(relation.target, scope, Mode.SYMBOLIC)
        self._set_numeric_attribute(self.guesses, target, relation.value, scope, relation.span,
                                    "guess")

    def _set_numeric_attribute(self, store: dict, target: Any, expr: ast.Expr, scope: EvalScope,
                               span: Span | None, what: str) -> None:
        try:
            value = _num(evaluate(expr, scope, Mode.NUMERIC), span)
        except MissingValue as missing:
            self.warnings.append(f"{span}: {what} ignored: parameter `{missing.name}` has no value")
            return
        symbols = _scalars(target)
        values = _scalars(value)
        if len(values) == 1 and len(symbols) > 1:
            values = values * len(symbols)
        if len(values) != len(symbols):
            raise DyadError(f"array size mismatch: the {what} has size {shape_of(value) or 'scalar'}"
                            f" but the variable has size {shape_of(target) or 'scalar'}", span)
        for sym, number in zip(symbols, values):
            if not isinstance(sym, sympy.Symbol) or not self.model.is_unknown(sym.name):
                raise DyadError(f"a {what} can only be given for a variable", span)
            as_float = _float(number)
            if as_float is None:
                raise DyadError(f"the {what} must be a number", span)
            store[sym.name] = as_float

    # ---------------------------------------------------------------------------- variables

    def _variable_equations(self, variable: VariableInstance) -> None:
        if variable.binding is not None:
            expr, scope, span = variable.binding
            value = _num(evaluate(expr, scope, Mode.SYMBOLIC), span)
            self._bind(variable, value, Origin(scope.node.path, span), span, "binding",
                       self.equations)
        attributes = variable.attributes
        if "initial" in attributes:
            expr, scope = attributes["initial"]
            span = getattr(expr, "span", None) or variable.span
            value = _num(evaluate(expr, scope, Mode.SYMBOLIC), span)
            self._bind(variable, value, Origin(scope.node.path, span), span, "equation",
                       self.initial)
            for name, number in zip(variable.names, self._broadcast(variable, value, span)):
                start = self._numeric_or_none(number)
                if start is not None:
                    self.starts[name] = start
        for attribute in ("guess", "start"):
            if attribute in attributes:
                expr, scope = attributes[attribute]
                self._set_numeric_attribute(self.guesses, variable.symbols, expr, scope,
                                            getattr(expr, "span", None) or variable.span, attribute)
        if "state_priority" in attributes:
            expr, scope = attributes["state_priority"]
            priority = structural_int(evaluate(expr, scope, Mode.STRUCTURAL), expr.span,
                                      "state_priority")
            for name in variable.names:
                self.priorities[name] = priority
        if "units" in attributes:
            expr, scope = attributes["units"]
            units = evaluate(expr, scope, Mode.NUMERIC)
            if getattr(units, "is_number", False) and units == 1:
                units = "1"         # Dyad writes a dimensionless unit as the number `units = 1`
            if not isinstance(units, str):
                raise DyadError("`units` must be a string", expr.span)
            for name in variable.names:
                self.units[name] = units
        for bound in ("min", "max"):
            if bound in attributes:
                expr, scope = attributes[bound]
                store: dict[str, float] = {}
                self._set_numeric_attribute(store, variable.symbols, expr, scope, expr.span, bound)
                for name, number in store.items():
                    self.bounds.setdefault(name, {})[bound] = number

    def _broadcast(self, variable: VariableInstance, value: Any, span: Span | None) -> list[Any]:
        values = _scalars(value)
        if len(values) == 1 and len(variable.names) > 1:
            values = values * len(variable.names)
        if len(values) != len(variable.names):
            raise DyadError(f"array size mismatch: `{variable.path}` has size "
                            f"{variable.shape or 'scalar'} but the value has size "
                            f"{shape_of(value) or 'scalar'}", span)
        return values

    def _bind(self, variable: VariableInstance, value: Any, origin: Origin, span: Span | None,
              kind: str, target: list[Equation]) -> None:
        for sym, number in zip(_scalars(variable.symbols), self._broadcast(variable, value, span)):
            target.append(Equation(sym - number, origin, kind))

    def _variables(self, nodes: list[Instance]) -> list[Variable]:
        out: list[Variable] = []
        for node in nodes:
            for variable in node.variables.values():
                owner = _owner(variable)
                top_signal = owner is self.root and variable.is_signal
                for name in variable.names:
                    if top_signal and variable.causality == "input":
                        kind = INPUT
                    elif name in self.model.differentiated:
                        kind = STATE_CANDIDATE
                    elif top_signal:
                        kind = OUTPUT
                    else:
                        kind = ALGEBRAIC
                    out.append(Variable(
                        name=name, kind=kind,
                        units=self.units.get(name) or _type_units(variable),
                        start=self.starts.get(name), guess=self.guesses.get(name),
                        state_priority=self.priorities.get(name, 0), description=variable.doc,
                        origin=Origin(owner.path, variable.span)))
        return out

    # ------------------------------------------------------------------------- connections

    def _unconnected_flows(self, nodes: list[Instance]) -> None:
        for node in nodes:
            if node.kind != "connector" or self.graph.is_inside_connected(node.path):
                continue
            owner = node.parent
            where = owner.parent.path if owner is not None and owner.parent is not None else ""
            for variable in node.variables.values():
                if variable.connector_kind == "flow":
                    for sym in _scalars(variable.symbols):
                        self.equations.append(Equation(sym, Origin(where, node.decl_span),
                                                       "unconnected_flow"))

    def _check_inputs(self, nodes: list[Instance], driven: dict[str, bool]) -> None:
        """An input of a subcomponent must be driven by a connection or given by an equation
        written outside that subcomponent (e.g. `controller.s_ref = s_ref`)."""
        used_outside: dict[str, set[str]] | None = None
        for node in nodes:
            for variable in node.variables.values():
                if variable.causality != "input":
                    continue
                owner = _owner(variable)
                if owner is self.root or driven.get(variable.path):
                    continue
                if used_outside is None:
                    used_outside = self._symbol_origins()
                origins = set()
                for name in variable.names:
                    origins |= used_outside.get(name, set())
                if any(not _inside(path, owner.path) for path in origins):
                    continue
                raise DyadError(
                    f"input `{variable.path}` is not connected and no equation gives it a value",
                    owner.decl_span,
                    hint=f"connect it to an output, or write `{variable.path} = ...` in the "
                         f"enclosing component",
                    notes=[Note(f"`{variable.name}` is declared here", variable.span)])

    def _symbol_origins(self) -> dict[str, set[str]]:
        out: dict[str, set[str]] = {}
        for equation in self.equations:
            for sym in equation.residual.free_symbols:
                out.setdefault(sym.name, set()).add(equation.origin.path)
        return out

    # ---------------------------------------------------------------------------- parameters

    def _parameters(self, nodes: list[Instance], visual_nodes: set[str]) -> list[Parameter]:
        out: list[Parameter] = []
        pending_visual: list[ParameterInstance] = []
        strings: dict[str, str] = {}
        for node in nodes:
            if node.path in visual_nodes:
                self.visual[node.path] = {
                    "type": node.qualified_name,
                    "parameters": {p.name: self._visual_value(p) for p in node.parameters.values()},
                }
                continue
            for parameter in node.parameters.values():
                if parameter.is_string:
                    strings[parameter.path] = parameter.value()
                    continue
                owner = self.model.library.find(parameter.owner)
                if owner is not None and self.model.is_visual_only(owner):
                    pending_visual.append(parameter)
                    continue
                out.extend(self._flat_parameters(parameter))
        if pending_visual:
            referenced = self._referenced_parameters(out)
            for parameter in pending_visual:
                if any(name in referenced for name in parameter.flat_names()):
                    out.extend(self._flat_parameters(parameter))
                else:
                    entry = self.visual.setdefault(parameter.node.path, {
                        "type": parameter.node.qualified_name, "parameters": {}})
                    entry["parameters"][parameter.name] = self._visual_value(parameter)
        self._strings = strings
        return out

    def _visual_value(self, parameter: ParameterInstance) -> Any:
        value = _plain(parameter.value())
        if parameter.type.primitive == "Boolean" and isinstance(value, float):
            return bool(value)
        return value

    def _flat_parameters(self, parameter: ParameterInstance) -> list[Parameter]:
        value = parameter.value()
        if value is None and parameter.binding is None:
            self.warnings.append(f"{parameter.span}: parameter `{parameter.path}` has no value: "
                                 f"give one when simulating (-p {parameter.path}=VALUE)")
        default = parameter.symbolic_default()
        values = _scalars(value) if value is not None else [None] * len(parameter.flat_names())
        defaults = _scalars(default) if default is not None else [None] * len(values)
        tunable = not (parameter.final or parameter.fixed_at_compile_time
                       or parameter.structural_use)
        units_attr = parameter.attributes.get("units")
        units = None
        if units_attr is not None:
            units = evaluate(units_attr[0], units_attr[1], Mode.NUMERIC)
        return [Parameter(name=name, value=_float(v) if v is not None else None, default=d,
                          tunable=tunable, variability=parameter.variability,
                          units=units if isinstance(units, str) else None,
                          description=parameter.decl.doc,
                          origin=Origin(parameter.node.path, parameter.span),
                          type_name=parameter.decl.type.name,
                          instance_span=parameter.node.decl_span if parameter.node.parent else None)
                for name, v, d in zip(parameter.flat_names(), values, defaults)]

    def _referenced_parameters(self, parameters: list[Parameter]) -> set[str]:
        referenced: set[str] = set()
        for equation in self.equations + self.initial:
            referenced.update(s.name for s in free_symbols(equation.residual))   # memoized: alias reuses it
        defaults = {p.name: p.default for p in parameters}
        stack = [name for name in referenced if name in defaults]
        while stack:
            default = defaults.get(stack.pop())
            for sym in getattr(default, "free_symbols", ()):
                if sym.name not in referenced:
                    referenced.add(sym.name)
                    stack.append(sym.name)
        return referenced

    # ------------------------------------------------------------------------------ metadata

    def _metadata(self, nodes: list[Instance], visual_nodes: set[str]) -> dict:
        components: dict[str, dict] = {}
        connectors: dict[str, dict] = {}
        instance_metadata: dict[str, dict] = {}
        for node in nodes:
            meta = ast.metadata_dict(getattr(node.resolved.definition, "metadata", None))
            if meta:
                instance_metadata[node.path] = meta
            if node.kind == "connector" and node.parent is not None \
                    and node.parent.path not in visual_nodes:
                connectors[node.path] = self._connector_info(node)
            if node.kind != "component" or node.path in visual_nodes:
                continue
            flows: list[str] = []
            inputs: list[str] = []
            for child in node.child_instances():
                if child.kind == "connector":
                    for variable in child.variables.values():
                        if variable.connector_kind == "flow":
                            flows.extend(variable.names)
                        elif variable.causality == "input":
                            inputs.extend(variable.names)
            for variable in node.variables.values():
                if variable.causality == "input":
                    inputs.extend(variable.names)
            components[node.path] = {"type": node.qualified_name, "span": span_text(node.decl_span),
                                     "connector_flows": flows, "inputs": inputs}
        top = instance_metadata.get("", {})
        return {"Dyad": top.get("Dyad", {}), "instances": instance_metadata,
                "components": components, "connectors": connectors, "bounds": self.bounds,
                "declared_partial": bool(getattr(self.root.resolved.definition, "partial", False)),
                "declared_external": bool(getattr(self.root.resolved.definition, "external", False)),
                "strings": getattr(self, "_strings", {}),
                "analysis_points": self.graph.analysis_points,
                "model_span": span_text(self.root.resolved.definition.span)}

    def _connector_info(self, node: Instance) -> dict:
        """What the model checks need about a physical connector instance: its type, owner,
        scalar potential and flow names per field, and whether any `connect` names it."""
        fields: dict[str, dict[str, list[str]]] = {"potential": {}, "flow": {}}
        for variable in node.variables.values():
            if variable.connector_kind in fields:
                fields[variable.connector_kind][variable.name] = list(variable.names)
        return {"type": node.resolved.name, "owner": node.parent.path,
                "span": span_text(node.decl_span), "connected": self.graph.is_connected(node.path),
                "potentials": fields["potential"], "flows": fields["flow"]}


def _inside(path: str, ancestor: str) -> bool:
    return path == ancestor or path.startswith(ancestor + ".")


def _type_units(variable: VariableInstance) -> str | None:
    for mod, _ in reversed(variable.type.attributes):
        if mod.name == "units" and isinstance(mod.value, ast.String):
            return mod.value.value
    return None


# ------------------------------------------------------------------------------- library check

def check_library(root_dir: str) -> list[str]:
    """Check every non-partial component under `root_dir` as `dyadc check` does; one line per
    component: `ok: Name (E equations, U unknowns)`, `partial: Name: balanced as a component,
    N open connectors (...)` for a component that cannot run alone, or the rendered error."""
    from compiler.model.model_check import check_model
    from pathlib import Path
    library = Library([root_dir])
    lines: list[str] = []
    try:
        definitions = library.definitions_under(Path(root_dir))
    except DyadError as err:
        return [err.format()]
    for resolved in definitions:
        definition = resolved.definition
        if not isinstance(definition, ast.ComponentDef) or definition.partial:
            continue
        try:
            flat = flatten_resolved(resolved, library)
            verdict = check_model(flat)
        except DyadError as err:
            lines.append(f"{resolved.qualified_name}: {err.format()}")
            continue
        if verdict.is_partial:
            lines.append(f"partial: {resolved.qualified_name}: "
                         f"{verdict.describe().removeprefix('partial: ')}")
            continue
        lines.append(f"ok: {resolved.qualified_name} ({verdict.equations} equations, "
                     f"{verdict.unknowns} unknowns)")
    return lines
