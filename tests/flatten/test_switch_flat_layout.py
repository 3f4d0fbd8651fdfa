"""`switch` written flat, its cases at the column of the `switch` keyword, each closed by its own
`end` (Dyad's form) or not (compiler/syntax/switch_layout.py): the tokens decide which `end`
closes a case, and the case the subject selects gives the one equation."""
from __future__ import annotations

import pytest

from tests.flatten.conftest import solved_single_unknown

HEAD = """
enum Gear = Low | Middle | High

component Box
  structural parameter g::Gear = Gear.{member}
  variable x::Real
relations
"""

CLOSED = """switch g
case Low
  x = 1
end
case Middle
  x = 2
end
else
  x = 3
end
end
end
"""

OPEN_IN_LOOP = """for i in 1:1
switch g
case Low
  x = 1
case Middle
  x = 2
else
  x = 3
end
end
end
"""


@pytest.mark.parametrize("body", [CLOSED, OPEN_IN_LOOP], ids=["cases-closed", "cases-open"])
@pytest.mark.parametrize("member, value", [("Low", 1), ("Middle", 2), ("High", 3)])
def test_the_selected_case_gives_the_equation(sources, body, member, value):
    assert solved_single_unknown(sources.flatten(HEAD.format(member=member) + body, "Box")) == value


def test_a_case_after_the_switch_is_closed_is_located(sources):
    text = HEAD.format(member="Low") + "switch g\ncase Low\n  x = 1\nend\nend\ncase Middle\nend\n"
    error = sources.error(text, "Box", marker="case Middle")
    assert "found `case`" in error.message
