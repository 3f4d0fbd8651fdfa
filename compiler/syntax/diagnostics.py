"""Turn lark's lexer and parser exceptions into DyadErrors that read "expected X, found Y", or name
the likely mistake (a Modelica or legacy form, a relation among declarations, `2 x`). How tokens
read: compiler/syntax/token_names.py; which blocks are open: compiler/syntax/open_blocks.py."""
from __future__ import annotations

from lark import Token
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from compiler.errors import DyadError, Note, Span
from compiler.syntax.build_support import token_span
from compiler.syntax.definition_forms import misplaced_enum, switch_inside_expression
from compiler.syntax.generator_forms import generator_with_more_arguments
from compiler.syntax.modelica_forms import modelica_form_error
from compiler.syntax.open_blocks import OpenBlock, open_blocks
from compiler.syntax.token_names import DECLARATION_STARTS, DEFINITION_STARTS, EXPRESSION_STARTS, \
    RELATION_ONLY, describe_found, expected_phrase


def lexer_error(err: UnexpectedCharacters, text: str, filename: str) -> DyadError:
    pos = err.pos_in_stream
    char = text[pos]
    line, column = err.line, err.column
    if char == '"':
        if text[max(pos - 2, 0):pos] == '""':
            span = Span(filename, line, column - 2, line, column)
            return DyadError('unclosed string literal `"""`: no closing `"""` before end of file',
                             span)
        return DyadError("unclosed string literal: no closing `\"` on this line",
                         Span(filename, line, column, line, column),
                         hint='a "..." string ends on its line; use """...""" for text over '
                              'several lines')
    return DyadError(f"unexpected character `{char}`", Span(filename, line, column, line, column))


def parse_error(err: UnexpectedInput, tokens: list[Token], filename: str) -> DyadError:
    if not isinstance(err, UnexpectedToken):
        return DyadError(f"syntax error: {err}", None)
    tok = err.token
    index = _index_of(tok, tokens)
    span = _span_of(tok, tokens, filename)
    expected = set(err.expected)
    found = describe_found(tok)
    blocks = open_blocks(tokens, index)
    special = _special_case(tok, expected, blocks, tokens, index, found, span)
    if special is not None:
        return special
    if ("END" in expected or "CASE_END" in expected) and blocks \
            and (tok.type == "$END" or tok.type in DEFINITION_STARTS):
        block = blocks[-1]
        return DyadError(
            f"expected `end` to close {block.title()} (opened at {block.token.line}:"
            f"{block.token.column}), found {found}", span,
            notes=[Note(f"{block.title()} starts here", token_span(block.token, filename))])
    return DyadError(f"expected {expected_phrase(expected)}, found {found}", span)


def _special_case(tok: Token, expected: set[str], blocks: list[OpenBlock], tokens, index,
                  found: str, span: Span) -> DyadError | None:
    innermost = blocks[-1] if blocks else None
    prev = _previous_significant(tokens, index)
    legacy = _legacy_form(tok, tokens, index, innermost, span)
    if legacy is not None:
        return legacy
    generator = generator_with_more_arguments(tok, tokens, index, expected, found, span) \
        or misplaced_enum(tok, tokens, index, innermost, span) \
        or switch_inside_expression(tok, tokens, index, span)
    if generator is not None:
        return generator
    adjacent = tokens[index - 1] if 0 < index <= len(tokens) else None
    if prev is not None and prev.type == "DOCSTRING" and tok.type in ("END", "$END"):
        return DyadError("a docstring must be followed by the definition, declaration or relation "
                         f"it documents, found {found}", span)
    if tok.type == "COMPARE_OP" and tok.type not in expected:
        return DyadError(f"comparisons cannot be chained, found a second `{tok.value}`", span,
                         hint="write `a < b and b < c`")
    if prev is not None and prev.type == "NAME" and tok.type not in expected:
        modelica = modelica_form_error(prev.value, token_span(prev, span.file))
        if modelica is not None:            # `when h < 0 then`, `reinit v`
            return modelica
    if tok.type in _VALUE_TOKENS and adjacent is not None and adjacent.type in _VALUE_ENDERS \
            and adjacent.end_line == tok.line and tok.type not in expected:
        return DyadError(f"expected an operator or end of line after `{adjacent.value}`, "
                         f"found {found}", span,
                         hint="multiplication needs `*`: write `2 * x`, not `2 x`")
    out_of_section = _out_of_section(tok, expected, innermost, span)
    if out_of_section is not None:
        return out_of_section
    if tok.type == "END" and "END" not in expected and "RSQB" in expected:
        return DyadError(f"expected {expected_phrase(expected)}, found `end`", span)
    if tok.type == "END" and "END" not in expected and expected & EXPRESSION_STARTS:
        return DyadError(f"expected {expected_phrase(expected)}, found `end`", span,
                         hint="`end` stands for the last index only inside `[...]`, as in `v[end]`")
    if tok.type == "_HSEP":
        return DyadError("expected an operator or `,` between two expressions, found a space",
                         span, hint="inside `[...]` a space separates matrix elements; elsewhere "
                                    "write an operator, e.g. `2 * x` instead of `2 x`")
    return None


