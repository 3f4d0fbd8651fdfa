"""Forms of the published Dyad language (issue 17, items 1, 3 and 4): what each parses into, and
the located errors around them. Examples written from the language reference, not copied."""
import json

import pytest

from compiler.errors import DyadError
from compiler.syntax import ast
from compiler.syntax.format import format_file
from compiler.syntax.format_comments import format_source
from compiler.syntax.parser import parse_expression, parse_source

N = ast.Number


def ref(*names):
    return ast.Ref(tuple(ast.RefPart(n) for n in names))


def parse(text: str) -> ast.File:
    result = parse_source(text, "t.dyad")
    assert parse_source(format_file(result), "t.dyad<fmt>") == result     # fmt round-trips
    return result


def component(body: str, relations: str = "") -> ast.ComponentDef:
    text = f"component T\n{body}\n" + (f"relations\n{relations}\n" if relations else "") + "end\n"
    (definition,) = parse(text).definitions
    return definition


def error(text: str) -> DyadError:
    with pytest.raises(DyadError) as caught:
        parse_source(text, "t.dyad")
    assert caught.value.span is not None and caught.value.span.file == "t.dyad"
    return caught.value


# ------------------------------------------------------------------------------- metadata forms

def test_link_after_declarations_is_kept():
    c = component("  parameter k::Real = 2 {^gain}\n  x = Sub() {^x}\n  variable v::Real {^v}")
    assert [d.link for d in c.declarations] == ["gain", "x", "v"]
    assert c.declarations[0].metadata is None


def test_bracketed_metadata_equals_braced_metadata():
    braced = component('  p = Pin() {"Dyad": {"x": 1}}')
    bracketed = component('  p = Pin() [{\n    "Dyad": {"x": 1}\n  }]')
    assert braced == bracketed
    assert json.loads(bracketed.declarations[0].metadata) == {"Dyad": {"x": 1}}


def test_bracketed_metadata_after_fields_connect_and_extends():
    (conn,) = parse('connector C\n  potential v::Real [{"a": 1}]\n  flow i::Real {^i}\nend\n').definitions
    assert conn.fields[0].metadata == '{"a": 1}' and conn.fields[1].link == "i"
    c = component('  extends Base(k = 1) [{"b": 2}]\n  a = P()\n  b = P()',
                  'connect(a.p, b.p) [{"edges": [{"S": 1}]}]\nconnect(a.n, b.n) {^wire}')
    assert c.extends[0].metadata == '{"b": 2}'
    assert json.loads(c.relations[0].metadata) == {"edges": [{"S": 1}]}
    assert c.relations[1].link == "wire"


def test_json_arrays_of_objects_stay_arrays_inside_metadata():
    c = component('  p = Pin() {"list": [{"a": 1}, {"b": [{"c": 2}]}]}')
    assert json.loads(c.declarations[0].metadata) == {"list": [{"a": 1}, {"b": [{"c": 2}]}]}


def test_metadata_after_one_line_connector_same_or_next_line():
    (a,) = parse('connector In = input Real metadata {"Dyad": {"icon": "i"}}\n').definitions
    (b,) = parse('connector In = input Real\nmetadata {"Dyad": {"icon": "i"}}\n').definitions
    assert a == b and json.loads(a.metadata) == {"Dyad": {"icon": "i"}}


def test_two_links_are_an_error():
    err = error("component T\n  x = P() {^a} {^b}\nend\n")
    assert "two `{^...}` links" in err.message and err.span.line == 2


# ------------------------------------------------------------------------------- declarations

def test_typed_declarations_in_analyses_and_components():
    (analysis,) = parse("analysis Run\n  extends TransientAnalysis(stop = 5)\n"
                        "  model::Plant() = Plant(k = 2)\n  solver::String = \"Rodas5\"\nend\n"
                        ).definitions
    model, solver = analysis.declarations
    assert model == ast.TypedDecl("model", ast.TypeSpec("Plant"),
                                  ast.Call("Plant", (), (ast.KeywordArg("k", N(2)),)))
    assert solver.value == ast.String("Rodas5")


def test_path_and_stream_declarations_and_fields():
    c = component("  path medium::Medium = Water(T = 300)\n  stream h::Real")
    assert [(d.kind, d.name) for d in c.declarations] == [("path", "medium"), ("stream", "h")]
    (port,) = parse("connector Port\n  potential p::Real\n  flow m::Real\n  path medium::Medium\n"
                    "  stream h::Real\nend\n").definitions
    assert [f.kind for f in port.fields] == ["potential", "flow", "path", "stream"]


def test_other_words_before_a_declaration_are_an_error():
    err = error("component T\n  velocity v::Real\nend\n")
    assert err.span.line == 2 and "found name `velocity`" in err.message


def test_function_types():
    f, g = parse("type F = func(::Real)::Real\ntype G = func(a::Real, ::Real[2])::Real\n"
                 ).definitions
    assert f == ast.FunctionTypeDef("F", (ast.FunctionParam(None, ast.TypeSpec("Real")),),
                                    ast.TypeSpec("Real"))
    assert g.params[0].name == "a" and g.params[1].type.dims == (N(2),)
    assert "expected `func`" in error("type F = fun(::Real)::Real\n").message


