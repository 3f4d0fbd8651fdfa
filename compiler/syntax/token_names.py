"""How tokens read in a syntax error: a punctuation token by its text (`)`, `::`), a class of tokens
by what it is ("a name", "end of line"), and a set of expected tokens as one phrase ("an
expression, `)` or `,`"), likeliest fix first."""
from __future__ import annotations

from lark import Token

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
EXPRESSION_STARTS = {"NAME", "NUMBER", "STRING", "LONG_STRING", "LPAR", "LSQB", "MINUS", "PLUS",
                     "BANG", "TRUE", "FALSE", "IF", "END_INDEX", "SWITCH_VALUE"}
DECLARATION_STARTS = {"PARAMETER", "VARIABLE", "FINAL", "STRUCTURAL", "CONSTANT", "EXTENDS",
                      "INPUT", "OUTPUT"}
DEFINITION_STARTS = {"COMPONENT", "CONNECTOR", "ANALYSIS", "TYPE", "ENUM", "USING", "PARTIAL",
                     "EXAMPLE", "TEST", "EXTERNAL", "STRUCT"}
RELATION_ONLY = {"INITIAL", "GUESS", "CONNECT", "FOR"}
# Order in which expected tokens are listed: the likeliest fix first.
_PRIORITY = ["END", "RPAR", "RSQB", "RBRACE", "EQUAL", "DOUBLE_COLON", "COMMA", "THEN", "ELSE",
             "_NL"]


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


def expected_phrase(expected: set[str]) -> str:
    """The tokens a parser expected, as one phrase of at most five items."""
    parts: list[str] = []
    remaining = set(expected)
    if "CASE_END" in remaining:             # the `end` of a case is spelled `end`
        remaining = (remaining - {"CASE_END"}) | {"END"}
    if len(remaining & EXPRESSION_STARTS) >= 3:
        parts.append("an expression")
        remaining -= EXPRESSION_STARTS
    if len(remaining & DECLARATION_STARTS) >= 3:
        parts.append("a declaration")
        remaining -= DECLARATION_STARTS | {"NAME", "DOCSTRING"}
    if len(remaining & DEFINITION_STARTS) >= 3:
        parts.append("a definition")
        remaining -= DEFINITION_STARTS | {"DOCSTRING"}
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

