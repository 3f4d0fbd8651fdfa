"""Mutated sources either parse or fail with a located DyadError, never another exception."""
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from compiler.errors import DyadError
from compiler.syntax.format import format_file
from compiler.syntax.parser import parse_source, tokenize

SOURCES = [Path(__file__).parent / "valid" / "all_constructs.dyad",
           Path(__file__).resolve().parents[2] / "components/MultibodyComponents/"
           "PlanarMechanics/examples/excavator/SoilContact.dyad"]
TEXTS = [p.read_text(encoding="utf-8") for p in SOURCES]
TOKENS = [tokenize(text, "fuzz") for text in TEXTS]


def _mutate(text: str, tokens, operation: str, i: int, j: int) -> str:
    a, b = tokens[i % len(tokens)], tokens[j % len(tokens)]
    if operation == "delete":
        return text[:a.start_pos] + text[a.end_pos:]
    if operation == "duplicate":
        return text[:a.end_pos] + " " + a.value + text[a.end_pos:]
    first, second = sorted((a, b), key=lambda t: t.start_pos)
    if first.end_pos > second.start_pos:
        return text
    return (text[:first.start_pos] + second.value + text[first.end_pos:second.start_pos]
            + first.value + text[second.end_pos:])


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(source=st.integers(0, len(TEXTS) - 1),
       operations=st.lists(st.tuples(st.sampled_from(["delete", "duplicate", "swap"]),
                                     st.integers(0, 10**6), st.integers(0, 10**6)),
                           min_size=1, max_size=3))
def test_mutated_source_parses_or_fails_with_span(source, operations):
    text = TEXTS[source]
    for operation, i, j in operations:
        text = _mutate(text, TOKENS[source], operation, i, j)
    try:
        parsed = parse_source(text, "fuzz.dyad")
    except DyadError as err:
        assert err.span is not None and err.span.file == "fuzz.dyad"
        assert err.span.line >= 1 and err.span.column >= 1
        err.format()
        return
    assert parse_source(format_file(parsed), "fuzz-formatted.dyad") == parsed


@settings(max_examples=100, deadline=None)
@given(st.text(alphabet='component end relations parameter x::Real = ( ) [ ] { } " # \n 1 , ;',
               max_size=60))
def test_random_token_soup_never_crashes(text):
    try:
        parse_source(text, "soup.dyad")
    except DyadError as err:
        assert err.span is not None
