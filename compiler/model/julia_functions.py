"""Functions a Dyad package defines in Julia, read (never run) from the package's `src/*.jl`.

Dyad has no function syntax of its own: a library's helper functions (unit conversions such as
`from_degC`, limiters) are Julia functions in the `src/` folder beside the `dyad/` folder of its
project (`Pkg/dyad/*.dyad`, `Pkg/src/*.jl`). dyadc cannot run Julia, but most such helpers are a
few assignments and one returned expression in the part of Julia that Dyad expressions share:

    function from_degC(Celsius)          # or the short form  from_degC(Celsius) = Celsius + 273.15
      Kelvin = Celsius - (-273.15)
      return Kelvin
    end

Those are read into a `JuliaFunction` (parameters, local assignments, result as Dyad expression
ASTs) and evaluated like an inlined expression at the call. Everything else (`if`/`for`/`while`
blocks, keyword arguments, names that are neither parameters nor earlier locals, ...) is kept as
an `UnreadableFunction` whose reason a call reports. Julia's `&` and `|` on conditions are read
as `&&` and `||` (their only meaning on Booleans). Nothing here executes the file.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, fields, is_dataclass
from pathlib import Path

from compiler.errors import DyadError
from compiler.syntax import ast

# Julia keywords that open a block closed by `end`
_BLOCK_OPENERS = {"function", "if", "for", "while", "let", "begin", "try", "do", "struct",
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


_TOKEN = _LazyPattern(r'"""(?:.|\n)*?"""|"(?:\\.|[^"\\\n])*"|#=(?:.|\n)*?=#|#[^\n]*|'
                    r"[A-Za-z_\u00a0-\uffff][\w!\u00a0-\uffff]*|\n|.", re.UNICODE)
_PARAMETER = _LazyPattern(r"^\s*([A-Za-z_\u00a0-\uffff][\w\u00a0-\uffff]*)\s*(?:::\s*[\w.{}, ]+)?\s*$")
_ASSIGNMENT = _LazyPattern(r"^\s*([A-Za-z_\u00a0-\uffff][\w\u00a0-\uffff]*)\s*=(?!=)")
_SHORT_FORM = _LazyPattern(r"([A-Za-z_\u00a0-\uffff][\w\u00a0-\uffff]*)\s*\(([^()]*)\)\s*=(?!=)")
_SEPARATORS = re.compile(r"[\n;]")
MAX_CALL_DEPTH = 32                   # a function calling itself would never stop being inlined


@dataclass(frozen=True)
class JuliaFunction:
    name: str                                   # qualified: `Pkg.from_degC`
    parameters: tuple[str, ...]
    locals: tuple[tuple[str, ast.Expr], ...]    # `name = expr` in order
    result: ast.Expr
    file: str
    line: int


@dataclass(frozen=True)
class UnreadableFunction:
    name: str
    reason: str
    file: str
    line: int

    def error(self, span) -> DyadError:
        return DyadError(f"function `{self.name}` is defined in Julia ({self.file}:{self.line}) in "
                         f"a form dyadc cannot read: {self.reason}", span,
                         hint="dyadc reads Julia functions made of assignments and one returned "
                              "expression; write the function's body into the equation instead")


def julia_source_files(package_folder: Path) -> list[Path]:
    """The `.jl` files of the Julia package that a Dyad package folder belongs to: `src/` beside
    the folder when the folder (or its link target) is the project's `dyad/` folder."""
    folder = package_folder.resolve()
    if folder.name != "dyad":
        return []
    src = folder.parent / "src"
    return sorted(src.glob("*.jl")) if src.is_dir() else []


def read_julia_functions(path: Path, package: str) -> dict[str, JuliaFunction | UnreadableFunction]:
    """Every top-level function of one Julia file, by qualified name (`package.name`)."""
    text = path.read_text(encoding="utf-8", errors="replace")
    out: dict[str, JuliaFunction | UnreadableFunction] = {}
    for name, head, body, offset in _top_level_functions(text):
        line = text.count("\n", 0, offset) + 1
        qualified = f"{package}.{name}"
        if qualified in out:
            first = out[qualified].line
            out[qualified] = UnreadableFunction(
                qualified, f"it has several methods (lines {first} and {line}); Julia chooses one "
                           f"by the types of the arguments when the model runs", str(path), first)
            continue
        try:
            out[qualified] = _read_function(qualified, head, body, text, offset, str(path), line)
        except _Unreadable as exc:
            out[qualified] = UnreadableFunction(qualified, str(exc), str(path), line)
    return out


class _Unreadable(Exception):
    pass


def _tokens(text: str):
    for match in _TOKEN.finditer(text):
        yield match.group(), match.start()


