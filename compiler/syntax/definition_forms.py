"""Located errors for forms written where they cannot stand: an `enum` inside a component
(definitions stand at the top level of a file) or as the right side of `type X = ...`, and a
`switch` value inside a larger expression (it stands alone right after `=`)."""
from __future__ import annotations

from lark import Token

from compiler.errors import DyadError, Span
from compiler.syntax.build_support import token_span

_BODIES = ("component", "analysis", "connector")


def misplaced_enum(tok: Token, tokens, index, innermost, span: Span) -> DyadError | None:
    """`component C  enum Mode = A | B ...` or `type Mode = enum A | B`."""
    if tok.type != "ENUM":
        return None
    following = tokens[index + 1] if index + 1 < len(tokens) else None
    name = following.value if following is not None and following.type == "NAME" else "Mode"
    if innermost is not None and innermost.kind in _BODIES:
        return DyadError(f"an `enum` is a definition of its own, declared at the top level of a "
                         f"file, not inside {innermost.title()}", span,
                         hint=f"move `enum {name} ...` above `{innermost.kind} {innermost.name}` "
                              f"(or into a file of its package) and declare the parameter "
                              f"`structural parameter p::{name} = {name}.Member()`")
    previous = tokens[index - 1] if index > 0 else None
    if previous is not None and previous.type == "EQUAL" and innermost is None:
        return DyadError("`type X = enum ...` is not a form: an enum is declared by itself", span,
                         hint="write `enum X = A | B`; an alias of it is `type Y = X`")
    return None


def switch_inside_expression(tok: Token, tokens, index, span: Span) -> DyadError | None:
    """`y = 2 * switch gear ...`: the word `switch` was read as a name, then `gear` followed it."""
    previous = tokens[index - 1] if index > 0 else None
    if previous is None or previous.type != "NAME" or previous.value != "switch" \
            or previous.line != tok.line or tok.type != "NAME":
        return None
    return DyadError("a `switch` value stands alone right after `=`, not inside a larger expression",
                     token_span(previous, span.file),
                     hint="give it a name of its own: `variable s::Real = switch ...`, then use `2 * s`")
