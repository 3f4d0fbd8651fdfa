"""Instantiation: a component definition -> a tree of instances with parameters, variables and
the relations still in AST form (bound to their evaluation scope).

Done here: `extends` (several, recursive, with modifiers), modifier merging with precedence
outer > extends > declaration > type, `final`, structural evaluation (array sizes, conditional
declarations, component arrays), lazy parameter evaluation in dependency order with cycle
detection. The relations are turned into equations by compiler/model/flatten.py. The pieces:
templates.py (definitions with extends resolved, value types), parameters.py, variables.py,
instances.py (the tree); `instantiate` is the entry point.
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np

from compiler.errors import DyadError, Note, Span, suggest_name
from compiler.model import object_values, replaceable, signal_arrays, structs
from compiler.model.expressions import EvalScope, Lexical, Mode, evaluate, iteration_values, \
    structural_bool
from compiler.model.instances import Instance, Model, check_not_recursive, scalar_count
from compiler.model.library import PRIMITIVE_TYPES, Library, Resolved
from compiler.model.parameters import ParameterInstance
from compiler.model.size_limits import check_elements, check_shape
from compiler.model.templates import (BoundMod, ElementTemplate, Template, check_top_level_names, nested_mods,
                                      normalize)
from compiler.model.variables import VariableInstance, fill_connector, join_path
from compiler.syntax import ast

__all__ = ["BoundMod", "Instance", "Model", "ParameterInstance", "VariableInstance", "instantiate",
           "join_path", "normalize"]


def instantiate(resolved: Resolved, library: Library, outer: tuple[BoundMod, ...] = ()) -> Model:
    """Instantiate a top-level component: the whole tree, with parameters still lazy. `outer`:
    modifiers applied as if written where the component is used (a sweep's structural values)."""
    if not isinstance(resolved.definition, ast.ComponentDef):
        raise DyadError(f"`{resolved.qualified_name}` is not a component",
                        resolved.definition.span)
    model = Model(library)
    check_top_level_names(model.template(resolved))
    model.root = _instantiate(model, resolved, "", None, list(outer), resolved.definition.span)
    return model


def _instantiate(model: Model, resolved: Resolved, path: str, parent: Instance | None,
                 outer: list[BoundMod], decl_span: Span | None) -> Instance:
    node = Instance(model, path, resolved, parent, decl_span)
    definition = resolved.definition
    if isinstance(definition, ast.ConnectorDef):
        fill_connector(node, definition, resolved, outer)
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
                            hint=suggest_name(name, sorted(known)) or _members_hint(resolved.name, template))

    def entries_for(element: ElementTemplate) -> list[BoundMod]:
        own = [BoundMod(m, node.scope(lex)) for m, lex in element.extends_mods]
        return by_name.get(element.name, []) + own

    # Parameters first (lazily evaluated), so that sizes and conditions can use any of them.
    struct_parameters = _add_parameters(node, template, entries_for)
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


def _add_parameters(node: Instance, template: Template,
                    entries_for: Callable[[ElementTemplate], list[BoundMod]]
                    ) -> dict[str, structs.StructType]:
    """The parameters of `node`, lazily evaluated; Julia-object parameters are recorded as such.
    Returns the struct-typed ones, which become nested instances later."""
    model = node.model
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
    return struct_parameters


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
        value_type = signal_arrays.array_type(decl, definition, own_scope) if decl.iterators \
            else definition.type
        own = [BoundMod(normalize(m), own_scope) for m in decl.modifications]
        signal_lex = Lexical(model.library, resolved.package, resolved.file)
        variable = VariableInstance(
            node, decl.name, decl, value_type, signal_lex,
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
            check_elements(array.size * scalar_count(array[(0,) * len(shape)]), decl.span,
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


def _as_attribute_entries(name: str, outer: list[BoundMod], own: list[BoundMod]
                          ) -> list[BoundMod]:
    """Modifiers of a signal connector (`u = RealInput(guess = 1)`) are attributes of its value:
    wrap them so that they look like `u(guess = 1)`, after the outer ones (lower precedence)."""
    if not own:
        return list(outer)
    wrapper = ast.Modification(name, None, tuple(e.mod for e in own), False, own[0].mod.span)
    return list(outer) + [BoundMod(wrapper, own[0].scope)]


# How many of a component's parameters an unknown modifier's hint lists
MEMBERS_LISTED = 12


def _members_hint(name: str, template: Template) -> str:
    """The parameters a modifier of `name` can set (where it has none: every member), for an
    unknown modifier with no name close to it."""
    settable = [e.name for e in template.elements
                if isinstance(e.decl, ast.ParameterDecl) and not e.decl.final]
    names, what = (settable, "parameters") if settable else ([e.name for e in template.elements], "members")
    shown = ", ".join(f"`{n}`" for n in names[:MEMBERS_LISTED])
    more = f" and {len(names) - MEMBERS_LISTED} more" if len(names) > MEMBERS_LISTED else ""
    return f"the {what} of `{name}`: {shown}{more}"
