"""Source text -> AST: lark LALR parser plus a Transformer that builds compiler.syntax.ast nodes.

Public API: parse_source, parse_file, parse_expression, summarize.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken, VisitError
from lark.lexer import BasicLexer, LexerThread

from compiler.errors import DyadError, Span, register_source
from compiler.syntax import ast
from compiler.syntax.checks import check_file
from compiler.syntax.diagnostics import lexer_error, parse_error
from compiler.syntax.lalr import load_parser
from compiler.syntax.layout import LayoutError, arrange

# Decimal exponents, so that `100n` is exactly the float of `100e-9`.
SI_EXPONENTS = {"p": -12, "n": -9, "u": -6, "μ": -6, "m": -3, "k": 3, "M": 6, "G": 9, "T": 12}


class _StartAt:
    """One LALR table serves files and lone expressions; this picks the start symbol."""

    def __init__(self, lark: Lark, start: str):
        self.lark = lark
        self.start = start

    def parse(self, tokens):
        return self.lark.parse(tokens, start=self.start)


@lru_cache(maxsize=None)
def _parsers() -> tuple[_StartAt, _StartAt, BasicLexer]:
    lark = load_parser()
    return _StartAt(lark, "start"), _StartAt(lark, "expression_start"), BasicLexer(lark.lexer_conf)


def tokenize(text: str, filename: str) -> list[Token]:
    """Raw tokens (comments and whitespace dropped), or a DyadError for an unlexable character."""
    lexer = _parsers()[2]
    tokens: list[Token] = []
    try:
        for tok in LexerThread.from_text(lexer, text).lex(None):
            tokens.append(tok)
    except UnexpectedCharacters as err:
        raise lexer_error(err, text, filename) from None
    return tokens


def _parse_tokens(parser: Lark, text: str, filename: str, docstrings: bool = True):
    raw = tokenize(text, filename)
    try:
        arranged = arrange(raw, docstrings)
    except LayoutError as err:
        raise DyadError(err.message, _token_span(err.token, filename)) from None
    try:
        tree = parser.parse(arranged)
    except UnexpectedInput as err:
        raise parse_error(err, arranged, filename) from None
    try:
        return AstBuilder(filename).transform(tree)
    except VisitError as err:
        if isinstance(err.orig_exc, DyadError):
            raise err.orig_exc from None
        raise


def parse_source(text: str, filename: str = "<string>") -> ast.File:
    register_source(filename, text)
    result = _parse_tokens(_parsers()[0], text, filename)
    check_file(result)
    return result


def parse_file(path) -> ast.File:
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as err:
        raise DyadError(f"cannot read `{path}`: {err.strerror}") from None
    except UnicodeDecodeError as err:
        raise DyadError(f"`{path}` is not UTF-8 text (byte {err.start})") from None
    return parse_source(text, str(path))


def parse_expression(text: str, filename: str = "<expr>") -> ast.Expr:
    register_source(filename, text)
    return _parse_tokens(_parsers()[1], text, filename, docstrings=False)


# ------------------------------------------------------------------------------------ helpers

def _token_span(tok: Token, filename: str) -> Span:
    return Span(filename, tok.line, tok.column, tok.end_line, max(tok.end_column - 1, tok.column))


def _string_content(raw: str) -> str:
    """The source text between the quotes, verbatim: escapes are not interpreted (see docs)."""
    if raw.startswith('"""'):
        return raw[3:-3]
    return raw[1:-1]


def number_value(text: str) -> float | int:
    suffix = text[-1]
    if suffix in SI_EXPONENTS:
        return float(f"{text[:-1]}e{SI_EXPONENTS[suffix]}")
    if any(c in text for c in ".eE"):
        return float(text)
    return int(text)


_OPERATOR_SPELLINGS = {"||": "or", "&&": "and", "≤": "<=", "≥": ">=", "≠": "!="}


@dataclass(frozen=True)
class _Doc:
    text: str


