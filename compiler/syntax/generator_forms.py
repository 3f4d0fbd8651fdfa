"""The located error for a bracketless generator followed by more arguments: `f(x for i in 1:n, y)`."""
from __future__ import annotations

from lark import Token

from compiler.errors import DyadError, Span


def generator_with_more_arguments(tok: Token, tokens, index, expected: set[str], found: str,
                                  span: Span) -> DyadError | None:
    """`f(x[i] for i in 1:n, y)`: a bracketless generator is only ever a call's sole argument."""
    previous = tokens[index - 1] if 0 < index <= len(tokens) else None
    if previous is None or previous.type != "COMMA" or expected != {"NAME"}:
        return None
    depth, saw_for = 0, False
    for earlier in reversed(tokens[:index - 1]):
        if earlier.type in ("RPAR", "RSQB", "RBRACE"):
            depth += 1
        elif earlier.type in ("LPAR", "LSQB", "LBRACE"):
            if depth == 0:
                break
            depth -= 1
        elif earlier.type == "FOR" and depth == 0:
            saw_for = True
    else:
        return None
    if not saw_for or earlier.type != "LPAR":
        return None
    return DyadError(f"a generator `... for ...` must be the only argument of its call, found {found} "
                     "after it", span,
                     hint="put the generator in brackets to pass more arguments: "
                          "`f([x[i] for i in 1:n], y)`")
