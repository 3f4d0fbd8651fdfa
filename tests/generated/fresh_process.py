"""Run a script in a fresh Python process (so that nothing of the compiler is imported unless the
script imports it) and return the JSON object it prints last."""
import json
import subprocess
import sys
from pathlib import Path


def run_json(script: str, cwd: Path, env: dict | None = None) -> dict:
    """`env`: the process's environment (default: this one's)."""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=cwd, timeout=300,
                          env=env)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])