@dataclass(frozen=True)
class _Suffix:
    kind: str           # 'metadata' | 'condition'
    value: object
    span: Span | None


@dataclass(frozen=True)
class _Binding:
    initial: bool
    value: ast.Expr


@dataclass(frozen=True)
class _TypeCall:
    name: str
    modifications: tuple


@dataclass(frozen=True)
class _TypePart:
    kind: str           # 'dims' | 'modifications'
    value: tuple
    span: Span | None


@dataclass(frozen=True)
class _Body:
    extends: tuple
    declarations: tuple
    relations: tuple
    metadata: str | None


@dataclass(frozen=True)
class _RelationsSection:
    relations: tuple


@dataclass(frozen=True)
class _Metadata:
    text: str


@dataclass(frozen=True)
class _Else:
    body: tuple


@dataclass(frozen=True)
class _CallArgs:
    args: tuple
    kwargs: tuple


@dataclass(frozen=True)
class _Nested:
    modifications: tuple


def _canonical(obj: dict) -> str:
    return json.dumps(obj, sort_keys=True)


def _split_doc(children: list) -> tuple[str | None, list]:
    if children and isinstance(children[0], _Doc):
        return children[0].text, children[1:]
    return None, children


def _suffixes(children: list, filename_owner: "AstBuilder", what: str):
    metadata = condition = None
    rest = []
    for child in children:
        if isinstance(child, _Suffix):
            if child.kind == "metadata":
                if metadata is not None:
                    raise DyadError(f"{what} has two metadata objects", child.span)
                metadata = child.value
            else:
                if condition is not None:
                    raise DyadError(f"{what} has two `if` conditions", child.span)
                condition = child.value
        else:
            rest.append(child)
    return metadata, condition, rest


