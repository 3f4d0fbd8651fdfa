"""Parse-tree rules for declarations (parameters, variables, subcomponents, `extends`) and the
parts they share: type specifications, modifier lists and the suffixes (condition, metadata, link)."""
from __future__ import annotations

from lark import Token

from compiler.errors import DyadError
from compiler.syntax import ast
from compiler.syntax.build_support import (
    Binding, RuleBase, Suffix, TypeCall, TypePart, canonical, split_doc, split_suffixes,
)


class DeclarationRules(RuleBase):

    def extends_clause(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, (name, *rest) = split_suffixes(rest, "an `extends` clause")
        modifications = next((r for r in rest if isinstance(r, tuple)), ())
        return ast.Extends(name, modifications, metadata=suffixes.metadata, span=self._span(meta),
                           doc=doc, link=suffixes.link)

    def parameter_decl(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, rest = split_suffixes(rest, "a parameter")
        final = isinstance(rest[0], Token) and rest[0].type == "FINAL"
        if final:
            rest = rest[1:]
        variability, name, type_spec, *default = rest
        return ast.ParameterDecl(name.value, type_spec, default[0] if default else None,
                                 variability=variability, final=final, doc=doc,
                                 metadata=suffixes.metadata, condition=suffixes.condition,
                                 span=self._span(meta), link=suffixes.link)

    def variability(self, meta, children):
        return {"parameter": "parameter", "structural": "structural",
                "constant": "constant"}[children[0].value]

    def variable_decl(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, (kind, name, type_spec, *binding) = split_suffixes(rest, "a variable")
        value = initial = None
        if binding:
            if binding[0].initial:
                initial = binding[0].value
            else:
                value = binding[0].value
        causality = None if kind == "variable" else kind
        return ast.VariableDecl(name.value, type_spec, binding=value, initial=initial,
                                causality=causality, doc=doc, metadata=suffixes.metadata,
                                condition=suffixes.condition, span=self._span(meta),
                                link=suffixes.link)

    def var_kind(self, meta, children):
        return children[0].value

    def equation_binding(self, meta, children):
        return Binding(False, children[0])

    def initial_binding(self, meta, children):
        return Binding(True, children[1])

    def typed_decl(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, (name, type_spec, *value) = split_suffixes(rest, "a declaration")
        return ast.TypedDecl(name.value, type_spec, value[0] if value else None, doc=doc,
                             metadata=suffixes.metadata, condition=suffixes.condition,
                             span=self._span(meta), link=suffixes.link)

    def field_decl(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, (kind, name, type_spec, *value) = split_suffixes(rest, "a declaration")
        if kind.value not in ("path", "stream"):
            raise self._error(f"expected a declaration, found name `{kind.value}` before "
                              f"`{name.value}`", self._tspan(kind),
                              hint="declarations start with `parameter`, `variable`, `path`, "
                                   "`stream`, or are `name::Type` / `name = Component()`")
        return ast.TypedDecl(name.value, type_spec, value[0] if value else None, kind=kind.value,
                             doc=doc, metadata=suffixes.metadata, condition=suffixes.condition,
                             span=self._span(meta), link=suffixes.link)

    def component_decl(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, (name, call) = split_suffixes(rest, "a component")
        return ast.ComponentDecl(name.value, call.name, call.modifications, doc=doc,
                                 metadata=suffixes.metadata, condition=suffixes.condition,
                                 span=self._span(meta), link=suffixes.link)

    def component_array_decl(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, (name, call, first, *more) = split_suffixes(rest, "a component array")
        extra = more[0] if more else first if first.condition is not None else None
        if extra is not None:
            raise DyadError("an array of components takes one `for` clause without a filter: its "
                            "elements are numbered by the iterators", extra.span,
                            hint="declare a conditional component per index instead "
                                 "(`r_2 = R() if n > 1`), or make the range hold only the indices wanted")
        iterators = first.iterators
        return ast.ComponentDecl(name.value, call.name, call.modifications, iterators=iterators,
                                 doc=doc, metadata=suffixes.metadata,
                                 condition=suffixes.condition, span=self._span(meta),
                                 link=suffixes.link)

    def type_call(self, meta, children):
        name, *mods = children
        return TypeCall(name, mods[0] if mods else ())

    def suffix_metadata(self, meta, children):
        obj = next(c for c in children if isinstance(c, dict))
        return Suffix("metadata", canonical(obj), self._span(meta))

    def suffix_link(self, meta, children):
        return Suffix("link", children[-1].value, self._span(meta))

    def suffix_condition(self, meta, children):
        return Suffix("condition", children[0], self._span(meta))

    def meta_suffix(self, meta, children):
        return children[0]

    def decl_suffix(self, meta, children):
        return children[0]

    def type_spec(self, meta, children):
        name, *parts = children
        dims = modifications = None
        for part in parts:
            if part.kind == "dims":
                if dims is not None:
                    raise self._error(f"type `{name}` has two array dimension lists", part.span)
                dims = part.value
            else:
                if modifications is not None:
                    raise self._error(f"type `{name}` has two modifier lists", part.span)
                modifications = part.value
        return ast.TypeSpec(name, modifications or (), dims or (), span=self._span(meta))

    def type_dims(self, meta, children):
        return TypePart("dims", children[0], self._span(meta))

    def type_modifications(self, meta, children):
        return TypePart("modifications", children[0] if children else (), self._span(meta))

    def modifications(self, meta, children):
        seen: dict[str, ast.Modification] = {}
        for mod in children:
            if mod.name in seen:
                raise self._error(f"modifier `{mod.name}` is given twice", mod.span)
            seen[mod.name] = mod
        return tuple(children)

    def modification(self, meta, children):
        final = isinstance(children[0], Token) and children[0].type == "FINAL"
        rest = children[1:] if final else children
        name, *rest = rest
        nested: tuple = ()
        value = None
        has_parens = False
        for item in rest:
            if isinstance(item, tuple):
                nested = item
                has_parens = True
            else:
                value = item
        span = self._span(meta)
        if value is None and not nested:
            what = "a value or nested modifiers" if has_parens else "a value"
            raise self._error(f"modifier `{name}` needs {what}", span,
                              hint=f"write `{name} = ...` or `{name}(attribute = ...)`")
        return ast.Modification(name, value, nested, final=final, span=span)

    def modifier_name(self, meta, children):
        return ".".join(t.value for t in children)
