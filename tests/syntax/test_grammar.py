"""What each construct parses into."""
import pytest

from compiler.syntax import ast
from compiler.syntax.parser import parse_expression, parse_source

N = ast.Number


def ref(*names):
    return ast.Ref(tuple(ast.RefPart(n) for n in names))


def component(body: str, relations: str = "") -> ast.ComponentDef:
    text = f"component T\n{body}\n" + (f"relations\n{relations}\n" if relations else "") + "end\n"
    (definition,) = parse_source(text, "t.dyad").definitions
    return definition


@pytest.mark.parametrize("text, value", [
    ("12", 12), ("1.5", 1.5), ("3e4", 3e4), ("1.2e-6", 1.2e-6), ("10k", 1e4), ("1m", 1e-3),
    ("100n", 100e-9), ("5M", 5e6), ("2μ", 2e-6), ("2u", 2e-6), ("3p", 3e-12), ("4G", 4e9),
    ("1T", 1e12),
])
def test_numbers_and_si_suffixes(text, value):
    number = parse_expression(text)
    assert number == N(value) and number.text == text
    assert type(number.value) is type(value)


def test_power_binds_tighter_than_unary_minus_and_is_right_associative():
    assert parse_expression("-2^2") == ast.UnaryOp("-", ast.BinaryOp("^", N(2), N(2)))
    assert parse_expression("a^b^c") == ast.BinaryOp("^", ref("a"), ast.BinaryOp("^", ref("b"), ref("c")))
    assert parse_expression("2^-x") == ast.BinaryOp("^", N(2), ast.UnaryOp("-", ref("x")))


def test_precedence_ladder():
    e = parse_expression("a or b and c == d + e * f")
    assert e.op == "or" and e.right.op == "and" and e.right.right.op == "=="
    assert e.right.right.right.op == "+" and e.right.right.right.right.op == "*"
    assert parse_expression("!a && b || c") == ast.BinaryOp(
        "or", ast.BinaryOp("and", ast.UnaryOp("!", ref("a")), ref("b")), ref("c"))


def test_if_expression_and_ifelse_call():
    assert parse_expression("if c then a elseif d then b else e") == ast.IfExpr(
        ref("c"), ref("a"), ast.IfExpr(ref("d"), ref("b"), ref("e")))
    assert parse_expression("ifelse(c, a, b)") == ast.Call("ifelse", (ref("c"), ref("a"), ref("b")))


def test_calls_with_keyword_arguments_both_spellings():
    expected = ast.Call("f", (ref("a"),), (ast.KeywordArg("k", N(1)),))
    assert parse_expression("f(a; k = 1)") == expected
    assert parse_expression("f(a, k = 1)") == expected
    assert parse_expression("Pkg.Sub.g()") == ast.Call("Pkg.Sub.g")


def test_indexing_end_colon_and_slices():
    e = parse_expression("links[end].frame_b.phi")
    assert e.parts[0] == ast.RefPart("links", (ast.End(),)) and e.dotted == "links.frame_b.phi"
    e = parse_expression("A[:, 1:2:end]")
    assert e.parts[0].indices == (ast.Colon(), ast.Range(N(1), ast.End(), N(2)))
    assert parse_expression("v[min(end, 3)]").parts[0].indices[0].args[0] == ast.End()


def test_arrays_matrices_and_comprehensions():
    assert parse_expression("[1, 2]") == ast.ArrayLit((N(1), N(2)))
    assert parse_expression("[x]") == ast.ArrayLit((ref("x"),))
    assert parse_expression("[a -b]") == ast.ArrayLit(
        (ast.ArrayLit((ref("a"), ast.UnaryOp("-", ref("b")))),), is_matrix=True)
    assert parse_expression("[a - b]") == ast.ArrayLit((ast.BinaryOp("-", ref("a"), ref("b")),))
    m = parse_expression("[1 2\n 3 4]")
    assert m == parse_expression("[1 2; 3 4]") and m.is_matrix and len(m.elements) == 2
    c = parse_expression("[i^2 for i in 1:n, j in 1:2]")
    assert [it.variable for it in c.iterators] == ["i", "j"]


def test_unicode_identifiers():
    assert parse_expression("ω₀ * x′") == ast.BinaryOp("*", ref("ω₀"), ref("x′"))


def test_keywords_allowed_after_a_dot():
    assert parse_expression("port.flow + a.end") == ast.BinaryOp("+", ref("port", "flow"), ref("a", "end"))