@v_args(meta=True)
class AstBuilder(Transformer):
    def __init__(self, filename: str):
        super().__init__(visit_tokens=False)
        self.filename = filename

    # ----------------------------------------------------------------- spans

    def _span(self, meta) -> Span | None:
        if getattr(meta, "empty", True):
            return None
        return Span(self.filename, meta.line, meta.column, meta.end_line,
                    max(meta.end_column - 1, 1))

    def _tspan(self, tok: Token) -> Span:
        return _token_span(tok, self.filename)

    def _error(self, message: str, span: Span | None, hint: str | None = None) -> DyadError:
        return DyadError(message, span, hint)

    # ------------------------------------------------------------------ file

    def start(self, meta, children):
        usings = tuple(c for c in children if isinstance(c, ast.Using))
        definitions = tuple(c for c in children if not isinstance(c, ast.Using))
        return ast.File(path=self.filename, usings=usings, definitions=definitions,
                        span=self._span(meta))

    def expression_start(self, meta, children):
        return children[0]

    def doc(self, meta, children):
        return _Doc(_string_content(children[0].value))

    def using(self, meta, children):
        package, *names = children
        return ast.Using(package, tuple(n.value for n in names), span=self._span(meta))

    def qual_name(self, meta, children):
        return ".".join(t.value for t in children)

    # ----------------------------------------------------------- definitions

    def def_prefix(self, meta, children):
        return children[0]

    def _prefixes(self, tokens: list[Token], what: str) -> tuple[bool, str | None]:
        partial = False
        prefix = None
        seen = set()
        for tok in tokens:
            if tok.value in seen:
                raise self._error(f"`{tok.value}` is given twice", self._tspan(tok))
            seen.add(tok.value)
            if tok.value == "partial":
                partial = True
            elif tok.value == "external":
                raise self._error(f"`external` {what}s are not supported yet", self._tspan(tok))
            else:
                if prefix is not None:
                    raise self._error(f"a {what} cannot be both `{prefix}` and `{tok.value}`",
                                      self._tspan(tok))
                prefix = tok.value
        return partial, prefix

    def component_def(self, meta, children):
        doc, rest = _split_doc(children)
        *prefix_tokens, name, body = rest
        partial, prefix = self._prefixes(prefix_tokens, "component")
        return ast.ComponentDef(name.value, body.extends, body.declarations, body.relations,
                                partial=partial, prefix=prefix, doc=doc, metadata=body.metadata,
                                span=self._span(meta))

    def analysis_def(self, meta, children):
        doc, rest = _split_doc(children)
        *prefix_tokens, name, body = rest
        partial, prefix = self._prefixes(prefix_tokens, "analysis")
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
            elif isinstance(child, _RelationsSection):
                relations = child.relations
            elif isinstance(child, _Metadata):
                metadata = child.text
            else:
                declarations.append(child)
        return _Body(tuple(extends), tuple(declarations), relations, metadata)

    def relations_section(self, meta, children):
        return _RelationsSection(children[1])

    def metadata_section(self, meta, children):
        return _Metadata(_canonical(children[0]))

    def connector_def(self, meta, children):
        doc, rest = _split_doc(children)
        partial = False
        if rest and isinstance(rest[0], Token) and rest[0].type == "PARTIAL":
            partial = True
            rest = rest[1:]
        name, *items = rest
        fields = tuple(i for i in items if isinstance(i, ast.ConnectorField))
        metadata = next((i.text for i in items if isinstance(i, _Metadata)), None)
        return ast.ConnectorDef(name.value, fields, partial=partial, doc=doc, metadata=metadata,
                                span=self._span(meta))

    def connector_field(self, meta, children):
        doc, rest = _split_doc(children)
        metadata, condition, rest = _suffixes(rest, self, "a connector field")
        kind, name, type_spec = rest
        if condition is not None:
            raise self._error("connector fields cannot be conditional", condition.span)
        return ast.ConnectorField(name.value, kind, type_spec, doc=doc, metadata=metadata,
                                  span=self._span(meta))

    def field_kind(self, meta, children):
        tok = children[0]
        if tok.type != "NAME":
            return tok.value
        if tok.value in ("stream", "path"):
            raise self._error(f"`{tok.value}` connector fields are not supported yet",
                              self._tspan(tok))
        raise self._error(f"expected `potential`, `flow`, `input` or `output` before a connector "
                          f"field, found name `{tok.value}`", self._tspan(tok))

    def signal_connector_def(self, meta, children):
        doc, rest = _split_doc(children)
        name, causality, type_spec, *metadata = rest
        return ast.SignalConnectorDef(name.value, causality, type_spec, doc=doc,
                                      metadata=_canonical(metadata[0]) if metadata else None,
                                      span=self._span(meta))

    def causality(self, meta, children):
        return children[0].value

    def type_def(self, meta, children):
        doc, (name, base) = _split_doc(children)
        return ast.TypeDef(name.value, base, doc=doc, span=self._span(meta))

    def enum_def(self, meta, children):
        doc, (name, *cases) = _split_doc(children)
        return ast.EnumDef(name.value, tuple(cases), doc=doc, span=self._span(meta))

    def enum_case(self, meta, children):
        return children[0].value

    def enum_block_case(self, meta, children):
        return children[-1].value

    # ---------------------------------------------------------- declarations

    def extends_clause(self, meta, children):
        doc, rest = _split_doc(children)
        name, *rest = rest
        modifications = next((r for r in rest if isinstance(r, tuple)), ())
        metadata = next((_canonical(r) for r in rest if isinstance(r, dict)), None)
        return ast.Extends(name, modifications, metadata=metadata, span=self._span(meta), doc=doc)

    def parameter_decl(self, meta, children):
        doc, rest = _split_doc(children)
        metadata, condition, rest = _suffixes(rest, self, "a parameter")
        final = isinstance(rest[0], Token) and rest[0].type == "FINAL"
        if final:
            rest = rest[1:]
        variability, name, type_spec, *default = rest
        return ast.ParameterDecl(name.value, type_spec, default[0] if default else None,
                                 variability=variability, final=final, doc=doc,
                                 metadata=metadata, condition=condition, span=self._span(meta))

    def variability(self, meta, children):
        return {"parameter": "parameter", "structural": "structural",
                "constant": "constant"}[children[0].value]

    def variable_decl(self, meta, children):
        doc, rest = _split_doc(children)
        metadata, condition, rest = _suffixes(rest, self, "a variable")
        kind, name, type_spec, *binding = rest
        value = initial = None
        if binding:
            if binding[0].initial:
                initial = binding[0].value
            else:
                value = binding[0].value
        causality = None if kind == "variable" else kind
        return ast.VariableDecl(name.value, type_spec, binding=value, initial=initial,
                                causality=causality, doc=doc, metadata=metadata,
                                condition=condition, span=self._span(meta))

    def var_kind(self, meta, children):
        return children[0].value

    def equation_binding(self, meta, children):
        return _Binding(False, children[0])

    def initial_binding(self, meta, children):
        return _Binding(True, children[1])

    def component_decl(self, meta, children):
        doc, rest = _split_doc(children)
        metadata, condition, (name, call) = _suffixes(rest, self, "a component")
        return ast.ComponentDecl(name.value, call.name, call.modifications, doc=doc,
                                 metadata=metadata, condition=condition, span=self._span(meta))

    def component_array_decl(self, meta, children):
        doc, rest = _split_doc(children)
        metadata, condition, (name, call, iterators) = _suffixes(rest, self, "a component array")
        return ast.ComponentDecl(name.value, call.name, call.modifications, iterators=iterators,
                                 doc=doc, metadata=metadata, condition=condition,
                                 span=self._span(meta))

    def type_call(self, meta, children):
        name, *mods = children
        return _TypeCall(name, mods[0] if mods else ())

    def suffix_metadata(self, meta, children):
        return _Suffix("metadata", _canonical(children[0]), self._span(meta))

    def suffix_condition(self, meta, children):
        return _Suffix("condition", children[0], self._span(meta))

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
        return _TypePart("dims", children[0], self._span(meta))

    def type_modifications(self, meta, children):
        return _TypePart("modifications", children[0] if children else (), self._span(meta))

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

    # ------------------------------------------------------------- relations

    def equation(self, meta, children):
        doc, (lhs, rhs) = _split_doc(children)
        return ast.Equation(lhs, rhs, doc=doc, span=self._span(meta))

    def initial_equation(self, meta, children):
        doc, (_, lhs, rhs) = _split_doc(children)
        return ast.Equation(lhs, rhs, initial=True, doc=doc, span=self._span(meta))

    def guess_stmt(self, meta, children):
        doc, (_, target, value) = _split_doc(children)
        if not isinstance(target, ast.Ref):
            raise self._error("`guess` needs a variable name on the left of `=`", target.span)
        return ast.Guess(target, value, span=self._span(meta), doc=doc)

    def connect_stmt(self, meta, children):
        doc, rest = _split_doc(children)
        metadata = None
        if rest and isinstance(rest[-1], dict):
            metadata = _canonical(rest.pop())
        for ref in rest:
            if not isinstance(ref, ast.Ref):
                raise self._error("`connect` takes connector names, like `connect(a.p, b.n)`",
                                  ref.span)
        return ast.Connect(tuple(rest), doc=doc, span=self._span(meta), metadata=metadata)

    def for_block(self, meta, children):
        doc, (iterators, body) = _split_doc(children)
        return ast.ForLoop(iterators, body, span=self._span(meta), doc=doc)

    def if_block(self, meta, children):
        doc, (condition, body, *clauses) = _split_doc(children)
        branches = [ast.IfBranch(condition, body, span=self._span(meta))]
        otherwise: tuple = ()
        for clause in clauses:
            if isinstance(clause, _Else):
                otherwise = clause.body
            else:
                branches.append(clause)
        return ast.IfRelation(tuple(branches), otherwise, span=self._span(meta), doc=doc)

    def elseif_clause(self, meta, children):
        return ast.IfBranch(children[0], children[1], span=self._span(meta))

    def else_clause(self, meta, children):
        return _Else(children[0])

    def relation_list(self, meta, children):
        return tuple(children)

    def iterators(self, meta, children):
        return tuple(children)

    def iterator(self, meta, children):
        return ast.Iterator(children[0].value, children[1], span=self._span(meta))

    # ----------------------------------------------------------- expressions

    def if_expr(self, meta, children):
        *pairs, otherwise = children
        result = otherwise
        for index in range(len(pairs) - 2, -1, -2):
            condition, then = pairs[index], pairs[index + 1]
            if index == 0:
                span = self._span(meta)
            else:
                span = _join(condition.span, result.span)
            result = ast.IfExpr(condition, then, result, span=span)
        return result

    def binary(self, meta, children):
        left, op, right = children
        return ast.BinaryOp(_OPERATOR_SPELLINGS.get(op.value, op.value), left, right,
                            span=self._span(meta))

    def unary(self, meta, children):
        op, operand = children
        return ast.UnaryOp(op.value, operand, span=self._span(meta))

    def range(self, meta, children):
        if len(children) == 2:
            return ast.Range(children[0], children[1], span=self._span(meta))
        start, step, stop = children
        return ast.Range(start, stop, step, span=self._span(meta))

    def ref(self, meta, children):
        return ast.Ref(children[0], span=self._span(meta))

    def call(self, meta, children):
        parts, *rest = children
        span = self._span(meta)
        if any(p.indices for p in parts):
            raise self._error("only a plain (possibly dotted) name can be called, not an indexed "
                              "one", span)
        args = rest[0] if rest else _CallArgs((), ())
        return ast.Call(".".join(p.name for p in parts), args.args, args.kwargs, span=span)

    def name_path(self, meta, children):
        return tuple(children)

    def name_part(self, meta, children):
        name, *indices = children
        return ast.RefPart(name.value, indices[0] if indices else ())

    def call_args(self, meta, children):
        args, kwargs = [], []
        for child in children:
            if isinstance(child, ast.KeywordArg):
                kwargs.append(child)
            elif isinstance(child, tuple):
                kwargs.extend(child)
            else:
                if kwargs:
                    raise self._error("a positional argument cannot follow a keyword argument",
                                      child.span)
                args.append(child)
        seen = set()
        for kwarg in kwargs:
            if kwarg.name in seen:
                raise self._error(f"keyword argument `{kwarg.name}` is given twice", kwarg.span)
            seen.add(kwarg.name)
        return _CallArgs(tuple(args), tuple(kwargs))

    def keyword_args(self, meta, children):
        return tuple(children)

    def keyword_arg(self, meta, children):
        return ast.KeywordArg(children[0].value, children[1], span=self._span(meta))

    def index_args(self, meta, children):
        return tuple(children)

    def colon(self, meta, children):
        return ast.Colon(span=self._span(meta))

    def number(self, meta, children):
        tok = children[0]
        return ast.Number(number_value(tok.value), span=self._tspan(tok), text=tok.value)

    def string(self, meta, children):
        tok = children[0]
        return ast.String(_string_content(tok.value), span=self._tspan(tok))

    def true(self, meta, children):
        return ast.Boolean(True, span=self._tspan(children[0]))

    def false(self, meta, children):
        return ast.Boolean(False, span=self._tspan(children[0]))

    def end_index(self, meta, children):
        return ast.End(span=self._tspan(children[0]))

    def array_empty(self, meta, children):
        return ast.ArrayLit((), span=self._span(meta))

    def array_literal(self, meta, children):
        return ast.ArrayLit(tuple(children), span=self._span(meta))

    def comprehension(self, meta, children):
        return ast.Comprehension(children[0], children[1], span=self._span(meta))

    def matrix(self, meta, children):
        span = self._span(meta)
        if len(children) == 1 and len(children[0]) == 1:
            return ast.ArrayLit(children[0], span=span)
        rows = tuple(ast.ArrayLit(row, span=_join(row[0].span, row[-1].span)) for row in children)
        return ast.ArrayLit(rows, is_matrix=True, span=span)

    def matrix_row(self, meta, children):
        return tuple(children)

    # ------------------------------------------------------------------ JSON

    def json_object(self, meta, children):
        obj = {}
        for key, value, key_span in children:
            if key in obj:
                raise self._error(f"JSON key \"{key}\" is given twice", key_span)
            obj[key] = value
        return obj

    def json_pair(self, meta, children):
        key_token, value = children
        return (self._json_string(key_token), value, self._tspan(key_token))

    def json_array(self, meta, children):
        return list(children)

    def json_string(self, meta, children):
        return self._json_string(children[0])

    def _json_string(self, tok: Token) -> str:
        try:
            return json.loads(tok.value)
        except ValueError:
            raise self._error("invalid escape sequence in JSON string", self._tspan(tok)) from None

    def json_number(self, meta, children):
        text = "".join(t.value for t in children)
        try:
            return json.loads(text)
        except ValueError:
            raise self._error(f"`{text}` is not a JSON number", self._span(meta)) from None

    def json_true(self, meta, children):
        return True

    def json_false(self, meta, children):
        return False

    def json_name(self, meta, children):
        tok = children[0]
        if tok.value == "null":
            return None
        raise self._error(f"expected a JSON value, found name `{tok.value}`", self._tspan(tok),
                          hint="JSON strings need double quotes")


