"""An error found inside a component (a library one, or one of the user's) also names the
declarations that put the component there, innermost first, so the user sees their own line."""
from __future__ import annotations

MISMATCHED_START = """
component Model
  lag = BlockComponents.Continuous.TransferFunction(a = [1.0, 2.0, 1.0], b = [1.0], init_mode = BlockComponents.Continuous.BlockInitMode.InitialState())
  source = BlockComponents.Sources.Constant(k = 1.0)
relations
  connect(source.y, lag.u)
end
"""

NESTED = """
component Inner
  variable x::Real[2]
relations
  x = [1.0, 2.0, 3.0]
end
component Middle
  inner = Inner()
end
component Model
  middle = Middle()
end
"""


def test_an_error_in_a_library_component_has_a_note_at_the_users_declaration(sources):
    err = sources.error(MISMATCHED_START, "Model")
    assert err.span.file.endswith("TransferFunction.dyad"), err.format()
    (note,) = err.notes
    assert note.message == ("in `lag` (BlockComponents.Continuous.TransferFunction), declared "
                            "here"), err.format()
    assert note.span.file.endswith("Model.dyad") and note.span.line == 2, err.format()


def test_each_enclosing_declaration_is_named_innermost_first(sources):
    err = sources.error(NESTED, "Model", marker="x = [1.0, 2.0, 3.0]")
    assert [(n.message, n.span.line) for n in err.notes] == [
        ("in `middle.inner` (Inner), declared here", 7),
        ("in `middle` (Middle), declared here", 10)], err.format()


def test_an_error_in_the_model_itself_has_no_such_note(sources):
    err = sources.error(NESTED.replace("component Model\n  middle = Middle()\nend\n", ""), "Inner",
                        marker="x = [1.0, 2.0, 3.0]")
    assert err.notes == [], err.format()
