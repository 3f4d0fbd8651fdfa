"""Instantiation: a component definition -> a tree of instances with parameters, variables and
the relations still in AST form (bound to their evaluation scope).

Done here: `extends` (several, recursive, with modifiers), modifier merging with precedence
outer > extends > declaration > type, `final`, structural evaluation (array sizes, conditional
declarations, component arrays), lazy parameter evaluation in dependency order with cycle
detection. The relations are turned into equations by compiler/model/flatten.py.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import sympy

from compiler.errors import DyadError, Note, Span, suggest_name
from compiler.model.expressions import CONDITION_TYPES, NOT_FOUND, EvalScope, Lexical, MissingValue, Mode, evaluate, \
    is_array, shape_of, structural_bool, structural_int, iteration_values, _num
from compiler.model.flat import der_name
from compiler.model import object_values, replaceable, structs
from compiler.model.library import PRIMITIVE_TYPES, Library, Resolved
from compiler.model.size_limits import check_elements, check_shape
from compiler.syntax import ast

VARIABLE_ATTRIBUTES = ("initial", "guess", "start", "units", "min", "max", "state_priority",
                       "fixed", "description")
PARAMETER_ATTRIBUTES = ("units", "min", "max", "description")


def join_path(parent: str, name: str) -> str:
    return f"{parent}.{name}" if parent else name


def element_names(base: str, shape: tuple[int, ...]) -> list[str]:
    """Flat scalar names of an array: `A[1,2]` (1-based, row-major)."""
    if not shape:
        return [base]
    return [f"{base}[{','.join(str(i + 1) for i in index)}]" for index in np.ndindex(*shape)]


def symbols_for(base: str, shape: tuple[int, ...]) -> Any:
    if not shape:
        return sympy.Symbol(base)
    out = np.empty(shape, dtype=object)
    for index, name in zip(np.ndindex(*shape), element_names(base, shape)):
        out[index] = sympy.Symbol(name)
    return out


# ----------------------------------------------------------------------------- modifications

@dataclass(frozen=True)
class BoundMod:
    """A modification and the scope its expressions are evaluated in."""
    mod: ast.Modification
    scope: EvalScope


def normalize(mod: ast.Modification) -> ast.Modification:
    """`body.m = 2` -> `body(m = 2)`, so every modification names one element."""
    if "." not in mod.name:
        return mod
    head, rest = mod.name.split(".", 1)
    inner = ast.Modification(rest, mod.value, mod.nested, mod.final, mod.span)
    return ast.Modification(head, None, (normalize(inner),), False, mod.span)


def nested_mods(entries: list[BoundMod]) -> list[BoundMod]:
    """The modifications an element passes on to its own elements, outermost first."""
    return [BoundMod(normalize(n), e.scope) for e in entries for n in e.mod.nested]


def check_final(entries: list[BoundMod], declared_final: bool, decl_span: Span | None,
                name: str) -> None:
    """`entries` is outermost first; a final one may not be overridden by any before it."""
    valued = [e for e in entries if e.mod.value is not None]
    if declared_final and valued:
        raise DyadError(f"cannot modify final parameter `{name}`", valued[0].mod.span,
                        notes=[Note(f"`{name}` is declared final here", decl_span)])
    for i, entry in enumerate(valued):
        if entry.mod.final and i > 0:
            raise DyadError(f"cannot modify `{name}`: it was made final by a modifier",
                            valued[0].mod.span,
                            notes=[Note("made final here", entry.mod.span)])


RESERVED_NAMES = {"time": ("the independent variable (simulation time)",
                           "rename the declaration, e.g. `t0` or `t_start` for an instant")}


def check_not_reserved(name: str, span: Span | None) -> None:
    """`time` is built in: a declaration of that name would silently shadow or clash with it."""
    reserved = RESERVED_NAMES.get(name)
    if reserved is not None:
        meaning, hint = reserved
        raise DyadError(f"`{name}` is a reserved name: it is {meaning}", span, hint=hint)


# ---------------------------------------------------------------------------- templates

@dataclass
class ElementTemplate:
    decl: ast.Declaration
    lexical: Lexical
    owner: str                                  # qualified name of the declaring definition
    extends_mods: list[tuple[ast.Modification, Lexical]] = field(default_factory=list)

    @property
    def name(self) -> str:
        return self.decl.name


@dataclass
class Template:
    """A definition with its `extends` resolved: every element and relation it contributes."""
    resolved: Resolved
    elements: list[ElementTemplate]
    relations: list[tuple[ast.Relation, Lexical]]


def build_template(resolved: Resolved, library: Library, seen: tuple[str, ...] = ()) -> Template:
    definition = resolved.definition
    lexical = Lexical(library, resolved.package, resolved.file)
    elements: list[ElementTemplate] = []
    relations: list[tuple[ast.Relation, Lexical]] = []
    for ext in getattr(definition, "extends", ()):
        base = library.resolve(ext.type_name, resolved.package, resolved.file, ext.span)
        if base.qualified_name in seen + (resolved.qualified_name,):
            raise DyadError(f"cyclic extends: `{resolved.name}` extends `{base.name}` which "
                            f"extends it back", ext.span)
        if not isinstance(base.definition, ast.ComponentDef):
            raise DyadError(f"`{ext.type_name}` is not a component and cannot be extended",
                            ext.span)
        base_template = build_template(base, library, seen + (resolved.qualified_name,))
        names = {e.name for e in base_template.elements}
        mods = [normalize(m) for m in ext.modifications]
        for mod in mods:
            if mod.name not in names:
                raise DyadError(f"`{base.name}` has no element `{mod.name}` to modify", mod.span,
                                hint=suggest_name(mod.name, sorted(names)))
        for element in base_template.elements:
            mine = [(m, lexical) for m in mods if m.name == element.name]
            elements.append(ElementTemplate(element.decl, element.lexical, element.owner,
                                            mine + element.extends_mods))
        relations.extend(base_template.relations)
    for decl in getattr(definition, "declarations", ()):
        elements.append(ElementTemplate(decl, lexical, resolved.qualified_name))
    relations.extend((rel, lexical) for rel in getattr(definition, "relations", ()))
    seen_names: dict[str, ElementTemplate] = {}
    for element in elements:
        check_not_reserved(element.name, element.decl.span)
        first = seen_names.get(element.name)
        if first is not None:
            inherited = first.owner != resolved.qualified_name
            raise DyadError(f"duplicate declaration `{element.name}`"
                            + (" (also inherited)" if inherited else ""), element.decl.span,
                            notes=[Note("first declared here", first.decl.span)])
        seen_names[element.name] = element
    return Template(resolved, elements, relations)


# --------------------------------------------------------------------------------- types

@dataclass
class TypeInfo:
    primitive: str                              # Real | Integer | Boolean | String
    attributes: list[tuple[ast.Modification, Lexical]]   # lowest precedence first
    dims: list[tuple[ast.Expr, Lexical]]
    name: str
    spec: ast.TypeSpec | None = None


def resolve_value_type(spec: ast.TypeSpec, lexical: Lexical, depth: int = 0) -> TypeInfo:
    """The primitive type, attributes and sizes behind a type name (memoized per library: the
    same declaration is resolved once however many instances it has)."""
    cache = lexical.library.type_cache
    key = (id(spec), lexical.package, id(lexical.file))
    found = cache.get(key)
    if found is not None and found.spec is spec:
        return found
    info = _resolve_value_type(spec, lexical, depth)
    info.spec = spec
    cache[key] = info
    return info


def _resolve_value_type(spec: ast.TypeSpec, lexical: Lexical, depth: int = 0) -> TypeInfo:
    if depth > 20:
        raise DyadError(f"type `{spec.name}` is defined in terms of itself", spec.span)
    own_attrs = [(m, lexical) for m in spec.modifications]
    own_dims = [(d, lexical) for d in spec.dims]
    if spec.name in PRIMITIVE_TYPES:
        return TypeInfo(spec.name, own_attrs, own_dims, spec.name)
    if spec.name in ("Native", "Dyad.Native"):
        raise DyadError("a `Native` value is a Julia object (a dataset, a medium, an "
                        "interpolator) that dyadc cannot represent", spec.span,
                        hint="only `path` connector fields may hold Native values in dyadc; a "
                             "parameter or variable of this type needs Dyad's Julia runtime")
    found = lexical.library.resolve(spec.name, lexical.package, lexical.file, spec.span)
    definition = found.definition
    if isinstance(definition, ast.TypeDef):
        base = resolve_value_type(definition.base,
                                  Lexical(lexical.library, found.package, found.file), depth + 1)
        return TypeInfo(base.primitive, base.attributes + own_attrs, base.dims + own_dims,
                        found.qualified_name)
    if isinstance(definition, ast.EnumDef):
        return TypeInfo("Integer", own_attrs, own_dims, found.qualified_name)
    raise DyadError(f"`{spec.name}` is a {type(definition).__name__.replace('Def', '').lower()}, "
                    f"not a value type", spec.span)


# ---------------------------------------------------------------------------- parameters

_UNEVALUATED, _EVALUATING, _DONE = 0, 1, 2


class ParameterInstance:
    def __init__(self, node: "Instance", element: ElementTemplate, entries: list[BoundMod]):
        decl: ast.ParameterDecl = element.decl
        self.node = node
        self.decl = decl
        self.name = decl.name
        self.path = join_path(node.path, decl.name)
        self.owner = element.owner
        self.lexical = element.lexical
        self.variability = decl.variability
        self.final = decl.final
        self.type = resolve_value_type(decl.type, element.lexical)
        check_final(entries, decl.final, decl.span, decl.name)
        valued = [e for e in entries if e.mod.value is not None]
        own_scope = node.scope(element.lexical)
        if valued:
            self.binding: tuple[ast.Expr, EvalScope] | None = (valued[0].mod.value, valued[0].scope)
        elif decl.default is not None:
            self.binding = (decl.default, own_scope)
        else:
            self.binding = None
        self.attributes = _collect_attributes(self.type, entries, own_scope, PARAMETER_ATTRIBUTES,
                                              self.name)
        self._shape: tuple[int, ...] | None = None
        self._state = _UNEVALUATED
        self._value: Any = None
        self._symbolic_default: Any = None
        self._symbolic_done = False
        self.deps: list[ParameterInstance] = []
        self.structural_use = False

    @property
    def span(self) -> Span | None:
        return self.decl.span

    @property
    def fixed_at_compile_time(self) -> bool:
        return self.variability in ("structural", "constant")

    @property
    def is_string(self) -> bool:
        return self.type.primitive == "String"

    def shape(self) -> tuple[int, ...]:
        if self._shape is None:
            self._shape = check_shape(tuple(
                structural_int(evaluate(d, self.node.scope(lex), Mode.STRUCTURAL), d.span,
                               "an array size") for d, lex in self.type.dims),
                self.decl.span, f"the array `{self.path}`")
        return self._shape

    def symbols(self) -> Any:
        return symbols_for(self.path, self.shape())

    def flat_names(self) -> list[str]:
        return element_names(self.path, self.shape())

    # -- access from expressions
    def read(self, mode: Mode, span: Span | None) -> Any:
        model = self.node.model
        if mode is Mode.SYMBOLIC:
            if self.fixed_at_compile_time or self.is_string:
                value = self.value()
                if value is None:
                    raise DyadError(f"{self.variability} parameter `{self.path}` has no value",
                                    span)
                return value
            return self.symbols()
        if model.parameter_stack:
            model.parameter_stack[-1].deps.append(self)
        value = self.value()
        if mode is Mode.STRUCTURAL:
            self.mark_structural()
            if value is None:
                raise DyadError(f"parameter `{self.path}` has no value but is needed at compile "
                                f"time", span)
        elif value is None:
            raise MissingValue(self.path)
        return value

    def mark_structural(self) -> None:
        if self.structural_use:
            return
        self.structural_use = True
        for dep in self.deps:
            dep.mark_structural()

    def value(self) -> Any:
        """The numeric value (sympy number or array of them), None if it has none."""
        if self._state == _DONE:
            return self._value
        model = self.node.model
        if self._state == _EVALUATING:
            chain = model.parameter_stack[model.parameter_stack.index(self):] + [self]
            raise DyadError("cyclic parameter defaults: "
                            + " -> ".join(p.path for p in chain), self.span,
                            notes=[Note(f"`{p.path}` declared here", p.span) for p in chain[1:-1]])
        self._state = _EVALUATING
        model.parameter_stack.append(self)
        try:
            self._value = self._evaluate_numeric()
        finally:
            model.parameter_stack.pop()
        self._state = _DONE
        return self._value

    def _evaluate_numeric(self) -> Any:
        if self.binding is None:
            return None
        expr, scope = self.binding
        try:
            raw = evaluate(expr, scope, Mode.NUMERIC)
        except MissingValue:
            return None
        if self.is_string:
            if not isinstance(raw, str):
                raise DyadError(f"parameter `{self.path}` is a String but its value is not",
                                expr.span)
            return raw
        value = _num(raw, expr.span)
        self._check_shape(value, expr.span)
        return _numeric(value, expr.span, self.path)

    def _check_shape(self, value: Any, span: Span | None) -> None:
        if shape_of(value) != self.shape():
            declared = self.shape() or "scalar"
            raise DyadError(f"array size mismatch: parameter `{self.path}` is declared "
                            f"{declared if declared == 'scalar' else 'with size ' + str(declared)}"
                            f" but its value has size {shape_of(value) or 'scalar'}", span)

    def symbolic_default(self) -> Any:
        """The binding in other parameters' symbols (structural ones substituted)."""
        if not self._symbolic_done:
            self._symbolic_done = True
            if self.binding is not None and not self.is_string:
                expr, scope = self.binding
                value = evaluate(expr, scope, Mode.SYMBOLIC)
                if self.type.primitive == "Boolean":
                    value = _boolean_as_number(value, expr.span)
                value = _num(value, expr.span)
                self._check_shape(value, expr.span)
                for sym in (value.ravel() if is_array(value) else [value]):
                    unknowns = [s.name for s in getattr(sym, "free_symbols", ())
                                if self.node.model.is_unknown(s.name) or s.name == "time"]
                    if unknowns:
                        raise DyadError(f"parameter `{self.path}` cannot depend on "
                                        f"`{unknowns[0]}` (not a parameter)", expr.span)
                self._symbolic_default = value
        return self._symbolic_default