def test_declarations():
    c = component('''  parameter a::Real = 1
  final parameter b::Real = a
  structural parameter n::Integer = 3
  constant c::Real = 2
  variable x::Real(guess = 1.0, state_priority = 10)
  variable g::Real[n, 3]
  variable y::Real = 2 * x
  variable z::Real = initial 0.5
  input u::Real
  output w::Real
  rev = Revolute(phi(initial = 0.3), w(initial = 0)) {"k": [1, -2.5, null, false]}
  links = [Link(L = l[i]) for i in 1:n]
  opt = Damper(final d = 1) if n > 2''')
    d = {x.name: x for x in c.declarations}
    assert d["b"].final and d["n"].variability == "structural" and d["c"].variability == "constant"
    assert d["x"].type.modifications[1] == ast.Modification("state_priority", N(10))
    assert d["g"].type.dims == (ref("n"), N(3))
    assert d["y"].binding == ast.BinaryOp("*", N(2), ref("x")) and d["y"].initial is None
    assert d["z"].initial == N(0.5) and d["z"].binding is None
    assert d["u"].causality == "input" and d["w"].causality == "output"
    assert d["rev"].modifications == (
        ast.Modification("phi", nested=(ast.Modification("initial", N(0.3)),)),
        ast.Modification("w", nested=(ast.Modification("initial", N(0)),)))
    assert ast.metadata_dict(d["rev"].metadata) == {"k": [1, -2.5, None, False]}
    assert d["links"].iterators == (ast.Iterator("i", ast.Range(N(1), ref("n"))),)
    assert d["links"].modifications[0].value == ast.Ref((ast.RefPart("l", (ref("i"),)),))
    assert d["opt"].condition == ast.BinaryOp(">", ref("n"), N(2))
    assert d["opt"].modifications[0].final


def test_relations():
    c = component("  variable x::Real[2]", '''  "documented"
  [x[1], x[2]] = r
  initial x[1] = 0
  guess x[2] = 1
  connect(a.p, b.n, c.p) {"edge": 1}
  for i in 1:2
    x[i] = i
  end
  if flag
    y = 1
  elseif other
    y = 2
  else
    y = 3
  end
  g = f(); h = 1''')
    r = c.relations
    assert r[0].doc == "documented" and isinstance(r[0].lhs, ast.ArrayLit)
    assert r[1].initial and isinstance(r[2], ast.Guess)
    assert r[3].refs == (ref("a", "p"), ref("b", "n"), ref("c", "p"))
    assert isinstance(r[4], ast.ForLoop) and len(r[4].body) == 1
    assert [b.condition for b in r[5].branches] == [ref("flag"), ref("other")]
    assert len(r[5].otherwise) == 1
    assert len(r) == 8


def test_line_breaks_end_statements_unless_the_next_line_continues():
    c = component("  variable x::Real", "  y = a\n  [b, c] = r\n  z = a\n    + b\n  w = (a\n    - b)")
    assert c.relations[0].rhs == ref("a")
    assert c.relations[2].rhs == ast.BinaryOp("+", ref("a"), ref("b"))
    assert c.relations[3].rhs == ast.BinaryOp("-", ref("a"), ref("b"))


def test_definitions_and_prefixes():
    f = parse_source('''using Pkg: A, B
"A length" type Length = Real(units = "m")
connector RealInput = input Real
enum Mode = | On | Off
partial connector P
  potential v::Real
  flow i::Real
end
example component E
end
test component T
end
partial component B
end
analysis Sim extends TransientAnalysis(stop = 10)
  parameter k::Real = 1
end
''', "defs.dyad")
    assert f.usings == (ast.Using("Pkg", ("A", "B")),)
    kinds = [type(d).__name__ for d in f.definitions]
    assert kinds == ["TypeDef", "SignalConnectorDef", "EnumDef", "ConnectorDef", "ComponentDef",
                     "ComponentDef", "ComponentDef", "AnalysisDef"]
    typedef, signal, enum, connector, example, test, base, analysis = f.definitions
    assert typedef.doc == "A length" and typedef.base.modifications[0].value == ast.String("m")
    assert signal.causality == "input" and enum.members == ("On", "Off")
    assert connector.partial and [x.kind for x in connector.fields] == ["potential", "flow"]
    assert (example.prefix, test.prefix, base.partial) == ("example", "test", True)
    assert analysis.extends[0].modifications == (ast.Modification("stop", N(10)),)


def test_comments_and_semicolons():
    c = component("  # a comment\n  parameter a::Real = 1; # trailing\n  parameter b::Real = 2;")
    assert [d.name for d in c.declarations] == ["a", "b"]


def test_one_line_component():
    (c,) = parse_source("component C parameter a::Real = 1 end", "one.dyad").definitions
    assert c.declarations[0].name == "a"
