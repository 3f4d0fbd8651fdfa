"""Issue 28: the hint on a missing golden file is a command that runs as printed, with the -L
folders the user gave (and quoted for a shell)."""
from __future__ import annotations

import shlex

from compiler.cli import main

DECAY = """component Decay
  variable x::Real
relations
  initial x = 1
  der(x) = -x
metadata {"Dyad": {"tests": {"decay": {"stop": 1, "rtol": 1e-8, "atol": {"x": 1e-6}, "expect": {"signals": ["x"]}}}}}
end
"""


def test_the_missing_golden_hint_runs_as_printed(tmp_path, capsys):
    library = tmp_path / "my lib"
    (library / "MyPkg").mkdir(parents=True)
    (library / "MyPkg" / "Decay.dyad").write_text(DECAY, encoding="utf-8")
    goldens = tmp_path / "goldens"
    assert main(["test", "MyPkg.Decay", "-L", str(library), "--golden", str(goldens)]) == 1
    out = capsys.readouterr().out
    hint = next(line for line in out.splitlines() if "hint: " in line)
    command = shlex.split(hint.split("independently): ", 1)[1])
    assert command == ["dyadc", "test", "MyPkg.Decay", "-L", str(library), "--golden", str(goldens),
                       "--accept"]
    assert main(command[1:]) == 0
    capsys.readouterr()
    assert (goldens / "MyPkg.Decay.decay.csv").is_file()
    assert main(["test", "MyPkg.Decay", "-L", str(library), "--golden", str(goldens)]) == 0