def _boolean_as_number(value: Any, span: Span | None) -> Any:
    if is_array(value):
        return np.vectorize(lambda v: _boolean_as_number(v, span), otypes=[object])(value)
    if isinstance(value, CONDITION_TYPES):
        if value is sympy.true:
            return sympy.Integer(1)
        if value is sympy.false:
            return sympy.Integer(0)
        return sympy.Piecewise((sympy.Integer(1), value), (sympy.Integer(0), True))
    return value


def _numeric(value: Any, span: Span | None, name: str) -> Any:
    """A parameter value must be a real number that a float can hold: the runtime computes in
    doubles, so `sqrt(-1)` or `1e400` would otherwise fail later, far from the declaration."""
    if is_array(value):
        return np.vectorize(lambda v: _numeric(v, span, name), otypes=[object])(value)
    if not getattr(value, "is_number", False) or value.has(sympy.zoo, sympy.nan):
        raise DyadError(f"the value of `{name}` is not a finite number ({value})", span,
                        hint="check for a division by zero or a logarithm of zero")
    if value.is_extended_real is False:
        raise DyadError(f"the value of `{name}` is not a real number ({value})", span,
                        hint="a square root or logarithm of a negative number, or asin/acos "
                             "outside [-1, 1], has no real value")
    try:
        as_float = float(value)
    except (TypeError, ValueError):
        raise DyadError(f"the value of `{name}` is not a real number ({value})", span) from None
    if not math.isfinite(as_float):
        shown = "infinite" if value.is_infinite else f"about {sympy.N(value, 3)}"
        raise DyadError(f"the value of `{name}` overflows a floating-point number: it is {shown}, "
                        f"beyond the largest double (about 1.8e308)", span,
                        hint="use a smaller value or other units")
    return value


