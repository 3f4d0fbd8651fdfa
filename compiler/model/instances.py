"""The instance tree: a component or connector instance (`Instance`, which serves the evaluator
its members) and the state one instantiation shares (`Model`: templates, unknown names, the
derivatives noted, the parameters being evaluated), plus checks on the tree."""
from __future__ import annotations

from typing import Any

import numpy as np

from compiler.errors import DyadError, Note, Span
from compiler.model.expressions import NOT_FOUND, EvalScope, Lexical, Mode
from compiler.model.flat import der_name
from compiler.model.library import Library, Resolved
from compiler.model.parameters import ParameterInstance
from compiler.model.templates import Template, build_template
from compiler.model.variables import VariableInstance, join_path
from compiler.syntax import ast


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


# How many enclosing instances an error inside a component names (innermost first).
MAX_INSTANCE_NOTES = 4


def instance_notes(node: Instance) -> list[Note]:
    """Where an instance comes from: a note at the declaration of `node` and of each enclosing
    instance (not the model itself), so that an error inside a library component also points at
    the line of the user's model that put the component there."""
    notes: list[Note] = []
    while node.parent is not None and len(notes) < MAX_INSTANCE_NOTES:
        if node.decl_span is not None:
            notes.append(Note(f"in `{node.path}` ({node.resolved.qualified_name}), declared here",
                              node.decl_span))
        node = node.parent
    return notes


def scalar_count(instance: Instance) -> int:
    """Scalar parameters, unknowns and instances of an instance and everything in it."""
    return sum(1 + sum(p.scalar_count() for p in node.parameters.values())
               + sum(len(v.names) for v in node.variables.values()) for node in instance.walk())
