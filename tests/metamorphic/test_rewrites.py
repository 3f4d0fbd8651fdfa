"""The rewrites themselves (no simulation): each yields source the project's parser reads back
into the same tree, keeps indices integer, and says what it renamed."""
from __future__ import annotations

import dataclasses
import random

import pytest

from compiler.syntax import ast
from compiler.syntax.format import format_file
from compiler.syntax.parser import parse_file, parse_source
from tests.metamorphic import agreement, rewrites, walk
from tests.metamorphic.corpus import BASES, BY_LABEL

ROBERTSON = """\
component R
  parameter k1::Real = 0.04
  variable y::Real[2]
  variable z::Real(guess = 0)
relations
  initial y[1] = 1
  initial y[2] = 0
  der(y[1]) = -k1 * y[1] + z
  der(y[2]) = k1 * y[1] - 2 * y[2]
  y[1] + y[2] + z = 1
end
"""


def _component(text=ROBERTSON):
    return parse_source(text).definitions[0]


def _reparsed(component):
    text = format_file(ast.File("<m>", (), (component,)))
    return parse_source(text).definitions[0]


@pytest.mark.parametrize("name", sorted(rewrites.REWRITES))
@pytest.mark.parametrize("label", [base.label for base in BASES])
def test_every_rewrite_of_every_model_prints_and_parses_back_to_itself(label, name):
    base = BY_LABEL[label]
    component = agreement.definition(parse_file(base.path), base.name)
    for seed in range(3):
        result = rewrites.REWRITES[name](component, random.Random(seed))
        if result is None:
            continue
        printable = dataclasses.replace(result.component, relations=tuple(
            rewrites.printable(r) if isinstance(r, ast.Equation) else r for r in result.component.relations))
        assert _reparsed(printable) == printable, (label, name, seed)


def test_literal_kinds_change_numbers_but_never_indices():
    component = _component()
    result = rewrites.literal_kinds(component, random.Random(1))

    def kinds(c):
        return [type(n.value) for n in walk.nodes(c.relations, walk.arithmetic) if isinstance(n, ast.Number)]
    assert result is not None and kinds(result.component) != kinds(component)    # 1 == 1.0 as nodes
    for node in walk.nodes(result.component.relations):
        if isinstance(node, ast.RefPart):
            assert all(isinstance(i.value, int) for i in node.indices if isinstance(i, ast.Number))


def test_swap_sides_and_one_side_keep_every_term():
    component = _component()
    swapped = rewrites.swap_sides(component, random.Random(0)).component
    assert swapped != component
    for before, after in zip(component.relations, swapped.relations):
        assert (after.lhs, after.rhs) in ((before.lhs, before.rhs), (before.rhs, before.lhs))
    one = rewrites.one_side(component, random.Random(0)).component
    changed = [(b, a) for b, a in zip(component.relations, one.relations) if a != b]
    assert changed
    for before, after in changed:
        zero = after.rhs if isinstance(after.rhs, ast.Number) else after.lhs
        assert zero.value == 0


def test_an_extracted_subexpression_is_defined_once_and_used_where_it_was():
    component = _component()
    result = rewrites.extract_subexpression(component, random.Random(3)).component
    added = [d.name for d in result.declarations if d.name.startswith(rewrites.PREFIX)]
    assert added
    for name in added:
        definitions = [r for r in result.relations if isinstance(r, ast.Equation)
                       and isinstance(r.lhs, ast.Ref) and r.lhs.parts[0].name == name]
        assert len(definitions) == 1
        assert sum(walk.refs_to(r, name) for r in result.relations) >= 2


def test_fresh_names_never_collide_when_a_rewrite_is_applied_twice():
    component = _component()
    for seed in range(10):
        component = rewrites.name_literals(component, random.Random(seed)) or component
        component = component.component if isinstance(component, rewrites.Rewrite) else component
    names = [d.name for d in component.declarations]
    assert len(names) == len(set(names))


def test_rename_reports_the_old_names():
    component = _component()
    result = rewrites.rename(component, random.Random(0))
    assert result.renamed
    for new, old in result.renamed.items():
        assert new == rewrites.PREFIX + old
        assert not any(walk.refs_to(r, old) for r in result.component.relations)
    assert agreement.original_name(f"der({next(iter(result.renamed))}[1])", result.renamed) == \
        f"der({next(iter(result.renamed.values()))}[1])"


def test_a_leading_minus_is_never_printed_at_the_start_of_a_relation():
    equation = ast.Equation(ast.BinaryOp("*", ast.UnaryOp("-", ast.Ref((ast.RefPart("x"),))), ast.Number(2)),
                            ast.Number(1))
    fixed = rewrites.printable(equation)
    assert rewrites.leads_with_minus(equation.lhs) and not rewrites.leads_with_minus(fixed.lhs)
    assert {fixed.lhs, fixed.rhs} == {equation.lhs, equation.rhs}
