"""Lexical pieces shared by the readers of Julia sources (compiler/julia/functions.py, its
bodies in bodies.py, structs and methods in methods.py): tokens, statements, and Julia
expressions read as Dyad expression ASTs. Nothing here executes Julia."""
from __future__ import annotations

import re
from dataclasses import fields, is_dataclass

from compiler.errors import DyadError
from compiler.julia import rewrite
from compiler.syntax import ast

# Julia keywords that open a block closed by `end`
BLOCK_OPENERS = {"function", "if", "for", "while", "let", "begin", "try", "do", "struct",
                 "module", "baremodule", "quote", "macro", "mutable"}


class _LazyPattern:
    """re.compile(...) on first use: these character ranges take 5-8 ms each to compile, paid by
    every compile that imports this module, not only by those reading Julia sources."""

    def __init__(self, *arguments):
        self._arguments, self._pattern = arguments, None

    def __getattr__(self, name):
        if self._pattern is None:
            self._pattern = re.compile(*self._arguments)
        return getattr(self._pattern, name)


TOKEN = _LazyPattern(r'"""(?:.|\n)*?"""|"(?:\\.|[^"\\\n])*"|#=(?:.|\n)*?=#|#[^\n]*|'
                    r"[A-Za-z_\u00a0-\uffff][\w!\u00a0-\uffff]*|\n|.", re.UNICODE)
PARAMETER = _LazyPattern(r"^\s*([A-Za-z_\u00a0-\uffff][\w\u00a0-\uffff]*)\s*(?:::\s*[\w.{}, ]+)?\s*$")
ASSIGNMENT = _LazyPattern(r"^\s*([A-Za-z_\u00a0-\uffff][\w\u00a0-\uffff]*)\s*=(?!=)")
SHORT_FORM = _LazyPattern(r"([A-Za-z_\u00a0-\uffff][\w\u00a0-\uffff]*)\s*\(([^()]*)\)\s*=(?!=)")
SEPARATORS = re.compile(r"[\n;]")


class Unreadable(Exception):
    pass


def tokens(text: str):
    for match in TOKEN.finditer(text):
        yield match.group(), match.start()


def statements(body: str, offset: int):
    """Top-level statements of a body (split at line breaks and `;` outside brackets), with the
    offset of each, comments removed."""
    current, begin, bracket = [], None, 0
    for token, at in tokens(body):
        if token.startswith("#"):
            continue
        if token in "([{":
            bracket += 1
        elif token in ")]}":
            bracket -= 1
        if bracket == 0 and SEPARATORS.fullmatch(token):
            if "".join(current).strip():
                yield "".join(current), begin
            current, begin = [], None
            continue
        if begin is None and not token.isspace():
            begin = offset + at
        if begin is not None:
            current.append(token)
    if "".join(current).strip():
        yield "".join(current), begin


def first_word(statement: str) -> str | None:
    match = re.match(r"[A-Za-z_]\w*", statement)
    return match.group() if match else None


def expression(source: str, text: str, offset: int, path: str, known: set[str]) -> ast.Expr:
    from compiler.syntax.parser import parse_expression
    translated = re.sub(r"(?<![&|])([&|])(?![&|])", r"\1\1", rewrite.translate(source))
    line = text.count("\n", 0, offset)
    column = offset - (text.rfind("\n", 0, offset) + 1)
    try:
        expr = parse_expression("\n" * line + " " * column + translated.strip(), path)
    except DyadError as exc:
        raise Unreadable(f"`{source.strip()}` is not a Dyad expression ({exc.message})") from None
    for ref in refs(expr):
        head = ref.parts[0].name
        if head not in known and head not in ("pi", "π", "Inf"):
            raise Unreadable(f"it uses `{ref.dotted}`, which is neither a parameter nor a local")
    return expr


def refs(node):
    """The references in `node` to names it does not bind itself: the variables of a
    comprehension's `for` clauses are its own inside it (`[L[j] for j in 1:N]` uses `L`, `N`)."""
    stack = [(node, frozenset())]
    while stack:
        item, bound = stack.pop()
        if isinstance(item, ast.Ref) and item.parts[0].name not in bound:
            yield item
        if isinstance(item, ast.Comprehension):
            bound = bound | {it.variable for clause in item.clauses for it in clause.iterators}
        if isinstance(item, (tuple, list)):
            stack.extend((part, bound) for part in item)
        elif is_dataclass(item):
            stack.extend((getattr(item, f.name), bound) for f in fields(item) if f.name != "span")
