"""Enumerations in expressions: `Gear.High` as its 1-based position among the members of enum
`Gear`, and the case of a `switch` relation that a structural value selects."""
from __future__ import annotations

from typing import Any

import sympy

from compiler.errors import DyadError, Span, suggest_name
from compiler.model.eval_scope import EvalScope, Lexical, Mode
from compiler.model.eval_values import is_node_like
from compiler.syntax import ast


def enum_member_value(qualified_member: str, lexical: Lexical, span: Span | None) -> Any:
    """`Gear.High` (or `Pkg.Gear.High`) as its 1-based position among the members of enum `Gear`;
    None when the prefix names no enum."""
    enum_name, _, member = qualified_member.rpartition(".")
    if not enum_name:
        return None
    found = lexical.library.lookup(enum_name, lexical.package, lexical.file)
    if found is None or not isinstance(found.definition, ast.EnumDef):
        return None
    members = found.definition.members
    if member not in members:
        raise DyadError(f"enum `{enum_name}` has no member `{member}`", span,
                        hint=suggest_name(member, list(members)))
    return sympy.Integer(members.index(member) + 1)


def selected_case(relation: ast.Switch, scope: EvalScope, value: int) -> tuple:
    """The relations of the case of `switch subject` that names the subject's value `value` (its
    `else` when no case names it)."""
    enum_name = _subject_enum(relation.subject, scope)
    for case in relation.cases:
        for name in case.members:
            qualified = name if "." in name else f"{enum_name}.{name}" if enum_name else None
            index = enum_member_value(qualified, scope.lexical, case.span) if qualified else None
            if index is None:
                raise DyadError(f"cannot tell which enum `{name}` belongs to", case.span,
                                hint="switch on a parameter declared with an enum type, or write "
                                     "the case as `EnumName.Member`")
            if int(index) == value:
                return case.body
    return relation.otherwise


def _subject_enum(subject: ast.Expr, scope: EvalScope) -> str | None:
    """The qualified enum type of a switch subject that names a parameter, else None."""
    if not isinstance(subject, ast.Ref) or any(p.indices for p in subject.parts):
        return None
    node = scope.node
    for part in subject.parts[:-1]:
        node = node.member(part.name, Mode.STRUCTURAL, subject.span)
        if not is_node_like(node):
            return None
    parameter = getattr(node, "parameters", {}).get(subject.parts[-1].name)
    type_name = getattr(getattr(parameter, "type", None), "name", None)
    found = scope.lexical.library.find(type_name) if type_name else None
    return type_name if found is not None and isinstance(found.definition, ast.EnumDef) else None
