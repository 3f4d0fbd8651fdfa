"""Turn lark's lexer and parser exceptions into DyadErrors that read "expected X, found Y"."""
from __future__ import annotations

from dataclasses import dataclass

from lark import Token
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from compiler.errors import DyadError, Note, Span
from compiler.syntax.definition_forms import misplaced_enum, switch_inside_expression
from compiler.syntax.generator_forms import generator_with_more_arguments
from compiler.syntax.modelica_forms import modelica_form_error

_PUNCTUATION = {
    "LPAR": "(", "RPAR": ")", "LSQB": "[", "RSQB": "]", "LBRACE": "{", "RBRACE": "}",
    "COMMA": ",", "SEMICOLON": ";", "COLON": ":", "DOUBLE_COLON": "::", "DOT": ".", "EQUAL": "=",
    "VBAR": "|", "PLUS": "+", "MINUS": "-", "STAR": "*", "SLASH": "/", "CARET": "^", "BANG": "!",
    "DOT_PLUS": ".+", "DOT_MINUS": ".-", "DOT_STAR": ".*", "DOT_SLASH": "./", "DOT_CARET": ".^",
    "OR": "or", "AND": "and", "PIPE_PIPE": "||", "AMP_AMP": "&&", "END_INDEX": "end", "__ANON_0": "∈", "_ROWSEP": ";",
    "QMARK": "?", "PERCENT": "%", "INT_DIV": "÷", "META_OPEN": "[", "TERNARY_ELSE": ":",
    "AP_COLON": ":",
}
_DESCRIPTIONS = {
    "NAME": "a name", "NUMBER": "a number", "STRING": "a string", "LONG_STRING": "a string",
    "DOCSTRING": "a docstring", "_NL": "end of line", "$END": "end of file",
    "COMPARE_OP": "a comparison operator", "_HSEP": "another matrix element",
}
_EXPRESSION_STARTS = {"NAME", "NUMBER", "STRING", "LONG_STRING", "LPAR", "LSQB", "MINUS", "PLUS",
                      "BANG", "TRUE", "FALSE", "IF", "END_INDEX", "SWITCH_VALUE"}
_DECLARATION_STARTS = {"PARAMETER", "VARIABLE", "FINAL", "STRUCTURAL", "CONSTANT", "EXTENDS",
                       "INPUT", "OUTPUT"}
_DEFINITION_STARTS = {"COMPONENT", "CONNECTOR", "ANALYSIS", "TYPE", "ENUM", "USING", "PARTIAL",
                      "EXAMPLE", "TEST", "EXTERNAL", "STRUCT"}
_RELATION_ONLY = {"INITIAL", "GUESS", "CONNECT", "FOR"}
_SECTION_WORDS = {"RELATIONS", "METADATA"}
# Order in which expected tokens are listed: the likeliest fix first.
_PRIORITY = ["END", "RPAR", "RSQB", "RBRACE", "EQUAL", "DOUBLE_COLON", "COMMA", "THEN", "ELSE",
             "_NL"]


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


def describe_expected(token_type: str) -> str:
    if token_type in _PUNCTUATION:
        return f"`{_PUNCTUATION[token_type]}`"
    if token_type in _DESCRIPTIONS:
        return _DESCRIPTIONS[token_type]
    return f"`{token_type.lower()}`"


def describe_found(tok: Token) -> str:
    if tok.type == "$END":
        return "end of file"
    if tok.type == "_NL":
        return "end of line"
    if tok.type == "NAME":
        return f"name `{tok.value}`"
    if tok.type == "NUMBER":
        return f"number `{tok.value}`"
    if tok.type in ("STRING", "LONG_STRING"):
        return "a string"
    if tok.type == "DOCSTRING":
        return "a string"
    if tok.type == "_HSEP":
        return "a space between two expressions"
    return f"`{tok.value}`"


@dataclass
class OpenBlock:
    kind: str            # 'component', 'analysis', 'connector', 'enum', '`for` loop', '`if` block'
    name: str | None
    token: Token

    def title(self) -> str:
        return f"{self.kind} `{self.name}`" if self.name else self.kind


def open_blocks(tokens: list[Token], upto: int) -> list[OpenBlock]:
    """The blocks still open before tokens[upto] (a scan that mirrors the grammar's `end`s)."""
    stack: list[OpenBlock] = []
    depth = 0
    prev: Token | None = None
    for index, tok in enumerate(tokens[:upto]):
        kind = tok.type
        if kind in ("LPAR", "LSQB", "LBRACE"):
            depth += 1
        elif kind in ("RPAR", "RSQB", "RBRACE"):
            depth -= 1
        elif depth == 0:
            following = tokens[index + 1:index + 3]
            name = following[0].value if following and following[0].type == "NAME" else None
            assigns = len(following) > 1 and following[1].type == "EQUAL"
            if kind in ("COMPONENT", "ANALYSIS"):
                stack.append(OpenBlock(kind.lower(), name, tok))
            elif kind in ("CONNECTOR", "ENUM") and not assigns:
                stack.append(OpenBlock(kind.lower(), name, tok))
            elif kind == "FOR":
                stack.append(OpenBlock("`for` loop", None, tok))
            elif kind == "SWITCH":
                stack.append(OpenBlock("`switch`", None, tok))
            elif kind == "IF" and _starts_if_block(prev, tok):
                stack.append(OpenBlock("`if` block", None, tok))
            elif kind == "END" and stack:
                stack.pop()
        prev = tok
    return stack


