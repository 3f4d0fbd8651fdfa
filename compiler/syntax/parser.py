"""Source text -> AST: lexer, layout pass, lark LALR parser, then compiler.syntax.transformer.

Public API: parse_source, parse_file, parse_expression, tokenize, summarize.
"""
from __future__ import annotations

import gc
from contextlib import contextmanager
from functools import lru_cache
from pathlib import Path

from lark import Lark, Token
from lark.exceptions import UnexpectedCharacters, UnexpectedInput
from lark.lexer import BasicLexer, LexerThread

from compiler.errors import DyadError, register_source
from compiler.syntax import ast
from compiler.syntax.checks import check_file
from compiler.syntax.diagnostics import lexer_error, parse_error
from compiler.syntax.lalr import load_parser
from compiler.syntax.layout import LayoutError, arrange
from compiler.syntax.switch_layout import mark_case_ends
from compiler.syntax.transformer import build_ast, number_value, token_span  # noqa: F401


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


@contextmanager
def _no_cycle_collection():
    """Parsing allocates many long-lived, acyclic objects (tokens, trees, AST nodes); the cycle
    collector would rescan them again and again (a 20000-term sum parses 2x faster without)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _parse_tokens(parser: Lark, text: str, filename: str, docstrings: bool = True):
    with _no_cycle_collection():
        return _parse_tokens_unguarded(parser, text, filename, docstrings)


def _parse_tokens_unguarded(parser: Lark, text: str, filename: str, docstrings: bool):
    raw = tokenize(text, filename)
    try:
        arranged = mark_case_ends(arrange(raw, docstrings))
    except LayoutError as err:
        raise DyadError(err.message, token_span(err.token, filename)) from None
    try:
        tree = parser.parse(arranged)
    except UnexpectedInput as err:
        raise parse_error(err, arranged, filename) from None
    return build_ast(tree, filename)


def parse_source(text: str, filename: str = "<string>") -> ast.File:
    register_source(filename, text)
    result = _parse_tokens(_parsers()[0], text, filename)
    check_file(result)
    return result


def read_source(path) -> str:
    """The text of a source file, or a DyadError saying why it cannot be read."""
    path = Path(path)
    try:
        return path.read_text(encoding="utf-8")
    except OSError as err:
        raise DyadError(f"cannot read `{path}`: {err.strerror}") from None
    except UnicodeDecodeError as err:
        raise DyadError(f"`{path}` is not UTF-8 text (byte {err.start})") from None


def parse_file(path) -> ast.File:
    return parse_source(read_source(path), str(path))


def parse_expression(text: str, filename: str = "<expr>") -> ast.Expr:
    register_source(filename, text)
    return _parse_tokens(_parsers()[1], text, filename, docstrings=False)


# ------------------------------------------------------------------------------------ summary

def summarize(file: ast.File) -> str:
    """A short human-readable listing of what a file defines, for `dyadc parse`."""
    lines = [f"{file.path}: {len(file.definitions)} definition(s)"]
    for using in file.usings:
        names = f": {using.listed}" if using.names else ""
        lines.append(f"  using {using.written}{names}")
    for definition in file.definitions:
        lines.append("  " + _describe(definition))
    return "\n".join(lines)


def _describe(definition) -> str:
    kind = type(definition).__name__
    if isinstance(definition, (ast.ComponentDef, ast.AnalysisDef)):
        counts = {"parameter": 0, "variable": 0, "component": 0, "field": 0}
        for decl in definition.declarations:
            key = {ast.ParameterDecl: "parameter", ast.VariableDecl: "variable",
                   ast.ComponentDecl: "component", ast.TypedDecl: "field"}[type(decl)]
            counts[key] += 1
        words = "analysis" if kind == "AnalysisDef" else "component"
        prefix = " ".join(p for p in (("partial" if definition.partial else None),
                                      ("external" if getattr(definition, "external", False)
                                       else None),
                                      getattr(definition, "prefix", None)) if p)
        head = f"{prefix + ' ' if prefix else ''}{words} {definition.name}"
        extends = ", ".join(e.type_name for e in definition.extends)
        fields = f"{counts['field']} typed fields, " if counts["field"] else ""
        return (f"{head}{' extends ' + extends if extends else ''}: {counts['parameter']} "
                f"parameters, {counts['variable']} variables, {counts['component']} "
                f"subcomponents, {fields}{len(definition.relations)} relations")
    if isinstance(definition, ast.ConnectorDef):
        fields = ", ".join(f"{f.kind} {f.name}" for f in definition.fields)
        return f"connector {definition.name}: {fields}"
    if isinstance(definition, ast.SignalConnectorDef):
        return f"connector {definition.name} = {definition.causality} {definition.type.name}"
    if isinstance(definition, ast.TypeDef):
        return f"type {definition.name} = {definition.base.name}"
    if isinstance(definition, ast.FunctionTypeDef):
        params = ", ".join(f"{p.name or ''}::{p.type.name}" for p in definition.params)
        return f"type {definition.name} = func({params})::{definition.result.name}"
    if isinstance(definition, ast.EnumDef):
        return f"enum {definition.name} = {' | '.join(definition.members)}"
    if isinstance(definition, ast.StructDef):
        return f"struct {definition.name}: {', '.join(f.name for f in definition.fields)}"
    return kind