def _out_of_section(tok: Token, expected: set[str], innermost: OpenBlock | None,
                    span: Span) -> DyadError | None:
    """A section keyword, declaration or relation where its section cannot stand."""
    if tok.type == "RELATIONS" and "RELATIONS" not in expected and innermost is not None:
        if innermost.kind in ("`for` loop", "`if` block"):
            return DyadError(f"`relations` section cannot appear inside {_a(innermost.kind)}", span,
                             hint="close the block with `end` first")
        if innermost.kind == "connector":
            return DyadError("`relations` section cannot appear inside a connector", span)
        return DyadError(f"`relations` section cannot appear here: {innermost.title()} already "
                         "has one, or its `metadata` came first", span)
    if tok.type in DECLARATION_STARTS and tok.type not in expected and expected & RELATION_ONLY:
        return DyadError(f"expected a relation, found declaration keyword `{tok.value}`", span,
                         hint="declarations come before the `relations` section")
    if tok.type in RELATION_ONLY and tok.type not in expected and expected & DECLARATION_STARTS:
        what = {"INITIAL": "`initial` equations", "GUESS": "`guess` statements",
                "CONNECT": "`connect` statements", "FOR": "`for` loops"}[tok.type]
        return DyadError(f"expected a declaration, found `{tok.value}`: {what} belong in the "
                         "`relations` section", span)
    if tok.type == "INITIAL" and "INITIAL" not in expected:
        return DyadError("`initial` cannot appear here: use it at the start of a relation "
                         "(`initial x = 1`) or as `variable x::Real = initial 1`", span)
    if tok.type == "METADATA" and "METADATA" not in expected and innermost is not None \
            and innermost.kind in ("`for` loop", "`if` block"):
        return DyadError(f"`metadata` cannot appear inside {_a(innermost.kind)}", span)
    return None


def _legacy_form(tok: Token, tokens, index, innermost, span: Span) -> DyadError | None:
    """`model Name ... begin ... end`: the syntax of early Dyad releases."""
    following = tokens[index + 1] if index + 1 < len(tokens) else None
    if tok.type == "NAME" and tok.value == "model" and innermost is None \
            and following is not None and following.type == "NAME":
        return DyadError("`model ... begin ... end` is the legacy Dyad syntax, which dyadc does "
                         "not read", span,
                         hint=f"write `component {following.value}`, its declarations, then "
                              "`relations` where `begin` was, and `end`")
    previous = tokens[index - 1] if 0 < index <= len(tokens) else None
    begin = tok if tok.type == "NAME" and tok.value == "begin" else previous
    if begin is not None and begin.type == "NAME" and begin.value == "begin" \
            and innermost is not None:
        return DyadError("`begin` is legacy Dyad syntax", token_span(begin, span.file),
                         hint="the relations of a component follow the keyword `relations`")
    return None


_VALUE_TOKENS = {"NAME", "NUMBER", "STRING", "LONG_STRING", "TRUE", "FALSE"}
_VALUE_ENDERS = {"NAME", "NUMBER", "RPAR", "RSQB", "TRUE", "FALSE"}


def _a(kind: str) -> str:
    return ("an " if kind.startswith("`if`") else "a ") + kind


def _previous_significant(tokens: list[Token], index: int) -> Token | None:
    for candidate in reversed(tokens[:index]):
        if candidate.type not in ("_NL", "SEMICOLON"):
            return candidate
    return None


def _index_of(tok: Token, tokens: list[Token]) -> int:
    if tok.type == "$END":
        return len(tokens)
    for index, candidate in enumerate(tokens):
        if candidate is tok:
            return index
    for index, candidate in enumerate(tokens):
        if candidate.start_pos == tok.start_pos and candidate.type == tok.type:
            return index
    return len(tokens)


def _span_of(tok: Token, tokens: list[Token], filename: str) -> Span:
    if tok.type == "$END":
        if not tokens:
            return Span(filename, 1, 1, 1, 1)
        last = tokens[-1]
        return Span(filename, last.end_line, last.end_column, last.end_line, last.end_column)
    if tok.type == "_NL":
        # A line break carries the position of the next line's first token; "found end of
        # line" should point where the line ends.
        index = _index_of(tok, tokens)
        if 0 < index <= len(tokens):
            last = tokens[index - 1]
            return Span(filename, last.end_line, last.end_column, last.end_line, last.end_column)
    return token_span(tok, filename)
