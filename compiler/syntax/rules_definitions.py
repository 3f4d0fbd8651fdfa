"""Parse-tree rules for a file (its `using` lines) and its definitions: components, analyses,
connectors, types, enums and structs. Declarations inside them: compiler.syntax.rules_declarations."""
from __future__ import annotations

from lark import Token

from compiler.syntax import ast
from compiler.syntax.build_support import (
    Body, Doc, Metadata, RelationsSection, RuleBase, canonical, split_doc, split_suffixes,
    string_content,
)

FIELD_KINDS = ("potential", "flow", "input", "output", "stream", "path")


class DefinitionRules(RuleBase):

    # ------------------------------------------------------------------ file

    def start(self, meta, children):
        # `using A, B` gives one Using per package
        flat = [u for c in children for u in (c if isinstance(c, tuple) else (c,))]
        usings = tuple(c for c in flat if isinstance(c, ast.Using))
        definitions = tuple(c for c in flat if not isinstance(c, ast.Using))
        return ast.File(path=self.filename, usings=usings, definitions=definitions,
                        span=self._span(meta))

    def expression_start(self, meta, children):
        return children[0]

    def doc(self, meta, children):
        return Doc(string_content(children[0].value))

    def using(self, meta, children):
        return tuple(ast.Using(package, (), span=self._span(meta), level=level)
                     for level, package in children)

    def using_names(self, meta, children):
        (level, package), *names = children
        return ast.Using(package, tuple(name for name, _ in names), span=self._span(meta),
                         level=level, aliases=tuple(alias for _, alias in names))

    def using_name(self, meta, children):
        """(the imported name, the name it has in this file): `x`, or `x as y` (Julia's renaming)."""
        if len(children) == 1:
            return children[0].value, children[0].value
        name, word, alias = children
        if word.value != "as":
            raise self._error(f"expected `as` or `,` after `{name.value}` in this `using`, found "
                              f"`{word.value}`", self._tspan(word),
                              hint=f"rename with `{name.value} as {alias.value}`, or list names "
                                   f"with commas")
        return name.value, alias.value

    def using_path(self, meta, children):
        """(number of leading dots, the dotted name after them)"""
        return len(children) - 1, children[-1]

    def using_dot(self, meta, children):
        return "."

    def qual_name(self, meta, children):
        return ".".join(t.value for t in children)

    # ----------------------------------------------------------- definitions

    def def_prefix(self, meta, children):
        return children[0]

    def _prefixes(self, tokens: list[Token], what: str) -> tuple[bool, str | None, bool]:
        partial = external = False
        prefix = None
        seen = set()
        for tok in tokens:
            if tok.value in seen:
                raise self._error(f"`{tok.value}` is given twice", self._tspan(tok))
            seen.add(tok.value)
            if tok.value == "partial":
                partial = True
            elif tok.value == "external":
                if what != "component":
                    raise self._error(f"an {what} cannot be `external`", self._tspan(tok))
                external = True
            else:
                if prefix is not None:
                    raise self._error(f"a {what} cannot be both `{prefix}` and `{tok.value}`",
                                      self._tspan(tok))
                prefix = tok.value
        return partial, prefix, external

    def component_def(self, meta, children):
        doc, rest = split_doc(children)
        *prefix_tokens, name, body = rest
        partial, prefix, external = self._prefixes(prefix_tokens, "component")
        return ast.ComponentDef(name.value, body.extends, body.declarations, body.relations,
                                partial=partial, prefix=prefix, doc=doc, metadata=body.metadata,
                                span=self._span(meta), external=external)

    def analysis_def(self, meta, children):
        doc, rest = split_doc(children)
        *prefix_tokens, name, body = rest
        partial, prefix, _ = self._prefixes(prefix_tokens, "analysis")
        if prefix is not None:
            raise self._error(f"an analysis cannot be `{prefix}`", self._span(meta))
        return ast.AnalysisDef(name.value, body.extends, body.declarations, body.relations,
                               partial=partial, doc=doc, metadata=body.metadata,
                               span=self._span(meta))

    def body(self, meta, children):
        extends, declarations, relations, metadata = [], [], (), None
        for child in children:
            if isinstance(child, ast.Extends):
                extends.append(child)
            elif isinstance(child, RelationsSection):
                relations = child.relations
            elif isinstance(child, Metadata):
                metadata = child.text
            else:
                declarations.append(child)
        return Body(tuple(extends), tuple(declarations), relations, metadata)

    def relations_section(self, meta, children):
        return RelationsSection(children[1])

    def metadata_section(self, meta, children):
        return Metadata(canonical(children[0]))

    def connector_def(self, meta, children):
        doc, rest = split_doc(children)
        partial = False
        if rest and isinstance(rest[0], Token) and rest[0].type == "PARTIAL":
            partial = True
            rest = rest[1:]
        name, *items = rest
        fields = tuple(i for i in items if isinstance(i, ast.ConnectorField))
        metadata = next((i.text for i in items if isinstance(i, Metadata)), None)
        return ast.ConnectorDef(name.value, fields, partial=partial, doc=doc, metadata=metadata,
                                span=self._span(meta))

    def connector_field(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, (kind, name, type_spec, *value) = split_suffixes(rest, "a connector field")
        if suffixes.condition is not None:
            raise self._error("connector fields cannot be conditional", suffixes.condition_span)
        if value and kind != "path":
            raise self._error(f"only a `path` field of a connector has a default value, not a "
                              f"`{kind}` field", value[0].span,
                              hint=f"give `{name.value}` its value in the components that use the "
                                   f"connector (`p = Port({name.value}(guess = 1))`)")
        return ast.ConnectorField(name.value, kind, type_spec, doc=doc, metadata=suffixes.metadata,
                                  span=self._span(meta), link=suffixes.link,
                                  value=value[0] if value else None)

    def field_kind(self, meta, children):
        tok = children[0]
        if tok.type != "NAME" or tok.value in FIELD_KINDS:
            return tok.value
        raise self._error(f"expected `potential`, `flow`, `input`, `output`, `stream` or `path` "
                          f"before a connector field, found name `{tok.value}`", self._tspan(tok))

    def signal_connector_def(self, meta, children):
        doc, rest = split_doc(children)
        block = next((r for r in rest if isinstance(r, Metadata)), None)
        suffixes, (name, causality, type_spec) = split_suffixes(
            [r for r in rest if not isinstance(r, Metadata)], "a connector")
        if suffixes.condition is not None:
            raise self._error("a connector definition cannot be conditional",
                              suffixes.condition_span)
        if block is not None and suffixes.metadata is not None:
            raise self._error("a connector has two metadata objects", self._span(meta))
        return ast.SignalConnectorDef(name.value, causality, type_spec, doc=doc,
                                      metadata=block.text if block else suffixes.metadata,
                                      span=self._span(meta), link=suffixes.link)

    def causality(self, meta, children):
        return children[0].value

    def type_def(self, meta, children):
        doc, (name, base) = split_doc(children)
        return ast.TypeDef(name.value, base, doc=doc, span=self._span(meta))

    def function_type_def(self, meta, children):
        doc, (name, keyword, *params, result) = split_doc(children)
        if keyword != "func":
            raise self._error(f"expected `func` before a function type, found `{keyword}`",
                              self._span(meta), hint="write `type F = func(::Real)::Real`")
        return ast.FunctionTypeDef(name.value, tuple(params), result, doc=doc,
                                   span=self._span(meta))

    def function_param(self, meta, children):
        *name, type_spec = children
        return ast.FunctionParam(name[0].value if name else None, type_spec)

    def struct_def(self, meta, children):
        doc, (_, name, *fields) = split_doc(children)
        self._unique([(f.name, f.span) for f in fields], f"struct `{name.value}`")
        return ast.StructDef(name.value, tuple(fields), doc=doc, span=self._span(meta))

    def enum_def(self, meta, children):
        doc, (name, *cases) = split_doc(children)
        members = tuple(member for member, _ in cases)
        fields = tuple(f for _, f in cases)
        return ast.EnumDef(name.value, members, doc=doc, span=self._span(meta),
                           fields=fields if any(fields) else ())

    def enum_case(self, meta, children):
        name, *fields = children
        return name.value, (fields[0] if fields else ())

    def enum_block_case(self, meta, children):
        rest = [c for c in children if not isinstance(c, Doc)]
        name, *fields = rest
        return name.value, (fields[0] if fields else ())

    def enum_fields(self, meta, children):
        self._unique([(f.name, f.span) for f in children], "this enum member")
        return tuple(children)

    def typed_field(self, meta, children):
        name, type_spec, *value = children
        return ast.TypedDecl(name.value, type_spec, value[0] if value else None,
                             span=self._span(meta))

    def _unique(self, named, where: str) -> None:
        seen = set()
        for name, span in named:
            if name in seen:
                raise self._error(f"duplicate field `{name}` in {where}", span)
            seen.add(name)