def test_struct_and_enum_members_with_fields():
    s, e = parse("struct Gas\n  name::String = \"air\"\n  R::Real = 287\nend\n"
                 "enum Load = Free | Fixed(position::Real = 0)\n").definitions
    assert s == ast.StructDef("Gas", (ast.TypedDecl("name", ast.TypeSpec("String"),
                                                    ast.String("air")),
                                      ast.TypedDecl("R", ast.TypeSpec("Real"), N(287))))
    assert e.members == ("Free", "Fixed")
    assert e.fields[0] == () and e.fields[1][0].name == "position"
    (plain,) = parse("enum E = A | B\n").definitions
    assert plain.fields == ()
    assert "duplicate field `R`" in error("struct S\n  R::Real\n  R::Real\nend\n").message


def test_external_component_keeps_its_interface():
    (c,) = parse("external component Table\n  u = In()\n  y = Out()\nend\n").definitions
    assert c.external and [d.name for d in c.declarations] == ["u", "y"]


def test_soft_keywords_stay_names_where_they_are_used_as_names():
    c = component("  switch = IdealSwitch()\n  case::Real = 1\n  struct = Holder()",
                  "switch.on = case > 0")
    assert [d.name for d in c.declarations] == ["switch", "case", "struct"]
    assert c.relations[0].lhs == ref("switch", "on")


# ---------------------------------------------------------------------------------- relations

def test_analysis_point_is_a_named_connection():
    c = component("  a = P()\n  b = P()", "u: analysis_point(a.y, b.u) {^u}")
    assert c.relations[0] == ast.Connect((ref("a", "y"), ref("b", "u")), analysis_point="u",
                                         link="u")


def test_continuity_is_recorded():
    c = component("  a = P()\n  b = P()", "continuity(a.medium, b.medium)")
    assert c.relations[0] == ast.Continuity((ref("a", "medium"), ref("b", "medium")))


def test_an_expression_without_equals_is_an_error():
    err = error("component T\n  variable x::Real\nrelations\n  x + 1\nend\n")
    assert err.message.startswith("expected `=` after this expression") and err.span.line == 4


def test_switch_on_enum_cases():
    c = component("  structural parameter mode::Mode = Mode.A\n  variable x::Real",
                  "switch mode\n  case A\n    x = 1\n  case B, C\n    x = 2\n  else\n    x = 3\nend")
    (sw,) = c.relations
    assert sw.subject == ref("mode")
    assert [case.names for case in sw.cases] == [("A",), ("B", "C")]
    assert sw.cases[1].body == (ast.Equation(ref("x"), N(2)),)
    assert sw.otherwise == (ast.Equation(ref("x"), N(3)),)


def test_switch_with_a_case_twice_is_an_error():
    err = error("component T\nrelations\n  switch m\n    case A\n      x = 1\n    case A\n"
                "      x = 2\n  end\nend\n")
    assert "case `A` appears twice" in err.message and err.span.line == 6


def test_legacy_model_begin_form_is_reported_with_a_hint():
    err = error("model Tank\n  h::Real\nbegin\n  der(h) = -h\nend\n")
    assert "legacy Dyad syntax" in err.message and (err.span.line, err.span.column) == (1, 1)
    assert "component Tank" in err.hint
    err = error("component Tank\n  variable h::Real\nbegin\n  der(h) = -h\nend\n")
    assert "legacy" in err.message and err.span.line == 3 and "relations" in err.hint


# -------------------------------------------------------------------------------- expressions

def test_ternary_is_an_if_expression():
    assert parse_expression("c ? a : b") == ast.IfExpr(ref("c"), ref("a"), ref("b"))
    assert parse_expression("c ? a : d ? e : f") == ast.IfExpr(
        ref("c"), ref("a"), ast.IfExpr(ref("d"), ref("e"), ref("f")))
    assert parse_expression("x < 0 || y ? -1 : 1") == ast.IfExpr(
        ast.BinaryOp("or", ast.BinaryOp("<", ref("x"), N(0)), ref("y")),
        ast.UnaryOp("-", N(1)), N(1))


def test_ternary_branches_may_hold_ranges_and_slices():
    e = parse_expression("c ? v[1:2] : w[2:3]")
    assert e.then.parts[0].indices == (ast.Range(N(1), N(2)),)
    assert parse_expression("c ? (1:3) : (2:4)").otherwise == ast.Range(N(2), N(4))


def test_ternary_over_lines():
    c = component("  variable y::Real", "y = time > 1 ?\n  2 :\n  3")
    assert c.relations[0].rhs == ast.IfExpr(ast.BinaryOp(">", ref("time"), N(1)), N(2), N(3))


