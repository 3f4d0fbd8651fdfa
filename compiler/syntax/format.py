"""Canonical reprint of an AST: 2-space indentation, one declaration per line, minimal parentheses
(the expressions: compiler/syntax/format_expressions.py).

The contract is `parse(format_file(f)) == f` (spans ignored). Layout follows the seed sources:
`relations`, `metadata` and `end` start at the definition's column, everything else is indented.
"""
from __future__ import annotations

from compiler.syntax import ast
from compiler.syntax.format_expressions import format_expr, format_iterators, format_string

INDENT = "  "


class Line(str):
    """A printed line and the span of the source node it prints (None: a keyword line such as
    `relations` or `end`); compiler/syntax/format_comments.py puts the comments back by it."""
    span = None


def _at(text: str, span) -> Line:
    line = Line(text)
    line.span = span
    return line


# ----------------------------------------------------------------------------- declarations

def _modifications(mods) -> str:
    return ", ".join(_modification(m) for m in mods)


def _modification(m: ast.Modification) -> str:
    text = ("final " if m.final else "") + m.name
    if m.nested:
        text += f"({_modifications(m.nested)})"
    if m.value is not None:
        text += f" = {format_expr(m.value)}"
    return text


def _type_spec(t: ast.TypeSpec) -> str:
    text = t.name
    if t.dims:
        text += f"[{', '.join(format_expr(d) for d in t.dims)}]"
    if t.modifications:
        text += f"({_modifications(t.modifications)})"
    return text


def _suffix(condition, metadata, link=None) -> str:
    text = ""
    if condition is not None:
        text += f" if {format_expr(condition)}"
    if metadata is not None:
        text += f" {metadata}"
    if link is not None:
        text += f" {{^{link}}}"
    return text


def _typed(d: ast.TypedDecl) -> str:
    text = f"{d.kind + ' ' if d.kind else ''}{d.name}::{_type_spec(d.type)}"
    if d.value is not None:
        text += f" = {format_expr(d.value)}"
    return text


def _doc_lines(doc: str | None, indent: str) -> list[str]:
    return [] if doc is None else [indent + format_string(doc)]


def _declaration(d, indent: str) -> list[str]:
    lines = _doc_lines(d.doc, indent)
    if isinstance(d, ast.ParameterDecl):
        keyword = {"parameter": "parameter", "structural": "structural parameter",
                   "constant": "constant"}[d.variability]
        text = f"{'final ' if d.final else ''}{keyword} {d.name}::{_type_spec(d.type)}"
        if d.default is not None:
            text += f" = {format_expr(d.default)}"
    elif isinstance(d, ast.VariableDecl):
        text = f"{d.causality or 'variable'} {d.name}::{_type_spec(d.type)}"
        if d.binding is not None:
            text += f" = {format_expr(d.binding)}"
        elif d.initial is not None:
            text += f" = initial {format_expr(d.initial)}"
    elif isinstance(d, ast.ComponentDecl):
        call = f"{d.type_name}({_modifications(d.modifications)})"
        if d.iterators:
            call = f"[{call} for {format_iterators(d.iterators)}]"
        text = f"{d.name} = {call}"
    elif isinstance(d, ast.TypedDecl):
        text = _typed(d)
    else:
        raise TypeError(f"not a declaration: {d!r}")
    lines.append(_at(indent + text + _suffix(d.condition, d.metadata, d.link), d.span))
    return lines


def _extends(e: ast.Extends, indent: str) -> list[str]:
    text = f"extends {e.type_name}"
    if e.modifications:
        text += f"({_modifications(e.modifications)})"
    text += _suffix(None, e.metadata, e.link)
    return _doc_lines(e.doc, indent) + [_at(indent + text, e.span)]


# -------------------------------------------------------------------------------- relations

