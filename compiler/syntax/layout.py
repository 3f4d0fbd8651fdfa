"""Layout pass between the lexer and the LALR parser.

The language is free-form except where layout carries meaning, as in Julia:
- a line break ends a statement when the line so far can end an expression and the next line
  does not obviously continue it (a line starting with a binary operator, `)`, `]`, `,`, `{`,
  `then`, `else`, ... continues the previous one);
- inside a matrix literal, whitespace separates the elements of a row (`[a -b]` has two
  elements, `[a - b]` one) and a line break separates rows;
- `end` inside square brackets is the last index, not a block terminator;
- a string at the start of a statement is a docstring;
- `[{` outside JSON opens metadata (`x = Foo() [{...}]`), never an array or an index;
- the `:` that closes `c ? a : b` is not a range, nor is the `:` of `u: analysis_point(a, b)`;
- `switch`, `case` and `struct` are keywords only where a statement can start with them, so
  `switch = IdealSwitch()` still declares a component named `switch`.
Brackets are checked here first so that an unclosed `(` is reported where it was opened.
"""
from __future__ import annotations

from dataclasses import dataclass

from lark import Token

# Tokens after which an expression may be complete.
EXPRESSION_ENDERS = frozenset({
    "NAME", "NUMBER", "STRING", "LONG_STRING", "DOCSTRING", "RPAR", "RSQB", "RBRACE", "TRUE",
    "FALSE", "END_INDEX", "END",
})
# Tokens that may begin an element of a matrix row.
ELEMENT_STARTERS = frozenset({
    "NAME", "NUMBER", "STRING", "LONG_STRING", "LPAR", "LSQB", "TRUE", "FALSE", "END",
    "IF", "BANG", "END_INDEX",
})
SIGNED_STARTERS = frozenset({"MINUS", "PLUS"})
# A line that starts with one of these continues the previous line.
CONTINUATION_STARTERS = frozenset({
    "PLUS", "MINUS", "DOT_PLUS", "DOT_MINUS", "STAR", "SLASH", "DOT_STAR", "DOT_SLASH", "CARET",
    "DOT_CARET", "COMPARE_OP", "AND", "OR", "AMP_AMP", "PIPE_PIPE", "EQUAL", "RPAR", "RSQB", "RBRACE", "COMMA",
    "COLON", "DOUBLE_COLON", "DOT", "LBRACE", "THEN", "ELSE", "ELSEIF", "IN",
    "PERCENT", "INT_DIV", "QMARK", "TERNARY_ELSE", "META_OPEN", "METADATA",
    "VBAR",     # `enum Mode =` with one `| Member` per line
})
# Docstrings follow these (besides expression enders): the start of a section.
STATEMENT_OPENERS = frozenset({"SEMICOLON", "RELATIONS"})
KEYWORD_TYPES = frozenset({
    "COMPONENT", "CONNECTOR", "PARTIAL", "EXAMPLE", "TEST", "EXTERNAL", "ANALYSIS", "EXTENDS",
    "RELATIONS", "METADATA", "END", "PARAMETER", "STRUCTURAL", "CONSTANT", "FINAL", "VARIABLE",
    "POTENTIAL", "FLOW", "INPUT", "OUTPUT", "INITIAL", "GUESS", "CONNECT", "FOR", "IN", "IF",
    "THEN", "ELSEIF", "ELSE", "OR", "AND", "TRUE", "FALSE", "TYPE", "ENUM", "USING",
    "SWITCH", "CASE", "STRUCT", "ANALYSIS_POINT",
})
# Keywords that are ordinary names unless a statement starts with them.
SOFT_KEYWORDS = frozenset({"SWITCH", "CASE", "STRUCT"})
# After a soft keyword, these show that it was used as a name (`switch = ...`, `case.x`).
NAME_USES = frozenset({
    "EQUAL", "DOT", "DOUBLE_COLON", "COMMA", "RPAR", "RSQB", "RBRACE", "LSQB", "COLON",
    "PLUS", "MINUS", "STAR", "SLASH", "CARET", "COMPARE_OP", "_NL", "SEMICOLON",
})
OPENERS = {"LPAR": "RPAR", "LSQB": "RSQB", "LBRACE": "RBRACE"}
CLOSERS = {v: k for k, v in OPENERS.items()}


class LayoutError(Exception):
    """A problem found before parsing; `token` locates it, `notes` are (message, token) pairs."""

    def __init__(self, message: str, token: Token, notes: tuple = ()):
        super().__init__(message)
        self.message = message
        self.token = token
        self.notes = notes


@dataclass
class _Bracket:
    token: Token
    kind: str            # 'paren' | 'index' | 'array' | 'comprehension' | 'brace' | 'meta'


def _synth(type_: str, value: str, at: Token) -> Token:
    return Token.new_borrow_pos(type_, value, at)


def check_brackets(tokens: list[Token]) -> None:
    stack: list[Token] = []
    for tok in tokens:
        if tok.type in OPENERS:
            stack.append(tok)
        elif tok.type in CLOSERS:
            if not stack:
                raise LayoutError(f"unexpected `{tok.value}` without a matching "
                                  f"`{_text(CLOSERS[tok.type])}`", tok)
            opener = stack.pop()
            if OPENERS[opener.type] != tok.type:
                raise LayoutError(
                    f"expected `{_text(OPENERS[opener.type])}` to close `{opener.value}` opened at "
                    f"{opener.line}:{opener.column}, found `{tok.value}`", tok)
    if stack:
        opener = stack[-1]
        raise LayoutError(f"unclosed `{opener.value}`: no matching `{_text(OPENERS[opener.type])}` "
                          f"before end of file", opener)