def _collect_attributes(type_info: TypeInfo, entries: list[BoundMod], own_scope: EvalScope,
                        allowed: tuple[str, ...], name: str) -> dict[str, tuple[ast.Expr, EvalScope]]:
    """Attribute name -> (expression, scope); later sources override earlier ones."""
    out: dict[str, tuple[ast.Expr, EvalScope]] = {}

    def take(mod: ast.Modification, scope: EvalScope) -> None:
        if mod.name not in allowed:
            raise DyadError(f"unknown attribute `{mod.name}` for `{name}`", mod.span,
                            hint=suggest_name(mod.name, list(allowed)))
        if mod.value is not None:
            out[mod.name] = (mod.value, scope)

    for mod, lexical in type_info.attributes:
        take(mod, own_scope.with_lexical(lexical))
    for entry in reversed(entries):
        for nested in entry.mod.nested:
            take(nested, entry.scope)
    return out


# ----------------------------------------------------------------------------- variables

class VariableInstance:
    """An unknown (scalar or array) declared by a variable, a connector field or a signal
    connector; `connector_kind` is 'potential', 'flow', 'signal' or None."""

    def __init__(self, node: "Instance", name: str, decl: Any, type_spec: ast.TypeSpec,
                 lexical: Lexical, entries: list[BoundMod], *, causality: str | None,
                 connector_kind: str | None, binding: ast.Expr | None = None,
                 initial: ast.Expr | None = None, doc: str | None = None):
        self.node = node
        self.name = name
        self.path = join_path(node.path, name)
        self.decl = decl
        self.causality = causality
        self.connector_kind = connector_kind
        self.doc = doc
        self.type = resolve_value_type(type_spec, lexical)
        own_scope = node.scope(lexical)
        self.shape = check_shape(tuple(structural_int(evaluate(d, node.scope(lex), Mode.STRUCTURAL),
                                                      d.span, "an array size") for d, lex in self.type.dims),
                                 getattr(decl, "span", None), f"the array `{self.path}`")
        self.symbols = symbols_for(self.path, self.shape)
        self.names = element_names(self.path, self.shape)
        valued = [e for e in entries if e.mod.value is not None]
        self.binding: tuple[ast.Expr, EvalScope, Span | None] | None = None
        if valued:
            self.binding = (valued[0].mod.value, valued[0].scope, valued[0].mod.span)
        elif binding is not None:
            self.binding = (binding, own_scope, getattr(decl, "span", None))
        self.attributes = _collect_attributes(self.type, entries, own_scope, VARIABLE_ATTRIBUTES,
                                              self.path)
        if initial is not None:
            self.attributes["initial"] = (initial, own_scope)

    @property
    def span(self) -> Span | None:
        return getattr(self.decl, "span", None)

    @property
    def is_signal(self) -> bool:
        return self.causality in ("input", "output")