def _relation(r, indent: str) -> list[str]:
    if isinstance(r, ast.Equation):
        keyword = "initial " if r.initial else ""
        return _doc_lines(r.doc, indent) + [_at(
            f"{indent}{keyword}{format_expr(r.lhs)} = {format_expr(r.rhs)}"
            + _suffix(None, r.metadata, r.link), r.span)]
    if isinstance(r, ast.Guess):
        return _doc_lines(r.doc, indent) + [_at(
            f"{indent}guess {format_expr(r.target)} = {format_expr(r.value)}", r.span)]
    if isinstance(r, (ast.Connect, ast.Continuity)):
        if isinstance(r, ast.Continuity):
            head = "continuity"
        elif r.analysis_point is not None:
            head = f"{r.analysis_point}: analysis_point"
        else:
            head = "connect"
        text = f"{head}({', '.join(format_expr(x) for x in r.refs)})"
        return _doc_lines(r.doc, indent) + [_at(indent + text + _suffix(None, r.metadata, r.link),
                                                r.span)]
    if isinstance(r, ast.Switch):
        lines = _doc_lines(r.doc, indent) + [_at(f"{indent}switch {format_expr(r.subject)}", r.span)]
        case_end = [f"{indent}{INDENT}end"] if r.closed_cases else []
        for case in r.cases:
            lines.append(f"{indent}{INDENT}case {', '.join(case.names)}")
            lines += _relations(case.body, indent + INDENT * 2) + case_end
        if r.otherwise:
            lines.append(f"{indent}{INDENT}else")
            lines += _relations(r.otherwise, indent + INDENT * 2) + case_end
        return lines + [f"{indent}end"]
    if isinstance(r, ast.ForLoop):
        lines = _doc_lines(r.doc, indent) + [_at(f"{indent}for {format_iterators(r.iterators)}", r.span)]
        lines += _relations(r.body, indent + INDENT)
        return lines + [f"{indent}end"]
    if isinstance(r, ast.IfRelation):
        lines = _doc_lines(r.doc, indent)
        for index, branch in enumerate(r.branches):
            keyword = "if" if index == 0 else "elseif"
            header = f"{indent}{keyword} {format_expr(branch.condition)}"
            lines.append(_at(header, r.span) if index == 0 else header)
            lines += _relations(branch.body, indent + INDENT)
        if r.otherwise:
            lines.append(f"{indent}else")
            lines += _relations(r.otherwise, indent + INDENT)
        return lines + [f"{indent}end"]
    raise TypeError(f"not a relation: {r!r}")


def _relations(relations, indent: str) -> list[str]:
    return [line for r in relations for line in _relation(r, indent)]


# ------------------------------------------------------------------------------ definitions

def _definition(d) -> list[str]:
    lines = _doc_lines(d.doc, "")
    if isinstance(d, (ast.ComponentDef, ast.AnalysisDef)):
        words = []
        if d.partial:
            words.append("partial")
        if getattr(d, "external", False):
            words.append("external")
        if getattr(d, "prefix", None):
            words.append(d.prefix)
        words.append("analysis" if isinstance(d, ast.AnalysisDef) else "component")
        lines.append(_at(f"{' '.join(words)} {d.name}", d.span))
        for e in d.extends:
            lines += _extends(e, INDENT)
        for decl in d.declarations:
            lines += _declaration(decl, INDENT)
        if d.relations:
            lines.append("relations")
            lines += _relations(d.relations, INDENT)
        if d.metadata is not None:
            lines.append(f"metadata {d.metadata}")
        lines.append("end")
    elif isinstance(d, ast.ConnectorDef):
        lines.append(_at(f"{'partial ' if d.partial else ''}connector {d.name}", d.span))
        for f in d.fields:
            lines += _doc_lines(f.doc, INDENT)
            value = f" = {format_expr(f.value)}" if f.value is not None else ""
            lines.append(_at(f"{INDENT}{f.kind} {f.name}::{_type_spec(f.type)}{value}"
                             + _suffix(None, f.metadata, f.link), f.span))
        if d.metadata is not None:
            lines.append(f"metadata {d.metadata}")
        lines.append("end")
    elif isinstance(d, ast.SignalConnectorDef):
        lines.append(_at(f"connector {d.name} = {d.causality} {_type_spec(d.type)}"
                         + _suffix(None, d.metadata, d.link), d.span))
    elif isinstance(d, ast.TypeDef):
        lines.append(_at(f"type {d.name} = {_type_spec(d.base)}", d.span))
    elif isinstance(d, ast.EnumDef):
        members = [m + (f"({', '.join(_typed(f) for f in d.fields[i])})" if d.fields
                        and d.fields[i] else "") for i, m in enumerate(d.members)]
        lines.append(_at(f"enum {d.name} = {' | '.join(members)}", d.span))
    elif isinstance(d, ast.FunctionTypeDef):
        params = ", ".join(f"{p.name or ''}::{_type_spec(p.type)}" for p in d.params)
        lines.append(_at(f"type {d.name} = func({params})::{_type_spec(d.result)}", d.span))
    elif isinstance(d, ast.StructDef):
        lines.append(_at(f"struct {d.name}", d.span))
        for f in d.fields:
            lines += _declaration(f, INDENT)
        lines.append("end")
    else:
        raise TypeError(f"not a definition: {d!r}")
    return lines


def format_blocks(file: ast.File) -> list[list[str]]:
    """The printed file as blocks of lines (the `using` lines, then one block per definition),
    which a blank line separates."""
    blocks = []
    if file.usings:
        blocks.append([_at(f"using {u.written}" + (f": {u.listed}" if u.names else ""), u.span)
                       for u in file.usings])
    blocks += [_definition(d) for d in file.definitions]
    return blocks


def format_file(file: ast.File) -> str:
    """The canonical text of `file`, without its comments (`format_comments.format_source` keeps
    them)."""
    return "\n\n".join("\n".join(block) for block in format_blocks(file)) + "\n"
