"""The blocks (definitions, `for` loops, `if` blocks, `switch`es) still open at a token of a file
that failed to parse: a scan of the tokens that mirrors the grammar's `end`s, for errors such as
"expected `end` to close component `C`"."""
from __future__ import annotations

from dataclasses import dataclass

from lark import Token


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