def _starts_if_block(prev: Token | None, tok: Token) -> bool:
    if prev is None or prev.type in ("_NL", "SEMICOLON", "RELATIONS", "END", "DOCSTRING"):
        return True
    return prev.type == "ELSE" and tok.line > prev.line


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
            and (tok.type == "$END" or tok.type in _DEFINITION_STARTS):
        block = blocks[-1]
        return DyadError(
            f"expected `end` to close {block.title()} (opened at {block.token.line}:"
            f"{block.token.column}), found {found}", span,
            notes=[Note(f"{block.title()} starts here", _token_span(block.token, filename))])
    return DyadError(f"expected {_expected_phrase(expected)}, found {found}", span)


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
        modelica = modelica_form_error(prev.value, _token_span(prev, span.file))
        if modelica is not None:            # `when h < 0 then`, `reinit v`
            return modelica
    if tok.type in _VALUE_TOKENS and adjacent is not None and adjacent.type in _VALUE_ENDERS \
            and adjacent.end_line == tok.line and tok.type not in expected:
        return DyadError(f"expected an operator or end of line after `{adjacent.value}`, "
                         f"found {found}", span,
                         hint="multiplication needs `*`: write `2 * x`, not `2 x`")
    if tok.type == "RELATIONS" and "RELATIONS" not in expected and innermost is not None:
        if innermost.kind in ("`for` loop", "`if` block"):
            return DyadError(f"`relations` section cannot appear inside {_a(innermost.kind)}", span,
                             hint="close the block with `end` first")
        if innermost.kind == "connector":
            return DyadError("`relations` section cannot appear inside a connector", span)
        return DyadError(f"`relations` section cannot appear here: {innermost.title()} already "
                         "has one, or its `metadata` came first", span)
    if tok.type in _DECLARATION_STARTS and tok.type not in expected and expected & _RELATION_ONLY:
        return DyadError(f"expected a relation, found declaration keyword `{tok.value}`", span,
                         hint="declarations come before the `relations` section")
    if tok.type in _RELATION_ONLY and tok.type not in expected and expected & _DECLARATION_STARTS:
        what = {"INITIAL": "`initial` equations", "GUESS": "`guess` statements",
                "CONNECT": "`connect` statements", "FOR": "`for` loops"}[tok.type]
        return DyadError(f"expected a declaration, found `{tok.value}`: {what} belong in the "
                         "`relations` section", span)
    if tok.type == "INITIAL" and "INITIAL" not in expected:
        return DyadError("`initial` cannot appear here: use it at the start of a relation "
                         "(`initial x = 1`) or as `variable x::Real = initial 1`", span)
    if tok.type == "END" and "END" not in expected and "RSQB" in expected:
        return DyadError(f"expected {_expected_phrase(expected)}, found `end`", span)
    if tok.type == "METADATA" and "METADATA" not in expected and innermost is not None \
            and innermost.kind in ("`for` loop", "`if` block"):
        return DyadError(f"`metadata` cannot appear inside {_a(innermost.kind)}", span)
    if tok.type == "END" and "END" not in expected and expected & _EXPRESSION_STARTS:
        return DyadError(f"expected {_expected_phrase(expected)}, found `end`", span,
                         hint="`end` stands for the last index only inside `[...]`, as in `v[end]`")
    if tok.type == "_HSEP":
        return DyadError("expected an operator or `,` between two expressions, found a space",
                         span, hint="inside `[...]` a space separates matrix elements; elsewhere "
                                    "write an operator, e.g. `2 * x` instead of `2 x`")
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
        return DyadError("`begin` is legacy Dyad syntax", _token_span(begin, span.file),
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


def _expected_phrase(expected: set[str]) -> str:
    parts: list[str] = []
    remaining = set(expected)
    if "CASE_END" in remaining:             # the `end` of a case is spelled `end`
        remaining = (remaining - {"CASE_END"}) | {"END"}
    if len(remaining & _EXPRESSION_STARTS) >= 3:
        parts.append("an expression")
        remaining -= _EXPRESSION_STARTS
    if len(remaining & _DECLARATION_STARTS) >= 3:
        parts.append("a declaration")
        remaining -= _DECLARATION_STARTS | {"NAME", "DOCSTRING"}
    if len(remaining & _DEFINITION_STARTS) >= 3:
        parts.append("a definition")
        remaining -= _DEFINITION_STARTS | {"DOCSTRING"}
    remaining -= {"DOCSTRING", "_NL", "SEMICOLON"} if parts or len(remaining) > 3 else set()
    ordered = sorted(remaining, key=lambda t: (_PRIORITY.index(t) if t in _PRIORITY else 99, t))
    operators = [t for t in ordered if t in ("PLUS", "MINUS", "STAR", "SLASH", "CARET",
                                              "COMPARE_OP", "AND", "OR", "AMP_AMP", "PIPE_PIPE", "DOT_PLUS",
                                              "DOT_MINUS", "DOT_STAR", "DOT_SLASH", "DOT_CARET")]
    if len(operators) >= 3:
        ordered = [t for t in ordered if t not in operators]
        ordered.append("an operator")
    parts.extend(describe_expected(t) if t != "an operator" else t for t in ordered)
    if not parts:
        return "something else"
    if len(parts) > 5:
        parts = parts[:5]
    if len(parts) == 1:
        return parts[0]
    return ", ".join(parts[:-1]) + " or " + parts[-1]


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


def _token_span(tok: Token, filename: str) -> Span:
    return Span(filename, tok.line, tok.column, tok.end_line, max(tok.end_column - 1, tok.column))


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
    return _token_span(tok, filename)