# ----------------------------------------------------------------------------- instances

class Instance:
    """A component or connector instance. `member` serves the expression evaluator."""

    def __init__(self, model: "Model", path: str, resolved: Resolved, parent: "Instance | None",
                 decl_span: Span | None):
        self.model = model
        self.path = path
        self.resolved = resolved
        self.parent = parent
        self.decl_span = decl_span
        self.kind = "connector" if isinstance(resolved.definition, ast.ConnectorDef) else "component"
        self.parameters: dict[str, ParameterInstance] = {}
        self.variables: dict[str, VariableInstance] = {}
        self.children: dict[str, Any] = {}          # Instance or np.ndarray of Instances
        self.disabled: dict[str, Span | None] = {}
        self.path_fields: dict[str, Span | None] = {}   # `path` fields of a connector
        self.object_bindings: dict[str, Any] = {}       # their bindings: object_values.py
        self.relations: list[tuple[ast.Relation, EvalScope]] = []
        self._scopes: dict[int, EvalScope] = {}

    @property
    def qualified_name(self) -> str:
        return self.resolved.qualified_name

    def scope(self, lexical: Lexical) -> EvalScope:
        key = id(lexical.file), lexical.package
        found = self._scopes.get(key)
        if found is None:
            found = self._scopes[key] = EvalScope(self, lexical, self.model)
        return found

    def member(self, name: str, mode: Mode, span: Span | None) -> Any:
        parameter = self.parameters.get(name)
        if parameter is not None:
            return parameter.read(mode, span)
        variable = self.variables.get(name)
        if variable is not None:
            if mode is not Mode.SYMBOLIC:
                raise DyadError(f"a parameter expression cannot depend on variable "
                                f"`{variable.path}`", span)
            return variable.symbols
        child = self.children.get(name)
        if child is not None:
            return child
        if name in self.disabled:
            raise DyadError(f"`{join_path(self.path, name)}` is disabled by its condition", span,
                            notes=[Note("declared here", self.disabled[name])])
        if name in self.path_fields:
            raise DyadError(f"`{join_path(self.path, name)}` is a Julia object (a `path` field or "
                            f"a `Native` parameter: a medium, a dataset): dyadc passes it to "
                            f"functions but cannot compute with it", span,
                            notes=[Note("declared here", self.path_fields[name])],
                            hint="functions of a medium (density, viscosity, ...) need Dyad's "
                                 "Julia runtime")
        return NOT_FOUND

    def member_names(self) -> list[str]:
        return list(self.parameters) + list(self.variables) + list(self.children)

    def child_instances(self) -> list["Instance"]:
        out: list[Instance] = []
        for child in self.children.values():
            if isinstance(child, np.ndarray):
                out.extend(child.ravel().tolist())
            else:
                out.append(child)
        return out

    def walk(self):
        yield self
        for child in self.child_instances():
            yield from child.walk()

    def __repr__(self) -> str:
        return f"Instance({self.path or '<model>'}: {self.qualified_name})"


