"""Elements of Dyad's standard library that keep a value set at an earlier event (flip-flops,
edges, timers, hysteresis, thyristors) need discrete states, which dyadc does not have: each is
refused at its declaration, in either spelling of its path, rather than reported unknown."""
from __future__ import annotations

import pytest

from compiler.errors import DyadError
from compiler.model.flatten import flatten_model


@pytest.mark.parametrize("name", ["BlockComponents.Logical.RSFlipFlop", "BlockComponents.Edge",
                                  "BlockComponents.Logical.Timer", "BlockComponents.Hysteresis",
                                  "ElectricalComponents.Analog.Ideal.IdealThyristor"])
def test_an_element_with_memory_is_refused_at_its_declaration(tmp_path, name):
    path = tmp_path / "Rig.dyad"
    path.write_text(f"component Rig\n  k = BlockComponents.Constant(k = 1)\n  latch = {name}()\nend\n")
    with pytest.raises(DyadError) as err:
        flatten_model(str(path))
    assert (err.value.span.file, err.value.span.line, err.value.span.column) == (str(path), 3, 3)
    package = name.split(".")[0]
    assert err.value.message == (f"`{name}` is an element with memory of Dyad's `{package}`: its "
                                 f"output keeps a value set at an earlier event (a latched state), "
                                 f"and dyadc has no discrete states yet (no `pre`, no `when`)")
