"""What the rest of the published syntax (issue 27, item 3) means once flattened: relative
`using`, `time` as a declared name, `path` declarations, `switch` everywhere, filtered and nested
comprehensions, enums in every position. Models written for these tests."""
from __future__ import annotations

import pytest

from compiler.model.flatten import flatten_model


def test_relative_usings_name_definitions_from_the_files_package(sources):
    sources.write("Rig/Parts/Spring.dyad", """
        component Spring
          parameter k::Real = 3
          variable f::Real
        relations
          f = k
        end
    """)
    sources.write("Rig/Tools/Damper.dyad", """
        using ..Parts: Spring
        component Damper
          s = Spring(k = 5)
        end
    """)
    sources.write("Rig/Bench.dyad", """
        using .Tools
        using .Parts: Spring
        component Bench
          d = Damper()
          s = Spring()
        end
    """)
    flat = flatten_model("Rig.Bench", [str(sources.root)])
    assert sorted(v.name for v in flat.variables) == ["d.s.f", "s.f"]
    assert {p.name: p.value for p in flat.parameters if p.name.endswith(".k")} == {"d.s.k": 5, "s.k": 3}