class Model:
    """Shared state of one instantiation; also the evaluator's derivative tracker."""

    def __init__(self, library: Library):
        self.library = library
        self.unknown_names: set[str] = set()
        self.derivatives: dict[str, str] = {}
        self.differentiated: set[str] = set()
        self.parameter_stack: list[ParameterInstance] = []
        self._templates: dict[str, Template] = {}
        self._visual: dict[str, bool] = {}
        self.root: Instance | None = None

    # DerivativeTracker
    def is_unknown(self, name: str) -> bool:
        return name in self.unknown_names or name in self.derivatives

    def note_derivative(self, name: str) -> None:
        self.derivatives[der_name(name)] = name
        if name in self.unknown_names:
            self.differentiated.add(name)

    def template(self, resolved: Resolved) -> Template:
        found = self._templates.get(resolved.qualified_name)
        if found is None:
            found = self._templates[resolved.qualified_name] = build_template(resolved,
                                                                              self.library)
        return found

    def is_visual_only(self, resolved: Resolved, seen: tuple[str, ...] = ()) -> bool:
        """A component that only draws: no variables, no relations, no connectors, and only
        visual-only subcomponents (e.g. MultibodyComponents.Renderable, BoxShape)."""
        key = resolved.qualified_name
        if key in self._visual:
            return self._visual[key]
        result = isinstance(resolved.definition, ast.ComponentDef) and key not in seen \
            and resolved.definition.prefix != "struct"      # a struct's fields are parameters
        if result:
            template = self.template(resolved)
            result = not template.relations
            for element in template.elements:
                if not result:
                    break
                decl = element.decl
                if isinstance(decl, ast.VariableDecl):
                    result = False
                elif isinstance(decl, ast.ComponentDecl):
                    lex = element.lexical
                    sub = self.library.lookup(decl.type_name, lex.package, lex.file)
                    result = sub is not None and self.is_visual_only(sub, seen + (key,))
        self._visual[key] = result
        return result