def _text(token_type: str) -> str:
    return {"LPAR": "(", "RPAR": ")", "LSQB": "[", "RSQB": "]", "LBRACE": "{", "RBRACE": "}"}[token_type]


def arrange(tokens: list[Token], docstrings: bool = True) -> list[Token]:
    """Insert layout tokens and retype context-dependent ones; see the module docstring.

    `docstrings=False` for a lone expression, where a leading string is a value.
    """
    check_brackets(tokens)
    out: list[Token] = []
    stack: list[_Bracket] = []
    prev: Token | None = None
    open_ternaries: list[int] = []      # bracket depth of each `?` still waiting for its `:`
    for i, tok in enumerate(tokens):
        inner = stack[-1].kind if stack else None
        following = tokens[i + 1] if i + 1 < len(tokens) else None
        tok = _retype(tok, prev, stack, inner, docstrings, following)
        if tok.type == "QMARK":
            open_ternaries.append(len(stack))
        elif tok.type == "COLON" and open_ternaries and open_ternaries[-1] == len(stack):
            open_ternaries.pop()
            tok = _synth("TERNARY_ELSE", tok.value, tok)
        if prev is not None:
            separator = _separator(prev, tok, inner, following)
            if separator is not None:
                out.append(_synth(separator, "\n", tok))
        if tok.type == "LPAR":
            stack.append(_Bracket(tok, "paren"))
        elif tok.type == "LBRACE":
            stack.append(_Bracket(tok, "brace"))
        elif tok.type == "META_OPEN":
            stack.append(_Bracket(tok, "meta"))
        elif tok.type == "LSQB":
            indexes = (prev is not None and prev.type in ("NAME", "RPAR", "RSQB")
                       and not (out and out[-1].type == "_HSEP"))
            stack.append(_Bracket(tok, "index" if indexes else "array"))
        elif tok.type in CLOSERS:
            stack.pop()
        elif tok.type == "FOR" and inner == "array":
            # `[f(i) for i in 1:n if c]`: no matrix rows in a comprehension, `if` is its filter
            stack[-1] = _Bracket(stack[-1].token, "comprehension")
        out.append(tok)
        prev = tok
    return out


def _retype(tok: Token, prev: Token | None, stack: list[_Bracket], inner: str | None,
            docstrings: bool, following: Token | None) -> Token:
    if prev is not None and prev.type == "DOT" and tok.type in KEYWORD_TYPES:
        return _synth("NAME", tok.value, tok)
    if tok.type == "SWITCH" and prev is not None and prev.type == "EQUAL" and not stack \
            and following is not None and following.line == tok.line \
            and following.type not in NAME_USES:
        return _synth("SWITCH_VALUE", tok.value, tok)      # `y = switch gear ...`: a value
    if tok.type in SOFT_KEYWORDS and not _is_statement_keyword(tok, prev, following):
        return _synth("NAME", tok.value, tok)
    if tok.type == "LSQB" and following is not None and following.type == "LBRACE" \
            and not any(b.kind == "brace" for b in stack):
        return _synth("META_OPEN", tok.value, tok)
    if tok.type == "COLON" and following is not None and following.type == "ANALYSIS_POINT" \
            and inner is None:
        return _synth("AP_COLON", tok.value, tok)
    if tok.type == "END" and any(b.kind in ("index", "array", "comprehension") for b in stack):
        return _synth("END_INDEX", tok.value, tok)
    if docstrings and tok.type in ("STRING", "LONG_STRING") and inner is None \
            and _opens_statement(prev):
        return _synth("DOCSTRING", tok.value, tok)
    if tok.type == "SEMICOLON" and inner == "array":
        return _synth("_ROWSEP", ";", tok)
    return tok


def _separator(prev: Token, tok: Token, inner: str | None, following: Token | None) -> str | None:
    if tok.type == "_ROWSEP":
        return None
    new_line = tok.line > prev.end_line
    if inner is None:
        if new_line and prev.type in EXPRESSION_ENDERS and tok.type not in CONTINUATION_STARTERS:
            return "_NL"
        return None
    if inner != "array" or tok.start_pos <= prev.end_pos or prev.type not in EXPRESSION_ENDERS:
        return None
    if new_line and (tok.type in ELEMENT_STARTERS or tok.type in SIGNED_STARTERS):
        return "_ROWSEP"
    if tok.type in ELEMENT_STARTERS:
        return "_HSEP"
    if tok.type in SIGNED_STARTERS and following is not None and following.start_pos == tok.end_pos:
        return "_HSEP"      # `[a -b]`: a sign glued to its operand starts a new element
    return None


def _is_statement_keyword(tok: Token, prev: Token | None, following: Token | None) -> bool:
    starts_statement = (prev is None or tok.line > prev.end_line
                        or prev.type in ("SEMICOLON", "RELATIONS", "DOCSTRING"))
    ends_statement = following is None or following.line > tok.end_line
    return starts_statement and not ends_statement and following.type not in NAME_USES


def _opens_statement(prev: Token | None) -> bool:
    if prev is None:
        return True
    return prev.type in EXPRESSION_ENDERS or prev.type in STATEMENT_OPENERS
