"""Definitions as templates, and the value types of declarations.

A template is a definition with its `extends` resolved: every element it declares or inherits,
each with the modifiers its `extends` clauses give it, and every relation. Modifiers are bound to
the scope they were written in (`BoundMod`), normalized so that each names one element, and
checked against `final`. A value type resolves through type aliases to a primitive type with its
attributes and array sizes.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from compiler.errors import DyadError, Note, Span, suggest_name
from compiler.model.expressions import EvalScope, Lexical
from compiler.model.library import PRIMITIVE_TYPES, Library, Resolved
from compiler.syntax import ast


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


def check_top_level_names(template: "Template") -> None:
    """`time` may name a declaration of a component used inside another (`c.time`: inside `c`
    the declaration shadows the independent variable, as a local name shadows an outer one), but
    not of the simulated model itself, where its flat name would be the independent variable's
    own (and the results' `time` column): that would silently be one quantity."""
    for element in template.elements:
        if element.name == "time":
            name = template.resolved.name
            raise DyadError("`time` cannot be declared by the simulated model itself: its flat name "
                            "would be the independent variable's", element.decl.span,
                            hint=f"simulate a component that contains this one (`c = {name}()`), "
                                 "where it is `c.time`, or rename it (`t_local`)")


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
        first = seen_names.get(element.name)
        if first is not None:
            inherited = first.owner != resolved.qualified_name
            raise DyadError(f"duplicate declaration `{element.name}`"
                            + (" (also inherited)" if inherited else ""), element.decl.span,
                            notes=[Note("first declared here", first.decl.span)])
        seen_names[element.name] = element
    return Template(resolved, elements, relations)


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
    found = lexical.library.resolve(spec.name, lexical.package, lexical.file, spec.span,
                                    kinds=(ast.TypeDef, ast.EnumDef))
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
