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
    # trailing parameters with a default value (`delta = 1`), in order; also in `parameters`
    defaults: tuple[tuple[str, ast.Expr], ...] = ()

    def accepts(self, count: int) -> bool:
        return len(self.parameters) - len(self.defaults) <= count <= len(self.parameters)

    def arity(self) -> str:
        least = len(self.parameters) - len(self.defaults)
        return str(least) if least == len(self.parameters) else f"{least} to {len(self.parameters)}"

    def defaults_after(self, count: int) -> tuple[tuple[str, ast.Expr], ...]:
        """The defaults of the parameters a call with `count` arguments leaves out."""
        return self.defaults[len(self.defaults) - (len(self.parameters) - count):] \
            if count < len(self.parameters) else ()


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
    parameters: list[str] = []
    defaults: list[tuple[str, ast.Expr]] = []
    head_offset = text.rfind(head, 0, body_offset)
    for item in filter(str.strip, head.split(",")):
        name_part, equals, default = item.partition("=")
        match = _PARAMETER.match(name_part)
        if not match:
            raise _Unreadable(f"parameter `{item.strip()}` is not a plain name")
        if equals:
            # a default may use the parameters before it, like Julia's
            at = head_offset + head.index(item) + len(name_part) + 1
            defaults.append((match[1], _expression(default, text, at, path, set(parameters))))
        elif defaults:
            raise _Unreadable(f"parameter `{match[1]}` without a default follows one with a default")
        parameters.append(match[1])
    known = set(parameters)
    locals_: list[tuple[str, ast.Expr]] = []
    statements = list(_statements(body, body_offset))
    index = 0
    while index < len(statements):
        statement, at = statements[index]
        stripped = statement.strip()
        first = _first_word(stripped)
        if first in ("if", "return") or index == len(statements) - 1:
            result = _tail_value(statements[index:], text, path, known)
            return JuliaFunction(name, tuple(parameters), tuple(locals_), result, path, line,
                                 tuple(defaults))
        if first in _BLOCK_OPENERS | {"local", "global", "const", "elseif", "else"}:
            raise _Unreadable(f"it uses `{first}`")
        assignment = _ASSIGNMENT.match(statement)
        if not assignment:
            raise _Unreadable(f"`{stripped}` is neither an assignment nor its returned value")
        value = _expression(statement[assignment.end():], text, at + assignment.end(), path, known)
        locals_.append((assignment[1], value))
        known.add(assignment[1])
        index += 1
    raise _Unreadable("it returns nothing")


def _first_word(statement: str) -> str | None:
    match = re.match(r"[A-Za-z_]\w*", statement)
    return match.group() if match else None


def _tail_value(statements, text, path, known) -> ast.Expr:
    """The value that the last statements of a body return: one `return expr` (or a last
    expression), or an `if`/`elseif`/`else` chain whose branches each return one; a chain
    without `else` falls through to the statements after its `end`."""
    statement, at = statements[0]
    stripped = statement.strip()
    first = _first_word(stripped)
    if first == "if":
        branches, otherwise, rest = _if_chain(statements)
        if otherwise is None:
            if not rest:
                raise _Unreadable("an `if` without `else` is its last statement")
            otherwise = rest
        elif rest:
            raise _Unreadable("it has statements after an `if` whose branches all return")
        selected = []
        for (condition, cond_at), branch in branches:
            if not branch or _first_word(branch[0][0].strip()) not in ("return", "if"):
                raise _Unreadable("an `if` branch does not end in `return`")
            selected.append((_condition(condition, text, cond_at, path, known),
                             _tail_value(branch, text, path, known)))
        value = _tail_value(otherwise, text, path, known)
        for condition, then in reversed(selected):
            value = ast.IfExpr(condition, then, value)
        return value
    if len(statements) > 1:
        raise _Unreadable("it has statements after its `return`")
    if first == "return":
        return _expression(stripped[len("return"):], text, at + len("return"), path, known)
    if first in _BLOCK_OPENERS | {"local", "global", "const", "elseif", "else", "end"} \
            or _ASSIGNMENT.match(statement):
        raise _Unreadable(f"it uses `{first}`" if first != "end" else "it returns nothing")
    return _expression(statement, text, at, path, known)


def _if_chain(statements):
    """([((condition text, its offset), branch statements)...], else statements or None, the
    statements after the chain's `end`) of an `if` chain starting at statements[0]."""
    branches, current, otherwise, depth = [], None, None, 0
    for index, (statement, at) in enumerate(statements):
        stripped = statement.strip()
        word = _first_word(stripped)
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
        elif word in _BLOCK_OPENERS:
            depth += 1
        current.append((statement, at))
    raise _Unreadable("an `if` without its `end`")


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
        return _expression(source, text, offset, path, known)
    chained = " && ".join(f"({operands[k]} {operators[k]} {operands[k + 1]})"
                          for k in range(len(operators)))
    return _expression(chained, text, offset, path, known)


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
