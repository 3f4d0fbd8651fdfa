"""The body of a Julia function read as Dyad expressions (never run): local assignments, then one
returned value, which may be an `if`/`elseif`/`else` chain whose branches each return one (an `if`
without `else` falls through to what follows), with Julia's chained comparisons `a < b < c` read
as `a < b && b < c`, and trailing parameters with default values."""
from __future__ import annotations

import re
from dataclasses import dataclass

from compiler.julia.source import ASSIGNMENT, BLOCK_OPENERS, PARAMETER, Unreadable, \
    expression, first_word, statements as split_statements
from compiler.syntax import ast

_TYPE = re.compile(r"::\s*([\w.]+)")
_UNPACK = re.compile(r"^@unpack\s+([\w\s,]+?)\s*=\s*(\w+)$")


@dataclass(frozen=True)
class JuliaFunction:
    name: str                                   # qualified: `Pkg.from_degC`
    parameters: tuple[str, ...]
    locals: tuple[tuple[str, ast.Expr], ...]    # `name = expr` in order
    result: ast.Expr
    file: str
    line: int
    # trailing parameters with a default value (`delta = 1`), in order; also in `parameters`
    defaults: tuple[tuple[str, ast.Expr], ...] = ()
    # `@unpack a, b = medium`: (a, medium), ...: fields of an object argument, bound by the caller
    # that knows the object (compiler/julia/objects.py)
    unpacks: tuple[tuple[str, str], ...] = ()
    types: tuple[str | None, ...] = ()          # each parameter's `::Type`, None if untyped

    def accepts(self, count: int) -> bool:
        return len(self.parameters) - len(self.defaults) <= count <= len(self.parameters)

    def arity(self) -> str:
        least = len(self.parameters) - len(self.defaults)
        return str(least) if least == len(self.parameters) else f"{least} to {len(self.parameters)}"

    def defaults_after(self, count: int) -> tuple[tuple[str, ast.Expr], ...]:
        """The defaults of the parameters a call with `count` arguments leaves out."""
        return self.defaults[len(self.defaults) - (len(self.parameters) - count):] \
            if count < len(self.parameters) else ()


def read_function(name, head, body, text, body_offset, path, line) -> JuliaFunction:
    if ";" in head:
        raise Unreadable("it has keyword arguments")
    parameters: list[str] = []
    types: list[str | None] = []
    defaults: list[tuple[str, ast.Expr]] = []
    head_offset = text.rfind(head, 0, body_offset)
    for item in filter(str.strip, head.split(",")):
        name_part, equals, default = item.partition("=")
        match = PARAMETER.match(name_part)
        if not match:
            raise Unreadable(f"parameter `{item.strip()}` is not a plain name")
        if equals:
            # a default may use the parameters before it, like Julia's
            at = head_offset + head.index(item) + len(name_part) + 1
            defaults.append((match[1], expression(default, text, at, path, set(parameters))))
        elif defaults:
            raise Unreadable(f"parameter `{match[1]}` without a default follows one with a default")
        parameters.append(match[1])
        typed = _TYPE.search(name_part)
        types.append(typed[1] if typed else None)
    known = set(parameters)
    locals_: list[tuple[str, ast.Expr]] = []
    unpacks: list[tuple[str, str]] = []
    statements = list(split_statements(body, body_offset))
    index = 0
    while index < len(statements):
        statement, at = statements[index]
        stripped = statement.strip()
        first = first_word(stripped)
        if first in ("if", "return") or index == len(statements) - 1:
            result = _tail_value(statements[index:], text, path, known)
            return JuliaFunction(name, tuple(parameters), tuple(locals_), result, path, line,
                                 tuple(defaults), tuple(unpacks), tuple(types))
        unpack = _UNPACK.match(stripped)
        if unpack and unpack[2] in parameters and not locals_:
            # the fields of an argument, read before any local so that the caller can bind them
            for field_name in (n.strip() for n in unpack[1].split(",")):
                unpacks.append((field_name, unpack[2]))
                known.add(field_name)
            index += 1
            continue
        if first in BLOCK_OPENERS | {"local", "global", "const", "elseif", "else"}:
            raise Unreadable(f"it uses `{first}`")
        assignment = ASSIGNMENT.match(statement)
        if not assignment:
            raise Unreadable(f"`{stripped}` is neither an assignment nor its returned value")
        value = expression(statement[assignment.end():], text, at + assignment.end(), path, known)
        locals_.append((assignment[1], value))
        known.add(assignment[1])
        index += 1
    raise Unreadable("it returns nothing")