@pytest.mark.parametrize("op", ["%", "÷"])
def test_remainder_and_integer_division_bind_like_division(op):
    assert parse_expression(f"a + b {op} c") == ast.BinaryOp(
        "+", ref("a"), ast.BinaryOp(op, ref("b"), ref("c")))
    assert parse_expression(f"a {op} b * c") == ast.BinaryOp(
        "*", ast.BinaryOp(op, ref("a"), ref("b")), ref("c"))


def test_capital_d_is_der_for_the_checks():
    err = error("component T\n  parameter k::Real = 1\nrelations\n  D(k) = 1\nend\n")
    assert "`D(k)` differentiates a parameter" in err.message


# ------------------------------------------------------------------ generator arguments (issue 27)

def _generator(expr, *iterators):
    return ast.Comprehension(expr, tuple(ast.Iterator(v, it) for v, it in iterators), generator=True)


def test_a_generator_argument_is_the_comprehension_of_its_call():
    i_squared = ast.BinaryOp("^", ast.Ref((ast.RefPart("w", (ref("i"),)),)), N(2))
    assert parse_expression("sum(w[i]^2 for i in 1:n)") == ast.Call(
        "sum", (_generator(i_squared, ("i", ast.Range(N(1), ref("n")))),))
    both = parse_expression("prod(k for i = 1:2, j ∈ 1:3)")
    assert both == ast.Call("prod", (_generator(ref("k"), ("i", ast.Range(N(1), N(2))),
                                                ("j", ast.Range(N(1), N(3)))),))


def test_a_generator_argument_prints_back_without_brackets():
    c = component("  parameter w::Real[3] = [1, 2, 3]\n  variable y::Real",
                  "y = sum(w[i] * i  for i in 1:3)  # weighted")
    text = format_source("component T\n  variable y::Real\nrelations\n"
                         "  # the total\n  y = sum(w[i]   for i in 1:3)\nend\n", "t.dyad")
    assert "  # the total\n  y = sum(w[i] for i in 1:3)\n" in text
    assert c.relations[0].rhs.args[0].generator
    assert parse_expression("sum([w[i] for i in 1:3])").args[0].generator is False


def test_a_generator_must_be_the_only_argument():
    err = error("component T\n  variable y::Real\nrelations\n  y = f(w[i] for i in 1:3, 2)\nend\n")
    assert (err.span.line, err.span.column) == (4, 28)
    assert "must be the only argument of its call, found number `2`" in err.message
    assert "`f([x[i] for i in 1:n], y)`" in err.hint
    err = error("component T\n  r = [R(k = w[i]) for i in 1:3, 2]\nend\n")
    assert err.message == "expected a name, found number `2`"
    err = error("component T\n  variable y::Real\nrelations\n  y = sum(for i in 1:3)\nend\n")
    assert (err.span.line, err.span.column) == (4, 11) and "`for`" in err.message


# ------------------------------------------------------- Dyad's `switch`: each case closes with `end`

OPEN_SWITCH = """  switch g
    case Low
      x = 1
    case Mid, High
      for i in 1:2
        x = i
      end
    else
      x = 3
  end"""
CLOSED_SWITCH = """  switch g
    case Low
      x = 1
    end
    case Mid, High
      for i in 1:2
        x = i
      end
    end
    else
      x = 3
    end
  end"""


def test_cases_closed_by_end_mean_the_same_switch():
    (open_form,) = component("  variable x::Real", OPEN_SWITCH).relations
    (closed_form,) = component("  variable x::Real", CLOSED_SWITCH).relations
    assert closed_form.closed_cases and not open_form.closed_cases
    assert closed_form.cases == open_form.cases and closed_form.otherwise == open_form.otherwise
    assert [c.names for c in closed_form.cases] == [("Low",), ("Mid", "High")]


def test_closed_cases_print_back_with_their_ends_and_comments():
    text = f"component T\n  variable x::Real\nrelations\n{CLOSED_SWITCH}\n  # after\nend\n"
    # a comment before `case` (like one before `else`) is printed at the depth of a body
    commented = text.replace("    case Mid", "      # the middle gears\n    case Mid")
    printed = format_source(commented, "t.dyad")
    assert printed == commented


def test_a_single_closed_case_and_a_nested_switch_in_each_form():
    (one,) = component("  variable x::Real", "switch g\n  case A\n    x = 1\n  end\nend").relations
    assert one.closed_cases and one.cases[0].body[0].rhs == N(1)
    nested = ("switch g\ncase A\n  switch h\n  case X\n    x = 1\n  end\ncase B\n  x = 2\nend")
    (outer,) = component("  variable x::Real", nested).relations
    assert [c.names for c in outer.cases] == [("A",), ("B",)] and not outer.closed_cases
    assert isinstance(outer.cases[0].body[0], ast.Switch)


def test_a_switch_left_open_after_closed_cases_is_a_located_error():
    err = error("component T\n  variable x::Real\nrelations\n  switch g\n    case A\n      x = 1\n"
                "    end\nend\n")
    assert err.message.startswith("expected `end` to close component `T`")
    assert (err.span.line, err.span.column) == (8, 4)      # end of file, after the last `end`