def instantiate(resolved: Resolved, library: Library, outer: tuple[BoundMod, ...] = ()) -> Model:
    """Instantiate a top-level component: the whole tree, with parameters still lazy. `outer`:
    modifiers applied as if written where the component is used (a sweep's structural values)."""
    if not isinstance(resolved.definition, ast.ComponentDef):
        raise DyadError(f"`{resolved.qualified_name}` is not a component",
                        resolved.definition.span)
    model = Model(library)
    model.root = _instantiate(model, resolved, "", None, list(outer), resolved.definition.span)
    return model


def _instantiate(model: Model, resolved: Resolved, path: str, parent: Instance | None,
                 outer: list[BoundMod], decl_span: Span | None) -> Instance:
    node = Instance(model, path, resolved, parent, decl_span)
    definition = resolved.definition
    if isinstance(definition, ast.ConnectorDef):
        _fill_connector(node, definition, resolved, outer)
        return node
    template = model.template(resolved)
    by_name: dict[str, list[BoundMod]] = {}
    for entry in outer:
        by_name.setdefault(entry.mod.name, []).append(entry)
    known = {e.name for e in template.elements}
    for name, entries in by_name.items():
        if name not in known:
            raise DyadError(f"`{resolved.name}` has no parameter, variable or component "
                            f"`{name}`", entries[0].mod.span,
                            hint=suggest_name(name, sorted(known)))

    def entries_for(element: ElementTemplate) -> list[BoundMod]:
        own = [BoundMod(m, node.scope(lex)) for m, lex in element.extends_mods]
        return by_name.get(element.name, []) + own

    # Parameters first (lazily evaluated), so that sizes and conditions can use any of them.
    struct_parameters: dict[str, structs.StructType] = {}
    for element in template.elements:
        if isinstance(element.decl, ast.ParameterDecl):
            found = structs.struct_type(model.library, element.decl.type, element.lexical.package,
                                        element.lexical.file)
            if found is not None:       # a record of parameters: built as a nested instance below
                struct_parameters[element.name] = found
                continue
            entries = entries_for(element)
            bound, bound_scope = object_values.winning_binding(entries, element.decl,
                                                              node.scope(element.lexical))
            if structs.is_julia_object(model.library, element.decl.type, element.lexical.package,
                                       element.lexical.file) \
                    or object_values.names_julia_object(bound, bound_scope):
                node.path_fields[element.name] = element.decl.span  # opaque: object_calls.py
                object_values.record(node, element.name, bound, bound_scope, element.decl.span)
                continue
            node.parameters[element.name] = ParameterInstance(node, element, entries)
    for element in template.elements:
        decl = element.decl
        scope = node.scope(element.lexical)
        if decl.condition is not None and not structural_bool(
                evaluate(decl.condition, scope, Mode.STRUCTURAL), decl.condition.span):
            node.parameters.pop(decl.name, None)
            node.disabled[decl.name] = decl.span
            continue
        if isinstance(decl, ast.VariableDecl):
            entries = entries_for(element)
            node.variables[decl.name] = VariableInstance(
                node, decl.name, decl, decl.type, element.lexical, entries,
                causality=decl.causality, connector_kind=None, binding=decl.binding,
                initial=decl.initial, doc=decl.doc)
            model.unknown_names.update(node.variables[decl.name].names)
        elif isinstance(decl, ast.ComponentDecl):
            _add_component(node, element, entries_for(element))
        elif isinstance(decl, ast.TypedDecl) and decl.kind is None:
            _add_replaceable(node, element, entries_for(element))
        elif isinstance(decl, ast.ParameterDecl) and decl.name in struct_parameters:
            _add_struct_parameter(node, element, entries_for(element), struct_parameters[decl.name])
    node.relations = [(rel, node.scope(lex)) for rel, lex in template.relations]
    return node


