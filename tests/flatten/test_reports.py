"""check_library, summarize and format_flat (the CLI's views)."""
from __future__ import annotations

from compiler.model.flatten import check_library, format_flat, summarize


def test_check_library_reports_each_component(sources):
    sources.write("Lib/Good.dyad", """
        component Good
          variable x::Real
        relations
          der(x) = -x
        end
    """)
    sources.write("Lib/Bad.dyad", """
        component Bad
          variable x::Real
          variable y::Real
        relations
          x = 1
        end
    """)
    sources.write("Lib/Base.dyad", """
        partial component Base
          variable z::Real
        end
    """)
    lines = check_library(str(sources.root))
    assert len(lines) == 2                                  # the partial one is skipped
    bad, good = lines
    assert bad.startswith("Lib.Bad:") and "error" in bad and "unbalanced" in bad
    assert good == "ok: Lib.Good (1 equations, 1 unknowns)"


def test_summarize_and_format_flat(sources):
    flat = sources.flatten("""
component Model
  parameter k::Real = 2
  variable x::Real(guess = 1)
  variable y::Real
relations
  der(x) = -k * x
  y = 2 * x
  initial x = 1
end
""", "Model")
    summary = summarize(flat)
    assert "1 state_candidate" in summary and "1 algebraic" in summary
    assert "balance: 2 equations, 2 unknowns: balanced" in summary
    text = format_flat(flat)
    assert "0 = der(x) + k*x" in text and "Model.dyad:6:" in text
    assert "state_candidate x" in text and "k = 2" in text
