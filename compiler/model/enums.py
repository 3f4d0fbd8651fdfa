"""Enumerations in expressions: `Gear.High` as its 1-based position among the members of enum
`Gear`, the case of a `switch` relation that a structural value selects, and the fields of a
member that carries some (`| InitialState(x0::Real[:])`): given where the value is written,
`InitialState(x0 = [0.5])`, and bound to local names by the case that names it,
`case InitialState(x0)`."""
from __future__ import annotations

from typing import Any, Callable

import sympy

from compiler.errors import DyadError, Note, Span, suggest_name
from compiler.model.eval_scope import EvalScope, Lexical, Mode
from compiler.model.eval_values import is_node_like
from compiler.syntax import ast

MAX_BINDING_HOPS = 20


def enum_member_value(qualified_member: str, lexical: Lexical, span: Span | None) -> Any:
    """`Gear.High` (or `Pkg.Gear.High`) as its 1-based position among the members of enum `Gear`;
    None when the prefix names no enum."""
    found = _member(qualified_member, lexical, span)
    return None if found is None else sympy.Integer(found[1] + 1)


def _member(qualified_member: str, lexical: Lexical, span: Span | None
            ) -> tuple[ast.EnumDef, int] | None:
    """The enum a qualified member belongs to and the member's 0-based position; None when the
    prefix names no enum."""
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
    return found.definition, members.index(member)


def _fields(enum: ast.EnumDef, index: int) -> tuple[ast.TypedDecl, ...]:
    return enum.fields[index] if enum.fields else ()


def check_member_call(call: ast.Call, lexical: Lexical) -> None:
    """`InitialState(x0 = [0.5])`: the arguments must name fields the member declares."""
    enum, index = _member(call.function, lexical, call.span)
    fields = _fields(enum, index)
    names = [f.name for f in fields]
    if not fields and (call.args or call.kwargs):
        raise DyadError(f"enum member `{call.function}` has no fields", call.span,
                        hint=f"write `{call.function}()` or `{call.function}`")
    if len(call.args) > len(fields):
        raise DyadError(f"enum member `{call.function}` has {len(fields)} field(s) "
                        f"({', '.join(names)}) but is given {len(call.args)} values", call.span)
    for argument in call.kwargs:
        if argument.name not in names:
            raise DyadError(f"enum member `{call.function}` has no field `{argument.name}`",
                            call.span, hint=suggest_name(argument.name, names))


def selected_case(relation: ast.Switch | ast.SwitchValue, scope: EvalScope, value: int
                  ) -> tuple[ast.SwitchCase | None, str]:
    """The case of `switch subject` that names the subject's value `value` and the member as that
    case writes it; (None, "") when no case names it (its `else` applies)."""
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
                return case, name
    return None, ""


def case_bindings(relation: ast.Switch | ast.SwitchValue, case: ast.SwitchCase, member: str,
                  scope: EvalScope, evaluate: Callable[[ast.Expr, EvalScope, Mode], Any]
                  ) -> dict[str, Any]:
    """The values `case InitialState(x0)` binds: the fields of the member the subject parameter
    was given (`init_mode = BlockInitMode.InitialState(x0 = [0.5])`), else their defaults."""
    names = case.bound_names(member)
    if not names:
        return {}
    parameter = _subject_parameter(relation.subject, scope)
    if parameter is None or parameter.binding is None:
        raise DyadError("a case that binds the fields of a member needs a `switch` on an enum "
                        "parameter with a value", case.span)
    value, value_scope = _member_value(parameter)
    written = value.function if isinstance(value, ast.Call) else value.dotted
    enum, index = _member(written, value_scope.lexical, value.span)
    fields = _fields(enum, index)
    if len(names) > len(fields):
        raise DyadError(f"`case {member}` binds {len(names)} name(s) but `{written}` has "
                        f"{len(fields)} field(s)", case.span)
    given: dict[str, ast.Expr] = {}
    if isinstance(value, ast.Call):
        given = dict(zip((f.name for f in fields), value.args))
        given.update({k.name: k.value for k in value.kwargs})
    values = {}
    for local, field in zip(names, fields):
        expr = given.get(field.name, field.value)
        if expr is None:
            raise DyadError(f"`{parameter.path}` is `{written}` without its field `{field.name}`, "
                            f"which `case {member}` uses", value.span,
                            hint=f"write `{written}({field.name} = ...)`",
                            notes=[Note("the case binding it", case.span)])
        values[local] = evaluate(expr, value_scope, Mode.NUMERIC)
    return values


def _member_value(parameter: Any) -> tuple[ast.Expr, EvalScope]:
    """The enum value written for a parameter, through parameters passed on unchanged
    (`init_mode = init_mode`): a member call `M.C(...)` or a bare member `M.C`."""
    expr, scope = parameter.binding
    for _ in range(MAX_BINDING_HOPS):
        if isinstance(expr, ast.Call) or (isinstance(expr, ast.Ref) and _is_member_ref(expr, scope)):
            return expr, scope
        following = _subject_parameter(expr, scope) if isinstance(expr, ast.Ref) else None
        if following is None or following.binding is None:
            break
        expr, scope = following.binding
    raise DyadError("the value of an enum parameter whose case binds fields must be written as "
                    "a member, `Enum.Member(field = ...)`", getattr(expr, "span", None))


def _is_member_ref(ref: ast.Ref, scope: EvalScope) -> bool:
    return not any(p.indices for p in ref.parts) and "." in ref.dotted and \
        _member(ref.dotted, scope.lexical, ref.span) is not None


def _subject_parameter(subject: ast.Expr, scope: EvalScope) -> Any:
    """The parameter instance a switch subject names, or None."""
    if not isinstance(subject, ast.Ref) or any(p.indices for p in subject.parts):
        return None
    node = scope.node
    for part in subject.parts[:-1]:
        node = node.member(part.name, Mode.STRUCTURAL, subject.span)
        if not is_node_like(node):
            return None
    return getattr(node, "parameters", {}).get(subject.parts[-1].name)


def _subject_enum(subject: ast.Expr, scope: EvalScope) -> str | None:
    """The qualified enum type of a switch subject that names a parameter, else None."""
    parameter = _subject_parameter(subject, scope)
    type_name = getattr(getattr(parameter, "type", None), "name", None)
    found = scope.lexical.library.find(type_name) if type_name else None
    return type_name if found is not None and isinstance(found.definition, ast.EnumDef) else None
