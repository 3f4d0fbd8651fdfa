"""Metamorphic tests: every model of the corpus (corpus.py) rewritten into an equivalent
formulation (rewrites.py) must give the same verdict and the same numbers (agreement.py).

`make test` runs a fixed sample (SAMPLE: the same cases on every machine); `make fuzz` runs
DYADC_METAMORPHIC_EXAMPLES seeds of every model. A failing case names its model and seed:
`.venv/bin/python -m pytest tests/metamorphic -k 'Robertson-7'` repeats it, and
`python -m tests.metamorphic.show Robertson 7` prints the rewritten source.
"""
from __future__ import annotations

import os

import pytest

from tests.metamorphic import agreement, rewrites
from tests.metamorphic.corpus import BASES, BY_LABEL, EXCAVATOR
from compiler.syntax.parser import parse_file

# (model, seed): the Test Set problems, a hard case, test components and the excavator, chosen
# once so that every rewrite of REWRITES appears (test below), sized for about a minute on 2 cores.
SAMPLE = (
    ("AndrewsTestSet", 1), ("Robertson", 5), ("Robertson", 2), ("Robertson", 4), ("Robertson", 6),
    ("CartesianPendulum", 0), ("PendulumA01", 2), ("Andrews", 6), ("FallingBody", 0),
    ("LCOscillator", 3), ("Excavator", 2),
)


# Rewrites that change the verdict today: strict xfails, each a bug found by the generator (an
# entry passes once its bug is fixed, which fails the suite until the entry is removed).
KNOWN: dict = {}


def _case(label: str, seed: int):
    if (label, seed) not in KNOWN:
        return (label, seed)
    why, kind = KNOWN[label, seed]
    return pytest.param(label, seed, marks=pytest.mark.xfail(strict=True, reason=why, raises=kind))


def _cases():
    requested = os.environ.get("DYADC_METAMORPHIC_EXAMPLES")
    if not requested:
        return [_case(*case) for case in SAMPLE + tuple(KNOWN)]
    return [_case(base.label, seed) for base in BASES for seed in range(int(requested))]


@pytest.fixture(scope="session")
def base_runs():
    """label -> (the base's run at its tolerance, at the reference tolerance), run once."""
    cache = {}

    def get(base):
        if base.label not in cache:
            cache[base.label] = agreement.run(base.path, base, base.rtol, agreement.REFERENCE_RTOL)
        return cache[base.label]
    return get


def _id(case) -> str:
    label, seed = case.values if hasattr(case, "values") else case
    return f"{label}-{seed}"


@pytest.mark.parametrize("label, seed", _cases(), ids=[_id(case) for case in _cases()])
def test_a_rewritten_model_gives_the_same_verdict_and_numbers(label, seed, base_runs, tmp_path):
    base = BY_LABEL[label]
    component = agreement.definition(parse_file(base.path), base.name)
    rewritten, applied = rewrites.rewrite(component, seed)
    assert applied, f"no rewrite applies to {label}"
    path = agreement.write_variant(base, rewritten.component, tmp_path)
    outcome, reference = base_runs(base)
    if outcome.ran:
        assert reference.ran, f"the base runs at rtol {base.rtol} but not at the reference's: {reference.error}"
    (variant,) = agreement.run(path, base, base.rtol)
    found = agreement.disagreements(outcome, variant, reference, rewritten.renamed, base.rtol)
    assert not found, (f"{label} seed {seed}, rewrites {applied}:\n  " + "\n  ".join(found[:12])
                       + f"\nsource: {path}\n" + path.read_text()[:4000])


def test_the_sample_covers_every_rewrite_and_the_excavator():
    applied = set()
    for label, seed in SAMPLE:
        base = BY_LABEL[label]
        _, names = rewrites.rewrite(agreement.definition(parse_file(base.path), base.name), seed)
        applied.update(names)
    assert EXCAVATOR.label in dict(SAMPLE)
    assert applied == set(rewrites.REWRITES), set(rewrites.REWRITES) - applied
