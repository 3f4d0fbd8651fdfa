"""Running `dyadc` in a fresh process with a cache folder of the test's own, and a small library
(a decaying state, a component using it, a Python function plugin) to edit between runs."""
from __future__ import annotations

import functools
import json
import os
import subprocess
import sys
import textwrap
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
HEAVY = ("sympy", "lark")

# Runs the command line in this process, then records which heavy packages it imported.
_DRIVER = """
import json, sys
from compiler.cli import main
code = main(sys.argv[2:])
with open(sys.argv[1], "w") as out:
    json.dump(sorted(m for m in %r if m in sys.modules), out)
raise SystemExit(code)
""" % (HEAVY,)

DECAY = """
component Decay
  parameter k::Real = 2.0
  variable x::Real
relations
  initial x = 1.0
  der(x) = -k * x
end
"""

SCALED = """
component Scaled
  d = Decay()
  variable y::Real
relations
  y = triple(1.0) * d.x
end
"""

PLUGIN = """
def register(registry):
    registry.register("CacheLib.triple", lambda x: 3 * x, 1, 1)
"""


@dataclass
class Run:
    code: int
    stdout: str
    stderr: str
    imported: list[str]           # which of HEAVY the process imported

    @property
    def compiled(self) -> bool:
        """The process compiled from source (a cache hit imports neither sympy nor lark)."""
        return "sympy" in self.imported

    def final(self, name: str) -> float:
        for line in self.stdout.splitlines():
            parts = line.split()
            if parts and parts[0] == name:
                return float(parts[1])
        raise KeyError(f"{name} not in the output:\n{self.stdout}")


def environment(cache: Path | str, **extra: str) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("DYADC_PATH", "DYADC_CACHE")}
    env["DYADC_CACHE_DIR"] = str(cache)
    env.update(extra)
    return env


def command(log: Path, *args: str) -> list[str]:
    return [sys.executable, "-c", _DRIVER, str(log), *map(str, args)]


def dyadc(cache: Path | str, *args: str, log: Path | None = None, **env: str) -> Run:
    """`dyadc ARGS` in a new process whose cache is `cache`."""
    log = log or Path(str(cache) + ".imports.json")
    done = subprocess.run(command(log, *args), cwd=ROOT, env=environment(cache, **env),
                          capture_output=True, text=True, timeout=600)
    imported = json.loads(log.read_text()) if log.exists() else []
    log.unlink(missing_ok=True)
    return Run(done.returncode, done.stdout, done.stderr, imported)


def write(path: Path, text: str) -> Path:
    """`text` (dedented) into `path`, its folders made."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text).lstrip(), encoding="utf-8")
    return path


def small_library(folder: Path) -> Path:
    """`folder` holding package CacheLib: Decay, Scaled (uses Decay and the plugin's triple)."""
    write(folder / "CacheLib" / "Decay.dyad", DECAY)
    write(folder / "CacheLib" / "Scaled.dyad", SCALED)
    write(folder / "CacheLib" / "dyad_functions.py", PLUGIN)
    return folder


def entries(cache: Path, suffix: str = ".model") -> list[Path]:
    return sorted((cache / "models").glob(f"*{suffix}"))


def _compiler_now() -> str:
    from compiler.cache.keys import compiler_fingerprint
    return compiler_fingerprint.__wrapped__()          # not the process's memoized value


def retried_if_the_compiler_changes(test):
    """Run `test` again (up to 3 times, in a fresh folder) when it failed while the compiler's own
    files changed: in a shared work tree an edit between two runs rightly makes the second a miss.
    A failure with the compiler unchanged fails at once."""
    @functools.wraps(test)
    def wrapper(*args, tmp_path, **kwargs):
        for attempt in range(3):
            before = _compiler_now()
            folder = tmp_path / f"attempt{attempt}"
            folder.mkdir()
            try:
                return test(*args, tmp_path=folder, **kwargs)
            except AssertionError:
                if attempt == 2 or _compiler_now() == before:
                    raise
    return wrapper
