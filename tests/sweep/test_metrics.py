"""The metric evaluator: numpy semantics, Julia precedence, located errors, nothing but its grammar."""
import numpy as np
import pytest

from compiler.errors import DyadError
from compiler.sweep.metrics import parse_metric, parse_metrics

TIME = np.linspace(0.0, 2.0, 201)
SIGNALS = {"tip.y": np.sin(3 * TIME) - 0.2, "body.r[1]": TIME ** 2, "p": np.full_like(TIME, 4.0)}


def value(text):
    return parse_metric(text).evaluate(SIGNALS.__getitem__, TIME)


@pytest.mark.parametrize("text, expected", [
    ("max(abs(tip.y))", np.max(np.abs(SIGNALS["tip.y"]))),
    ("min(tip.y)", np.min(SIGNALS["tip.y"])),
    ("final(body.r[1])", 4.0),
    ("initial(body.r[1]) + 1", 1.0),
    ("body.r[1]", 4.0),                                   # a signal left as a signal: its final value
    ("mean(p) * 2 - 1", 7.0),
    ("rms(p)", 4.0),
    ("integral(body.r[1])", np.sum(0.5 * (TIME[1:] ** 2 + TIME[:-1] ** 2) * np.diff(TIME))),
    ("argmax(tip.y)", TIME[np.argmax(SIGNALS["tip.y"])]),
    ("max(max(tip.y, 0))", np.max(np.maximum(SIGNALS["tip.y"], 0))),
    ("-2^2", -4.0),                                       # ^ binds tighter than unary minus
    ("2^3^2", 512.0),                                     # and is right-associative
    ("2**-1", 0.5),
    ("(1 + 2) * 3 / 4", 2.25),
    ("sqrt(final(p)) + exp(0) + log(1) + sign(-3)", 2.0),
    ("max(time)", 2.0),
])
def test_values(text, expected):
    assert value(text) == pytest.approx(expected, rel=1e-14, abs=1e-14)


def test_labels_and_names():
    metric = parse_metric("peak = max(abs(tip.y)) + final(body.r[ 1 ])")
    assert metric.label == "peak" and metric.names == ("tip.y", "body.r[1]")
    assert parse_metric("max(p)").label == "max(p)"
    with pytest.raises(DyadError, match="two metrics are called `a`"):
        parse_metrics(["a=max(p)", "a=min(p)"])


@pytest.mark.parametrize("text, says, column", [
    ("max(tip.y", "missing `)`", 10),
    ("foo(p)", "unknown function `foo`", 1),
    ("__import__('os')", "unexpected character `'`", 12),
    ("p.__class__", None, None),                          # a name, not an attribute: unknown signal
    ("max(p, p, p)", "takes 1 or 2 argument", 1),
    ("final(p, 2)", "takes 1 argument", 1),
    ("1 +", "ends too early", 4),
    ("p p", "unexpected `p`", 3),
    ("a; b", "unexpected character `;`", 2),
])
def test_bad_metrics_are_located_errors(text, says, column):
    if says is None:
        metric = parse_metric(text)
        assert metric.names == ("p.__class__",)
        with pytest.raises(KeyError):
            metric.evaluate(SIGNALS.__getitem__, TIME)
        return
    with pytest.raises(DyadError) as info:
        parse_metric(text)
    assert says in info.value.message
    assert info.value.span.column == column
    assert "^" in info.value.format() and text in info.value.format()
