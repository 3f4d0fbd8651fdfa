"""How many examples, and where each one runs: example counts from DYADC_FUZZ_EXAMPLES (`make fuzz`),
the same examples on every machine (derandomize), no example database written into the repository,
a fresh working folder per example."""
from __future__ import annotations

import itertools
import os
from pathlib import Path

from hypothesis import HealthCheck, settings

_counter = itertools.count()


def fuzz_settings(default_examples: int, share: float = 1.0):
    """`default_examples` in `make test` (sized for about a minute in all on 2 cores); when
    DYADC_FUZZ_EXAMPLES is set, that many per test, times `share` for tests whose examples are
    slow (a fresh process each), but never fewer than the default."""
    requested = os.environ.get("DYADC_FUZZ_EXAMPLES")
    examples = max(default_examples, int(int(requested) * share)) if requested else default_examples
    return settings(max_examples=examples, deadline=None, derandomize=True, database=None,
                    print_blob=False, suppress_health_check=list(HealthCheck))


def example_dir(base: Path) -> Path:
    """A fresh working folder two levels below `base`, so that `../name` stays inside `base`."""
    work = base / f"example{next(_counter)}" / "cwd"
    work.mkdir(parents=True)
    return work


def write_seed(work: Path, seed, text: str | None = None) -> Path:
    path = work / f"{seed.name}.dyad"
    path.write_text(seed.text if text is None else text, encoding="utf-8", errors="surrogatepass")
    return path