def _add_component(node: Instance, element: ElementTemplate, entries: list[BoundMod]) -> None:
    decl: ast.ComponentDecl = element.decl
    model = node.model
    lex = element.lexical
    for entry in entries:
        if entry.mod.value is not None:
            raise DyadError(f"cannot replace component `{decl.name}` with a value; modify its "
                            f"parameters instead: `{decl.name}(p = ...)`", entry.mod.span)
    resolved = model.library.resolve(decl.type_name, lex.package, lex.file, decl.span,
                                     what="component type")
    definition = resolved.definition
    own_scope = node.scope(lex)
    if isinstance(definition, ast.SignalConnectorDef):
        if decl.iterators:
            raise DyadError("arrays of signal connectors are declared with a sized type, not a "
                            "comprehension", decl.span)
        own = [BoundMod(normalize(m), own_scope) for m in decl.modifications]
        signal_lex = Lexical(model.library, resolved.package, resolved.file)
        variable = VariableInstance(
            node, decl.name, decl, definition.type, signal_lex,
            _as_attribute_entries(decl.name, entries, own), causality=definition.causality,
            connector_kind="signal", doc=decl.doc)
        node.variables[decl.name] = variable
        model.unknown_names.update(variable.names)
        return
    if not isinstance(definition, (ast.ComponentDef, ast.ConnectorDef)):
        raise DyadError(f"`{decl.type_name}` is not a component or connector", decl.span)
    if isinstance(definition, ast.ComponentDef) and definition.partial:
        raise DyadError(f"cannot instantiate partial component `{decl.type_name}`", decl.span)
    check_not_recursive(node, resolved, decl)
    child_mods = nested_mods(entries)
    if not decl.iterators:
        own = [BoundMod(normalize(m), own_scope) for m in decl.modifications]
        node.children[decl.name] = _instantiate(model, resolved, join_path(node.path, decl.name),
                                                node, child_mods + own, decl.span)
        return
    ranges: list[list[Any]] = []
    scope = own_scope
    for iterator in decl.iterators:
        ranges.append(iteration_values(iterator.iterable, scope))
    shape = check_shape(tuple(len(r) for r in ranges), decl.span, f"the component array `{decl.name}`")
    array = np.empty(shape, dtype=object)
    for number, index in enumerate(np.ndindex(*shape)):
        if number == 1:         # one element built: the whole array is about `count` times its size
            check_elements(array.size * _scalar_count(array[(0,) * len(shape)]), decl.span,
                           f"the component array `{decl.name}` ({array.size:,} x {resolved.qualified_name})")
        bound = own_scope.bind(**{it.variable: ranges[k][index[k]]
                                  for k, it in enumerate(decl.iterators)})
        own = [BoundMod(normalize(m), bound) for m in decl.modifications]
        name = f"{decl.name}[{','.join(str(i + 1) for i in index)}]"
        array[index] = _instantiate(model, resolved, join_path(node.path, name), node,
                                    child_mods + own, decl.span)
    node.children[decl.name] = array


def _add_replaceable(node: Instance, element: ElementTemplate, entries: list[BoundMod]) -> None:
    """`sensor::Sensor = Thermometer(k = 2)`: a subcomponent whose type the outermost modifier
    giving a constructor (`Rig(sensor = Pyrometer())`) replaces (compiler/model/replaceable.py)."""
    decl: ast.TypedDecl = element.decl
    lex = element.lexical
    constraint = None if decl.type.name in PRIMITIVE_TYPES else \
        node.model.library.resolve(decl.type.name, lex.package, lex.file, decl.type.span)
    if constraint is None or not isinstance(constraint.definition, ast.ComponentDef):
        raise DyadError(f"`{decl.name}::{decl.type.name}` declares neither a parameter nor a "
                        f"variable", decl.span,
                        hint=f"write `parameter {decl.name}::{decl.type.name} = ...` or "
                             f"`variable {decl.name}::{decl.type.name}`; a keyword-less typed "
                             f"declaration in a component is a replaceable component")
    valued = [e for e in entries if e.mod.value is not None]
    if valued:              # replaced from outside: the outermost constructor wins
        chosen = valued[0]
        call = replaceable.constructor(chosen.mod.value, decl.name, chosen.mod.span)
        component = replaceable.as_component_decl(decl, call, with_modifications=False)
        replacing = ast.Modification(decl.name, None, replaceable.call_modifications(call), False,
                                     chosen.mod.span)
        entries = [BoundMod(replacing, chosen.scope)] + [e for e in entries if e.mod.value is None]
        call_lex = chosen.scope.lexical
    else:
        call = replaceable.constructor(decl.value, decl.name, decl.span)
        component = replaceable.as_component_decl(decl, call)
        call_lex = lex
    chosen_type = node.model.library.resolve(call.function, call_lex.package, call_lex.file,
                                             call.span, what="component type")
    if not _extends(node.model.library, chosen_type, constraint.qualified_name):
        raise DyadError(f"`{chosen_type.qualified_name}` cannot replace `{decl.name}`: it does not "
                        f"extend `{constraint.qualified_name}`, the type `{decl.name}` is declared "
                        f"with", call.span, notes=[Note("declared here", decl.span)])
    _add_component(node, ElementTemplate(component, call_lex, element.owner), entries)


def _add_struct_parameter(node: Instance, element: ElementTemplate, entries: list[BoundMod],
                          found: "structs.StructType") -> None:
    """A parameter of a struct type: a nested instance whose fields are parameters, with the
    precedence of compiler/model/structs.py."""
    decl: ast.ParameterDecl = element.decl
    model = node.model
    lex = element.lexical

    def alias_scope(owner: Resolved | None, use_site: EvalScope) -> EvalScope:
        return use_site if owner is None else node.scope(Lexical(model.library, owner.package,
                                                                 owner.file))

    mods = nested_mods(entries)
    valued = [e for e in entries if e.mod.value is not None]
    given = (valued[0].mod.value, valued[0].scope) if valued else \
        (decl.default, node.scope(lex)) if decl.default is not None else None
    if given is not None:
        call, scope = structs.constructor_type(given[0], decl.name), given[1]
        chosen = structs.struct_type(model.library, ast.TypeSpec(call.function, span=call.span),
                                     scope.lexical.package, scope.lexical.file)
        if chosen is None or chosen.resolved.qualified_name != found.resolved.qualified_name:
            raise DyadError(f"`{call.function}` is not a `{found.resolved.qualified_name}`, the "
                            f"struct `{decl.name}` is declared with", call.span,
                            notes=[Note("declared here", decl.span)])
        mods += [BoundMod(normalize(m), scope) for m in replaceable.call_modifications(call)]
        mods += [BoundMod(normalize(m), alias_scope(owner, scope)) for m, owner in chosen.modifications]
    mods += [BoundMod(normalize(m), alias_scope(owner, node.scope(lex)))
             for m, owner in found.modifications]
    struct = found.resolved
    as_component = Resolved(struct.qualified_name, structs.as_component(struct.definition),
                            struct.package, struct.file)
    node.children[decl.name] = _instantiate(model, as_component, join_path(node.path, decl.name),
                                            node, mods, decl.span)