def _tail_value(statements, text, path, known) -> ast.Expr:
    """The value that the last statements of a body return: one `return expr` (or a last
    expression), or an `if`/`elseif`/`else` chain whose branches each return one; a chain
    without `else` falls through to the statements after its `end`."""
    statement, at = statements[0]
    stripped = statement.strip()
    first = first_word(stripped)
    if first == "if":
        branches, otherwise, rest = _if_chain(statements)
        if otherwise is None:
            if not rest:
                raise Unreadable("an `if` without `else` is its last statement")
            otherwise = rest
        elif rest:
            raise Unreadable("it has statements after an `if` whose branches all return")
        selected = []
        for (condition, cond_at), branch in branches:
            if not branch or first_word(branch[0][0].strip()) not in ("return", "if"):
                raise Unreadable("an `if` branch does not end in `return`")
            selected.append((_condition(condition, text, cond_at, path, known),
                             _tail_value(branch, text, path, known)))
        value = _tail_value(otherwise, text, path, known)
        for condition, then in reversed(selected):
            value = ast.IfExpr(condition, then, value)
        return value
    if len(statements) > 1:
        raise Unreadable("it has statements after its `return`")
    if first == "return":
        return expression(stripped[len("return"):], text, at + len("return"), path, known)
    if first in BLOCK_OPENERS | {"local", "global", "const", "elseif", "else", "end"} \
            or ASSIGNMENT.match(statement):
        raise Unreadable(f"it uses `{first}`" if first != "end" else "it returns nothing")
    return expression(statement, text, at, path, known)


def _if_chain(statements):
    """([((condition text, its offset), branch statements)...], else statements or None, the
    statements after the chain's `end`) of an `if` chain starting at statements[0]."""
    branches, current, otherwise, depth = [], None, None, 0
    for index, (statement, at) in enumerate(statements):
        stripped = statement.strip()
        word = first_word(stripped)
        if (index == 0 and word == "if") or (depth == 1 and word == "elseif"):
            keyword = len(statement) - len(statement.lstrip()) + len(word)
            current = []
            branches.append(((statement[keyword:], at + keyword), current))
            depth = 1
            continue
        if depth == 1 and word == "else" and stripped == "else":
            current = otherwise = []
            continue
        if word == "end" and stripped == "end":
            depth -= 1
            if depth == 0:
                return branches, otherwise, statements[index + 1:]
        elif word in BLOCK_OPENERS:
            depth += 1
        current.append((statement, at))
    raise Unreadable("an `if` without its `end`")


_COMPARISONS = ("<=", ">=", "==", "!=", "<", ">")


def _condition(source: str, text: str, offset: int, path: str, known: set[str]) -> ast.Expr:
    """A condition; Julia's chained comparison `a < b < c` is read as `a < b && b < c`."""
    operands, operators, depth, start, i = [], [], 0, 0, 0
    while i < len(source):
        char = source[i]
        depth += {"(": 1, "[": 1, ")": -1, "]": -1}.get(char, 0)
        operator = next((op for op in _COMPARISONS if source.startswith(op, i)), None) \
            if depth == 0 else None
        if operator:
            operands.append(source[start:i])
            operators.append(operator)
            i = start = i + len(operator)
            continue
        i += 1
    operands.append(source[start:])
    if len(operators) < 2 or "&" in source or "|" in source:
        return expression(source, text, offset, path, known)
    chained = " && ".join(f"({operands[k]} {operators[k]} {operands[k + 1]})"
                          for k in range(len(operators)))
    return expression(chained, text, offset, path, known)


