"""Which `end` inside a `switch` closes a case: the layout decision the LALR parser cannot make.

Dyad closes every case of a `switch` with its own `end` (`case A` ... `end` `case B` ... `end`, then
the `end` of the switch); dyadc also reads the form without them (`case A` ... `case B` ... `end`).
One token of lookahead cannot tell the two `end`s apart, so this pass, run on the arranged token
stream, retypes the `end` of a case (or of a switch's `else`) to CASE_END. The rule is the layout
both forms are written in (and `dyadc fmt` prints): a case's `end` stands deeper than its `switch`
keyword, the switch's own `end` stands at the keyword's column. Where the layout is flat (cases
written at the column of their `switch`), the tokens decide: an `end` followed by another `case`
(or the switch's `else`) not left of the `switch` closes a case, and once one case of a switch
was closed so, every case of that switch is (the Dyad form throughout).
"""
from __future__ import annotations

from dataclasses import dataclass

from lark import Token

_OPENERS = {"LPAR", "LSQB", "LBRACE"}
_CLOSERS = {"RPAR", "RSQB", "RBRACE"}
_STATEMENT_BOUNDARIES = {"_NL", "SEMICOLON", "RELATIONS", "END", "DOCSTRING", "CASE_END"}


@dataclass
class _Block:
    kind: str            # 'block' (anything closed by `end`), 'switch', 'case' (a case or else)
    column: int
    cases_closed: bool = False      # a switch one of whose cases had an `end` of its own
    value: bool = False             # of a switch value: its cases hold expressions, not relations

_SEPARATORS = {"_NL", "SEMICOLON"}


def mark_case_ends(tokens: list[Token]) -> list[Token]:
    """A new token list in which each `end` that closes a switch's case or `else` is CASE_END."""
    out: list[Token] = []
    stack: list[_Block] = []
    depth = 0
    for index, tok in enumerate(tokens):
        kind = tok.type
        if kind in _OPENERS:
            depth += 1
        elif kind in _CLOSERS:
            depth -= 1
        elif depth == 0:
            tok = _track(tok, tokens, index, stack)
        out.append(tok)
    return out


def _track(tok: Token, tokens: list[Token], index: int, stack: list[_Block]) -> Token:
    kind = tok.type
    top = stack[-1] if stack else None
    if kind == "SWITCH":
        stack.append(_Block("switch", tok.column))
    elif kind == "SWITCH_VALUE":        # `y = switch g`: its cases are deeper than the line's start
        stack.append(_Block("switch", _line_start(tokens, index).column, value=True))
    elif kind == "CASE" or (kind == "ELSE" and top is not None and top.kind in ("switch", "case")
                            and _starts_statement(tokens, index)):
        if top is not None and top.kind == "case":
            stack.pop()                      # the previous case had no `end` of its own
        stack.append(_Block("case", tok.column, value=stack[-1].value if stack else False))
    elif kind == "END" and top is not None:
        if top.kind == "case":
            stack.pop()
            switch = stack[-1] if stack else None
            if switch is None:
                return tok
            if switch.kind == "switch" and _closes_case(tok, tokens, index, switch):
                switch.cases_closed = True
                return Token.new_borrow_pos("CASE_END", tok.value, tok)
        stack.pop()                          # the block (or the switch) this `end` closes
    elif _opens_block(tok, tokens, index) and not (kind == "IF" and top is not None and top.value):
        stack.append(_Block("block", tok.column))
    return tok


def _closes_case(tok: Token, tokens: list[Token], index: int, switch: _Block) -> bool:
    """Does this `end`, met inside a case of `switch`, close that case (not the switch)?"""
    following = next((t for t in tokens[index + 1:] if t.type not in _SEPARATORS), None)
    if following is not None and following.type in ("CASE", "ELSE") \
            and following.column >= switch.column:      # not a case of an enclosing switch
        return True
    return switch.cases_closed or tok.column > switch.column


def _opens_block(tok: Token, tokens: list[Token], index: int) -> bool:
    kind = tok.type
    following = tokens[index + 1:index + 3]
    assigns = len(following) > 1 and following[1].type == "EQUAL"
    if kind in ("COMPONENT", "ANALYSIS", "FOR", "STRUCT"):
        return True
    if kind in ("CONNECTOR", "ENUM"):
        return not assigns
    if kind == "IF":                         # an `if` block, not `if c then` nor `x = C() if flag`
        previous = tokens[index - 1] if index > 0 else None
        return previous is None or previous.type in _STATEMENT_BOUNDARIES \
            or (previous.type == "ELSE" and tok.line > previous.line)
    return False


def _line_start(tokens: list[Token], index: int) -> Token:
    """The first token on the line of tokens[index]."""
    while index > 0 and tokens[index - 1].line == tokens[index].line \
            and tokens[index - 1].type not in _SEPARATORS:
        index -= 1
    return tokens[index]


def _starts_statement(tokens: list[Token], index: int) -> bool:
    """Is tokens[index] first in its statement? (`else` of a switch is; of `if c then a else b`
    it follows a value.)"""
    return index == 0 or tokens[index - 1].type in _SEPARATORS | {"CASE_END", "END"}