def _extends(library: Library, resolved: Resolved, base: str, depth: int = 0) -> bool:
    if resolved.qualified_name == base:
        return True
    if depth > 20 or not isinstance(resolved.definition, ast.ComponentDef):
        return False
    for ext in resolved.definition.extends:
        parent = library.lookup(ext.type_name, resolved.package, resolved.file)
        if parent is not None and _extends(library, parent, base, depth + 1):
            return True
    return False


def _scalar_count(instance: Instance) -> int:
    """Scalar parameters, unknowns and instances of an instance and everything in it."""
    return sum(1 + sum(len(p.flat_names()) if p._shape is not None else 1 for p in node.parameters.values())
               + sum(len(v.names) for v in node.variables.values()) for node in instance.walk())


def check_not_recursive(node: Instance, resolved: Resolved, decl: ast.ComponentDecl) -> None:
    """A component may not contain itself, directly or through other components: the instance
    tree would be infinite. Name the cycle with every declaration on it."""
    chain: list[Instance] = []
    ancestor: Instance | None = node
    while ancestor is not None:
        chain.append(ancestor)
        if ancestor.qualified_name == resolved.qualified_name:
            break
        ancestor = ancestor.parent
    else:
        return
    chain.reverse()                       # the first occurrence of the type, then down to `node`
    steps = [chain[0].resolved.name]
    notes = []
    for inner in chain[1:]:
        steps.append(f"{inner.path.rsplit('.', 1)[-1]}: {inner.resolved.name}")
        notes.append(Note(f"`{chain[chain.index(inner) - 1].resolved.name}` contains "
                          f"`{inner.resolved.name}` here", inner.decl_span))
    steps.append(f"{decl.name}: {resolved.name}")
    raise DyadError(f"component `{resolved.name}` contains itself: " + " -> ".join(steps),
                    decl.span, notes=notes,
                    hint="a component cannot have a subcomponent of its own type, directly or "
                         "through other components; the instance tree would be infinite")


def _as_attribute_entries(name: str, outer: list[BoundMod], own: list[BoundMod]
                          ) -> list[BoundMod]:
    """Modifiers of a signal connector (`u = RealInput(guess = 1)`) are attributes of its value:
    wrap them so that they look like `u(guess = 1)`, after the outer ones (lower precedence)."""
    if not own:
        return list(outer)
    wrapper = ast.Modification(name, None, tuple(e.mod for e in own), False, own[0].mod.span)
    return list(outer) + [BoundMod(wrapper, own[0].scope)]


def _fill_connector(node: Instance, definition: ast.ConnectorDef, resolved: Resolved,
                    outer: list[BoundMod]) -> None:
    lexical = Lexical(node.model.library, resolved.package, resolved.file)
    by_name: dict[str, list[BoundMod]] = {}
    for entry in outer:
        by_name.setdefault(entry.mod.name, []).append(entry)
    names = [f.name for f in definition.fields]
    for name, entries in by_name.items():
        if name not in names:
            raise DyadError(f"connector `{definition.name}` has no field `{name}`",
                            entries[0].mod.span, hint=suggest_name(name, names))
    for fld in definition.fields:
        check_not_reserved(fld.name, fld.span)
        if fld.kind == "path":
            # A path field carries a value of the whole connected path (a fluid medium, a Julia
            # `Native` object) that is neither an unknown nor an equation: it is recorded, and
            # reading it in an expression is an error (see Instance.member).
            node.path_fields[fld.name] = fld.span
            continue
        if fld.kind == "stream":
            raise DyadError("`stream` connector fields are not supported yet", fld.span)
        signal = fld.kind in ("input", "output")
        variable = VariableInstance(
            node, fld.name, fld, fld.type, lexical, by_name.get(fld.name, []),
            causality=fld.kind if signal else None,
            connector_kind="signal" if signal else fld.kind, doc=fld.doc)
        node.variables[fld.name] = variable
        node.model.unknown_names.update(variable.names)