def _join(first: Span | None, last: Span | None) -> Span | None:
    if first is None or last is None:
        return first or last
    return Span(first.file, first.line, first.column, last.end_line, last.end_column)


# ------------------------------------------------------------------------------------ summary

def summarize(file: ast.File) -> str:
    """A short human-readable listing of what a file defines, for `dyadc parse`."""
    lines = [f"{file.path}: {len(file.definitions)} definition(s)"]
    for using in file.usings:
        names = f": {', '.join(using.names)}" if using.names else ""
        lines.append(f"  using {using.package}{names}")
    for definition in file.definitions:
        lines.append("  " + _describe(definition))
    return "\n".join(lines)


def _describe(definition) -> str:
    kind = type(definition).__name__
    if isinstance(definition, (ast.ComponentDef, ast.AnalysisDef)):
        counts = {"parameter": 0, "variable": 0, "component": 0}
        for decl in definition.declarations:
            key = {ast.ParameterDecl: "parameter", ast.VariableDecl: "variable",
                   ast.ComponentDecl: "component"}[type(decl)]
            counts[key] += 1
        words = "analysis" if kind == "AnalysisDef" else "component"
        prefix = " ".join(p for p in (("partial" if definition.partial else None),
                                      getattr(definition, "prefix", None)) if p)
        head = f"{prefix + ' ' if prefix else ''}{words} {definition.name}"
        extends = ", ".join(e.type_name for e in definition.extends)
        return (f"{head}{' extends ' + extends if extends else ''}: {counts['parameter']} "
                f"parameters, {counts['variable']} variables, {counts['component']} "
                f"subcomponents, {len(definition.relations)} relations")
    if isinstance(definition, ast.ConnectorDef):
        fields = ", ".join(f"{f.kind} {f.name}" for f in definition.fields)
        return f"connector {definition.name}: {fields}"
    if isinstance(definition, ast.SignalConnectorDef):
        return f"connector {definition.name} = {definition.causality} {definition.type.name}"
    if isinstance(definition, ast.TypeDef):
        return f"type {definition.name} = {definition.base.name}"
    if isinstance(definition, ast.EnumDef):
        return f"enum {definition.name} = {' | '.join(definition.members)}"
    return kind
