"""Located semantic errors: each names FILE:LINE:COL of the offending source."""
from __future__ import annotations

from compiler.model.flatten import check_balance

PIN = """
connector Pin
  potential v::Real
  flow i::Real
end
"""


def test_unbalanced_model_names_component_and_variable(sources):
    path = sources.write("Model.dyad", """
component Leaky
  variable a::Real
  variable b::Real
relations
  a = 1
end
component Model
  part = Leaky()    # HERE
end
""")
    from compiler.model.flatten import flatten_model
    flat = flatten_model(f"{path}:Model")
    import pytest
    from compiler.errors import DyadError
    with pytest.raises(DyadError) as info:
        check_balance(flat)
    text = info.value.format()
    assert "1 equation(s) for 2 unknown(s)" in text
    assert "component `part` (Leaky)" in text
    assert "no equation determines `part.b`" in text or "no equation determines `part.a`" in text
    note_lines = [n.span.line for n in info.value.notes if n.span]
    assert 8 in note_lines                       # the `part = Leaky()` declaration


def test_overdetermined_model_names_the_extra_equation(sources):
    path = sources.write("Model.dyad", """
component Model
  variable a::Real
relations
  a = 1
  a = 2
end
""")
    from compiler.model.flatten import flatten_model
    import pytest
    from compiler.errors import DyadError
    with pytest.raises(DyadError) as info:
        check_balance(flatten_model(str(path)))
    assert "has no unknown left" in info.value.format()


def test_unknown_name(sources):
    err = sources.error("""
component Model
  variable speed::Real
relations
  speed = sped + 1   # HERE
end
""", marker="# HERE")
    assert "unknown name `sped`" in err.message and "speed" in (err.hint or "")


def test_unknown_type_with_hint(sources):
    err = sources.error("""
component Model
  variable x::Lenght   # HERE
relations
  x = 1
end
""", marker="# HERE")
    assert "unknown type `Lenght`" in err.message and "Length" in err.hint


def test_unknown_component_type(sources):
    err = sources.error("""
component Model
  body = NoSuchBody(m = 1)   # HERE
end
""", marker="# HERE")
    assert "unknown component type `NoSuchBody`" in err.message


def test_incompatible_connectors(sources):
    err = sources.error(PIN + """
component A
  p = Pin()
  f = Spline()
relations
  p.v = 0
  f.phi = 0
end
component Model
  a = A()
  b = A()
relations
  connect(a.p, b.f)   # HERE
end
""", "Model", marker="# HERE")
    assert "incompatible connectors" in err.message


def test_cyclic_parameter_defaults(sources):
    err = sources.error("""
component Model
  parameter a::Real = b + 1   # HERE
  parameter b::Real = 2 * a
  variable x::Real
relations
  x = a
end
""", marker="# HERE")
    assert "cyclic parameter defaults" in err.message and "a -> b -> a" in err.message


def test_array_size_mismatch_in_equation(sources):
    err = sources.error("""
component Model
  variable v::Real[2]
relations
  v = [1, 2, 3]   # HERE
end
""", marker="# HERE")
    assert "array size mismatch" in err.message


def test_array_size_mismatch_in_parameter_value(sources):
    err = sources.error("""
component Part
  parameter r::Real[2] = [0, 0]
end
component Model
  p = Part(r = [1, 2, 3])   # HERE
  variable x::Real
relations
  x = p.r[1]
end
""", "Model", marker="# HERE")
    assert "array size mismatch" in err.message and "`p.r`" in err.message


def test_final_parameter_cannot_be_modified(sources):
    err = sources.error("""
component Part
  final parameter k::Real = 1
  variable x::Real
relations
  x = k
end
component Model
  p = Part(k = 2)   # HERE
end
""", "Model", marker="# HERE")
    assert "cannot modify final parameter `k`" in err.message


def test_final_modifier_cannot_be_overridden(sources):
    err = sources.error("""
component Part
  parameter k::Real = 1
  variable x::Real
relations
  x = k
end
component Fixed
  extends Part(final k = 3)
end
component Model
  f = Fixed(k = 4)   # HERE
end
""", "Model", marker="# HERE")
    assert "made final" in err.message


def test_unconnected_input(sources):
    err = sources.error("""
component Gain
  u = RealInput()
  y = RealOutput()
relations
  y = 2 * u
end
component Model
  g = Gain()   # HERE
end
""", "Model", marker="# HERE")
    assert "input `g.u` is not connected" in err.message


