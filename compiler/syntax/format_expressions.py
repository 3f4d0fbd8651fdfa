"""Expressions printed canonically (compiler/syntax/format.py prints the rest): each operator at
its binding strength, with the fewest parentheses that parse back to the same tree."""
from __future__ import annotations

from compiler.syntax import ast

# Binding strength, loosest first; a child printed below its required level gets parentheses.
IF_LEVEL, OR_LEVEL, AND_LEVEL, COMPARE_LEVEL, RANGE_LEVEL, ADD_LEVEL, MUL_LEVEL, UNARY_LEVEL, \
    POWER_LEVEL, ATOM_LEVEL = range(10)

_BINARY_LEVELS = {
    "or": OR_LEVEL, "and": AND_LEVEL,
    "==": COMPARE_LEVEL, "!=": COMPARE_LEVEL, "<": COMPARE_LEVEL, "<=": COMPARE_LEVEL,
    ">": COMPARE_LEVEL, ">=": COMPARE_LEVEL,
    "+": ADD_LEVEL, "-": ADD_LEVEL, ".+": ADD_LEVEL, ".-": ADD_LEVEL,
    "*": MUL_LEVEL, "/": MUL_LEVEL, ".*": MUL_LEVEL, "./": MUL_LEVEL, "%": MUL_LEVEL,
    "÷": MUL_LEVEL,
    "^": POWER_LEVEL, ".^": POWER_LEVEL,
}


def _level(e) -> int:
    if isinstance(e, ast.IfExpr):
        return IF_LEVEL
    if isinstance(e, ast.BinaryOp):
        return _BINARY_LEVELS[e.op]
    if isinstance(e, ast.Range):
        return RANGE_LEVEL
    if isinstance(e, ast.UnaryOp):
        return UNARY_LEVEL
    return ATOM_LEVEL


def _operand(e, required: int) -> str:
    text = format_expr(e)
    return f"({text})" if _level(e) < required else text


def format_expr(e) -> str:
    """The canonical text of expression node `e` (its printer in _PRINTERS)."""
    printer = _PRINTERS.get(type(e))
    if printer is None:
        raise TypeError(f"not an expression node: {e!r}")
    return printer(e)


def _range(e: ast.Range) -> str:
    parts = [e.start] + ([e.step] if e.step is not None else []) + [e.stop]
    return ":".join(_operand(p, ADD_LEVEL) for p in parts)


def _unary(e: ast.UnaryOp) -> str:
    operand = _operand(e.operand, UNARY_LEVEL)
    separator = " " if operand[:1] in "+-!." else ""
    return f"{e.op}{separator}{operand}"


def _call(e: ast.Call) -> str:
    args = [format_expr(a) for a in e.args]
    args += [f"{k.name} = {format_expr(k.value)}" for k in e.kwargs]
    return f"{e.function}({', '.join(args)})"


def _comprehension(e: ast.Comprehension) -> str:
    clauses = "".join(f" for {format_iterators(c.iterators)}"
                      + (f" if {format_expr(c.condition)}" if c.condition is not None else "")
                      for c in e.clauses)
    inner = f"{format_expr(e.expr)}{clauses}"
    return inner if e.generator else f"[{inner}]"


def _switch_value(e: ast.SwitchValue) -> str:
    """On one line, `;` between its parts: the layout reads each `end` by its tokens there."""
    parts = [f"switch {format_expr(e.subject)}"]
    for case in e.cases:
        parts += [f"case {', '.join(case.names)}", format_expr(case.body[0]), "end"]
    if e.otherwise:
        parts += ["else", format_expr(e.otherwise[0]), "end"]
    return "; ".join(parts + ["end"])


def _number(e: ast.Number) -> str:
    if e.text is not None:
        return e.text
    if isinstance(e.value, bool) or not isinstance(e.value, (int, float)):
        raise TypeError(f"not a number: {e.value!r}")
    return str(e.value) if isinstance(e.value, int) else repr(float(e.value))


def format_string(value: str) -> str:
    if "\n" in value or '"' in value.replace('\\"', ""):
        return f'"""{value}"""'
    return f'"{value}"'


def _ref_part(part: ast.RefPart) -> str:
    if not part.indices:
        return part.name
    return f"{part.name}[{', '.join(format_expr(i) for i in part.indices)}]"


def _binary(e: ast.BinaryOp) -> str:
    level = _BINARY_LEVELS[e.op]
    if level == POWER_LEVEL:
        # Right-associative; the base must be tighter than unary (`(-2) ^ 2`), the exponent may
        # carry a sign (`2 ^ -3`).
        left, right = _operand(e.left, ATOM_LEVEL), _operand(e.right, UNARY_LEVEL)
    elif level == COMPARE_LEVEL:
        left, right = _operand(e.left, RANGE_LEVEL), _operand(e.right, RANGE_LEVEL)
    else:
        # A left-associated chain of one level (`a + b - c`) is printed in a loop: it can be
        # thousands of terms long.
        same_level = {op for op, lvl in _BINARY_LEVELS.items() if lvl == level}
        first, links = ast.left_chain(e, same_level)
        parts = [_operand(first, level)]
        parts += [f" {link.op} {_operand(link.right, level + 1)}" for link in links]
        return "".join(parts)
    return f"{left} {e.op} {right}"


def _if_expr(e: ast.IfExpr) -> str:
    out = [f"if {_operand(e.condition, OR_LEVEL)} then {format_expr(e.then)}"]
    rest = e.otherwise
    while isinstance(rest, ast.IfExpr):
        out.append(f" elseif {_operand(rest.condition, OR_LEVEL)} then {format_expr(rest.then)}")
        rest = rest.otherwise
    out.append(f" else {format_expr(rest)}")
    return "".join(out)


def _array(e: ast.ArrayLit) -> str:
    if not e.is_matrix:
        return f"[{', '.join(format_expr(x) for x in e.elements)}]"
    rows = []
    for row in e.elements:
        elements = row.elements if isinstance(row, ast.ArrayLit) and not row.is_matrix else (row,)
        # Inside a matrix row a space separates elements, so anything with an operator is
        # parenthesized to stay one element.
        rows.append(" ".join(_operand(x, ATOM_LEVEL) for x in elements))
    return f"[{'; '.join(rows)}]"


def format_iterators(iterators) -> str:
    return ", ".join(f"{it.variable} in {format_expr(it.iterable)}" for it in iterators)


_PRINTERS = {
    ast.Number: _number,
    ast.String: lambda e: format_string(e.value),
    ast.Boolean: lambda e: "true" if e.value else "false",
    ast.End: lambda e: "end",
    ast.Colon: lambda e: ":",
    ast.Ref: lambda e: ".".join(_ref_part(p) for p in e.parts),
    ast.Range: _range,
    ast.UnaryOp: _unary,
    ast.BinaryOp: _binary,
    ast.IfExpr: _if_expr,
    ast.Call: _call,
    ast.ArrayLit: _array,
    ast.SwitchValue: _switch_value,
    ast.Comprehension: _comprehension,
}
