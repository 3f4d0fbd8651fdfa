"""Julia structs and the methods of Julia functions, read (never run) from a package's `src/*.jl`.

A Dyad library's media are Julia structs with default field values, and the functions of a medium
have one method per medium type, which Julia picks by the type of the argument:

    @kwdef struct Oil <: AbstractMedium          # fields with defaults, read as Dyad expressions
      density = 850
      let_gas = false
    end
    density(medium::Oil, p) = ...                # one method per medium type
    density(medium::Water, p) = ...

dyadc reads both so that a call with a known medium (compiler/julia/objects.py) can pick the
method the way Julia would for these simple signatures: the method whose first typed parameter
names the medium's struct, else one naming its declared supertype.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from compiler.julia.bodies import JuliaFunction, read_function
from compiler.julia.functions import UnreadableFunction, top_level_functions
from compiler.julia.source import BLOCK_OPENERS, Unreadable, expression
from compiler.syntax import ast

_STRUCT = re.compile(r"^(?:(?:Base\.)?@kwdef\s+)?(?:mutable\s+)?struct\s+(\w+)"
                     r"(?:\s*<:\s*([\w.]+))?\s*$")
_FIELD = re.compile(r"^\s*(\w+)\s*(?:::\s*[\w.{}, ]+?)?\s*(?:=\s*(.+?))?\s*$")


@dataclass(frozen=True)
class JuliaStruct:
    name: str                                       # qualified: `Pkg.Oil`
    supertype: str | None                           # as written: `AbstractMedium`
    fields: tuple[tuple[str, ast.Expr | None], ...]  # name and default value, in order
    file: str
    line: int


@dataclass(frozen=True)
class JuliaDefinitions:
    structs: dict[str, JuliaStruct | UnreadableFunction]
    methods: dict[str, tuple[JuliaFunction | UnreadableFunction, ...]]


def read_julia_definitions(paths: list[Path], package: str) -> JuliaDefinitions:
    structs: dict = {}
    methods: dict[str, list] = {}
    for path in paths:
        text = path.read_text(encoding="utf-8", errors="replace")
        structs.update(_structs(text, str(path), package))
        for name, head, body, offset in top_level_functions(text):
            line = text.count("\n", 0, offset) + 1
            qualified = f"{package}.{name}"
            try:
                found = read_function(qualified, head, body, text, offset, str(path), line)
            except Unreadable as exc:
                found = UnreadableFunction(qualified, str(exc), str(path), line)
            methods.setdefault(qualified, []).append(found)
    return JuliaDefinitions(structs, {name: tuple(found) for name, found in methods.items()})


def _structs(text: str, path: str, package: str):
    lines = text.splitlines()
    index = 0
    while index < len(lines):
        head = _STRUCT.match(lines[index].split("#")[0].rstrip())
        if not head:
            index += 1
            continue
        qualified, start = f"{package}.{head[1]}", index
        fields: list[tuple[str, ast.Expr | None]] = []
        reason = None
        index += 1
        while index < len(lines) and lines[index].split("#")[0].strip() != "end":
            content = lines[index].split("#")[0]
            word = content.strip().split(" ")[0].split("(")[0]
            if word in BLOCK_OPENERS:
                reason = f"struct `{head[1]}` has an inner `{word}`"
                break
            field = _FIELD.match(content) if content.strip() else None
            if content.strip() and not field:
                reason = f"struct `{head[1]}` has a field dyadc cannot read: `{content.strip()}`"
            elif field:
                offset = sum(len(line) + 1 for line in lines[:index]) + (field.start(2)
                                                                         if field[2] else 0)
                try:
                    value = expression(field[2], text, offset, path, set()) if field[2] else None
                except Unreadable as exc:
                    reason = f"field `{field[1]}` of struct `{head[1]}`: {exc}"
                    value = None
                fields.append((field[1], value))
            index += 1
        if reason:
            yield qualified, UnreadableFunction(qualified, reason, path, start + 1)
        else:
            yield qualified, JuliaStruct(qualified, head[2], tuple(fields), path, start + 1)
        index += 1


def pick_method(methods, struct: JuliaStruct, position: int) -> JuliaFunction | UnreadableFunction | None:
    """The method for an object of type `struct` as argument `position`: the one typed with the
    struct's own name, else one typed with its supertype (Julia's choice for these signatures)."""
    own, parent = struct.name.rpartition(".")[2], (struct.supertype or "").rpartition(".")[2]
    for wanted in (own, parent):
        for method in methods:
            types = getattr(method, "types", ())
            if wanted and position < len(types) and (types[position] or "").rpartition(".")[2] == wanted:
                return method
    return None