def test_two_outputs_connected(sources):
    err = sources.error("""
component Source
  y = RealOutput()
relations
  y = 1
end
component Model
  a = Source()
  b = Source()
relations
  connect(a.y, b.y)   # HERE
end
""", "Model", marker="# HERE")
    assert "two outputs connected" in err.message


def test_unknown_function_with_hint(sources):
    err = sources.error("""
component Model
  variable x::Real
relations
  x = sqr(2)   # HERE
end
""", marker="# HERE")
    assert "unknown function `sqr`" in err.message and "sqrt" in err.hint


def test_der_of_a_parameter(sources):
    err = sources.error("""
component Model
  parameter p::Real = 1
  variable x::Real
relations
  x = der(2 * p + 1)   # HERE
end
""", marker="# HERE")
    assert "does not depend on time" in err.message


def test_duplicate_declaration(sources):
    err = sources.error("""
component Model
  variable x::Real
  parameter x::Real = 1   # HERE
end
""", marker="# HERE")
    assert "duplicate declaration `x`" in err.message


def test_duplicate_declaration_through_extends(sources):
    err = sources.error("""
partial component Base
  variable x::Real
end
component Model
  extends Base()
  variable x::Real   # HERE
relations
  x = 1
end
""", "Model", marker="# HERE")
    assert "duplicate declaration `x` (also inherited)" in err.message


def test_modifier_of_a_missing_element(sources):
    err = sources.error("""
component Part
  parameter mass::Real = 1
end
component Model
  p = Part(mas = 2)   # HERE
end
""", "Model", marker="# HERE")
    assert "no parameter, variable or component `mas`" in err.message and "mass" in err.hint


def test_index_out_of_bounds(sources):
    err = sources.error("""
component Model
  variable v::Real[2]
relations
  v[1] = 0
  v[3] = 1   # HERE
end
""", marker="# HERE")
    assert "out of bounds" in err.message


def test_if_relation_on_a_variable_is_not_structural(sources):
    err = sources.error("""
component Model
  variable x::Real
relations
  if x > 0   # HERE
    x = 1
  else
    x = 2
  end
end
""", marker="# HERE")
    assert "cannot depend on variable `x`" in err.message


def test_parameter_depending_on_a_variable(sources):
    err = sources.error("""
component Model
  variable x::Real
  parameter p::Real = 2 * x   # HERE
relations
  x = p
end
""", marker="# HERE")
    assert "cannot depend on" in err.message


def test_connecting_a_plain_variable(sources):
    err = sources.error(PIN + """
component Model
  p = Pin()
  variable x::Real
relations
  p.v = 0
  connect(p, x)   # HERE
end
""", "Model", marker="# HERE")
    assert "not a connector" in err.message


def test_cyclic_extends(sources):
    err = sources.error("""
component A
  extends B()
end
component B
  extends A()   # HERE
end
component Model
  a = A()
end
""", "A", marker="# HERE")
    assert "cyclic extends" in err.message


def test_partial_component_cannot_be_instantiated(sources):
    err = sources.error("""
partial component Base
  variable x::Real
end
component Model
  b = Base()   # HERE
end
""", "Model", marker="# HERE")
    assert "partial" in err.message


def test_unknown_attribute(sources):
    err = sources.error("""
component Model
  variable x::Real(gues = 1)   # HERE
relations
  x = 1
end
""", marker="# HERE")
    assert "unknown attribute `gues`" in err.message


def test_structural_size_without_value(sources):
    err = sources.error("""
component Model
  structural parameter n::Integer
  variable v::Real[n]   # HERE
end
""", marker="# HERE")
    assert "`n` has no value" in err.message


def test_errors_render_with_file_line_and_caret(sources):
    err = sources.error("""
component Model
  variable x::Real
relations
  x = nope
end
""", marker="x = nope")
    text = err.format()
    assert "Model.dyad:4:" in text and "x = nope" in text and "^" in text


def test_der_of_an_inherited_parameter(sources):
    err = sources.error("""
partial component Base
  parameter p::Real = 1
end
component Model
  extends Base()
  variable x::Real
relations
  x = der(p)   # HERE
end
""", "Model", marker="# HERE")
    assert "der of `p`" in err.message