def _top_level_functions(text: str):
    """(name, parameter text, body text and its offset) of each top-level function: the long form
    `function f(args) ... end` and the short form `f(args) = expr` at the start of a line."""
    depth, bracket, start = 0, 0, None
    line_start = True
    for token, offset in _tokens(text):
        if token.startswith("#") or token.startswith('"'):
            continue
        if token in "([{":
            bracket += 1
        elif token in ")]}":
            bracket -= 1
        elif bracket == 0 and token in _BLOCK_OPENERS:
            if depth == 0 and token == "function":
                start = offset
            depth += 1
        elif bracket == 0 and token == "end" and depth > 0:
            depth -= 1
            if depth == 0 and start is not None:
                found = _long_form(text[start:offset], start)
                if found:
                    yield found
                start = None
        elif depth == 0 and bracket == 0 and line_start:
            short = _SHORT_FORM.match(text, offset)
            if short:
                end = text.find("\n", short.end())
                end = len(text) if end < 0 else end
                yield short[1], short[2], text[short.end():end], short.end()
        if token == "\n":
            line_start = True
        elif not token.isspace():
            line_start = False


def _long_form(text: str, offset: int):
    match = re.match(r"function\s+([A-Za-z_\u00a0-\uffff][\w\u00a0-\uffff]*)\s*\(", text)
    if not match:
        return None
    depth = 0
    for i in range(match.end() - 1, len(text)):
        depth += {"(": 1, ")": -1}.get(text[i], 0)
        if depth == 0:
            return match[1], text[match.end():i], text[i + 1:], offset + i + 1
    return None


def _statements(body: str, offset: int):
    """Top-level statements of a body (split at line breaks and `;` outside brackets), with the
    offset of each, comments removed."""
    current, begin, bracket = [], None, 0
    for token, at in _tokens(body):
        if token.startswith("#"):
            continue
        if token in "([{":
            bracket += 1
        elif token in ")]}":
            bracket -= 1
        if bracket == 0 and _SEPARATORS.fullmatch(token):
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


def _read_function(name, head, body, text, body_offset, path, line) -> JuliaFunction:
    if ";" in head:
        raise _Unreadable("it has keyword arguments")
    parameters = []
    for item in filter(str.strip, head.split(",")):
        match = _PARAMETER.match(item)
        if not match:
            raise _Unreadable(f"parameter `{item.strip()}` is not a plain name")
        parameters.append(match[1])
    known = set(parameters)
    locals_: list[tuple[str, ast.Expr]] = []
    result = None
    for statement, at in _statements(body, body_offset):
        if result is not None:
            raise _Unreadable("it has statements after its `return`")
        stripped = statement.strip()
        first = re.match(r"[A-Za-z_]\w*", stripped)
        if first and first.group() in _BLOCK_OPENERS | {"local", "global", "const", "elseif",
                                                        "else"}:
            raise _Unreadable(f"it uses `{first.group()}`")
        if first and first.group() == "return":
            result = _expression(stripped[len("return"):], text, at + len("return"), path, known)
            continue
        assignment = _ASSIGNMENT.match(statement)
        if assignment:
            value = _expression(statement[assignment.end():], text, at + assignment.end(),
                                path, known)
            locals_.append((assignment[1], value))
            known.add(assignment[1])
            continue
        result = _expression(statement, text, at, path, known)
    if result is None:
        raise _Unreadable("it returns nothing")
    return JuliaFunction(name, tuple(parameters), tuple(locals_), result, path, line)


def _expression(source: str, text: str, offset: int, path: str, known: set[str]) -> ast.Expr:
    from compiler.syntax.parser import parse_expression
    translated = re.sub(r"(?<![&|])([&|])(?![&|])", r"\1\1", source)
    line = text.count("\n", 0, offset)
    column = offset - (text.rfind("\n", 0, offset) + 1)
    try:
        expr = parse_expression("\n" * line + " " * column + translated.strip(), path)
    except DyadError as exc:
        raise _Unreadable(f"`{source.strip()}` is not a Dyad expression ({exc.message})") from None
    for ref in _refs(expr):
        head = ref.parts[0].name
        if head not in known and head not in ("pi", "π", "Inf"):
            raise _Unreadable(f"it uses `{ref.dotted}`, which is neither a parameter nor a local")
    return expr


def _refs(node):
    stack = [node]
    while stack:
        item = stack.pop()
        if isinstance(item, ast.Ref):
            yield item
        if isinstance(item, (tuple, list)):
            stack.extend(item)
        elif is_dataclass(item):
            stack.extend(getattr(item, f.name) for f in fields(item) if f.name != "span")
