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
ASTs; compiler/julia/bodies.py, which also reads `if`/`elseif`/`else` chains of returns and
default arguments) and evaluated like an inlined expression at the call. Everything else (loops,
keyword arguments, names that are neither parameters nor earlier locals, ...) is kept as an
`UnreadableFunction` whose reason a call reports. Julia's `&` and `|` on conditions are read as
`&&` and `||` (their only meaning on Booleans). Nothing here executes the file.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from compiler.errors import DyadError
from compiler.julia.bodies import JuliaFunction, read_function
from compiler.julia.source import BLOCK_OPENERS, SHORT_FORM, Unreadable, tokens

__all__ = ["JuliaFunction", "UnreadableFunction", "julia_source_files",
           "read_julia_functions"]


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
    the folder when the folder (or its link target) is a project's `dyad/` folder, else `src/`
    inside it (a top-level package folder of a library, as dyadc's own HydraulicComponents)."""
    folder = package_folder.resolve()
    src = folder.parent / "src" if folder.name == "dyad" else folder / "src"
    return sorted(src.glob("*.jl")) if src.is_dir() else []


def read_julia_functions(path: Path, package: str) -> dict[str, JuliaFunction | UnreadableFunction]:
    """Every top-level function of one Julia file, by qualified name (`package.name`)."""
    text = path.read_text(encoding="utf-8", errors="replace")
    out: dict[str, JuliaFunction | UnreadableFunction] = {}
    for name, head, body, offset in top_level_functions(text):
        line = text.count("\n", 0, offset) + 1
        qualified = f"{package}.{name}"
        if qualified in out:
            first = out[qualified].line
            out[qualified] = UnreadableFunction(
                qualified, f"it has several methods (lines {first} and {line}); Julia chooses one "
                           f"by the types of the arguments when the model runs", str(path), first)
            continue
        try:
            out[qualified] = read_function(qualified, head, body, text, offset, str(path), line)
        except Unreadable as exc:
            out[qualified] = UnreadableFunction(qualified, str(exc), str(path), line)
    return out


def top_level_functions(text: str):
    """(name, parameter text, body text and its offset) of each top-level function: the long form
    `function f(args) ... end` and the short form `f(args) = expr` at the start of a line."""
    depth, bracket, start = 0, 0, None
    line_start = True
    for token, offset in tokens(text):
        if token.startswith("#") or token.startswith('"'):
            continue
        if token in "([{":
            bracket += 1
        elif token in ")]}":
            bracket -= 1
        elif bracket == 0 and token in BLOCK_OPENERS:
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
            short = SHORT_FORM.match(text, offset)
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


