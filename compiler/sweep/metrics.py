"""Per-sample scalar metrics such as `max(abs(bucket.frame_b.y))`, evaluated safely over numpy.

A metric is `EXPR` or `LABEL=EXPR`. EXPR has numbers, signal names (dotted, optionally indexed:
`body.r[1]`, and `time`), `+ - * / ^` (also `**`), parentheses and these functions:
  reductions of a signal to a number: max min mean rms final initial integral argmax argmin
    (argmax/argmin give the time of the extreme; integral is the trapezoidal rule over time)
  element-wise: abs sqrt exp log sin cos tan sign, and max(a, b), min(a, b) with two arguments
A metric whose value is still a signal is its final value. The text is parsed here into a small
tree and evaluated by walking it: no Python eval, no attribute access, nothing but these names.
This module imports numpy and compiler.errors only (workers evaluate metrics).
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from compiler.errors import DyadError, Span, register_source

_TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)
  | (?P<name>[A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*(?:\[\s*\d+(?:\s*,\s*\d+)*\s*\])?)
  | (?P<op>\*\*|[-+*/^(),])
""", re.VERBOSE)

_ELEMENTWISE = {"abs": np.abs, "sqrt": np.sqrt, "exp": np.exp, "log": np.log, "sin": np.sin,
                "cos": np.cos, "tan": np.tan, "sign": np.sign}
_REDUCTIONS = ("max", "min", "mean", "rms", "final", "initial", "integral", "argmax", "argmin")
FUNCTIONS = tuple(sorted(set(_ELEMENTWISE) | set(_REDUCTIONS)))


@dataclass(frozen=True)
class Metric:
    label: str
    text: str
    tree: tuple
    names: tuple[str, ...]            # the signals it reads

    def evaluate(self, signal: Callable[[str], np.ndarray], time: np.ndarray) -> float:
        value = np.asarray(_evaluate(self.tree, signal, time), dtype=float)
        return float(value.reshape(-1)[-1]) if value.ndim else float(value)


def parse_metric(spec: str, index: int = 1) -> Metric:
    label, text = _split_label(spec)
    source = f"<metric {index}>"
    register_source(source, text)
    tokens = _tokenize(text, source)
    parser = _Parser(tokens, text, source)
    tree = parser.expression()
    if parser.peek() is not None:
        parser.fail(f"unexpected `{parser.peek()[1]}`", parser.peek()[2])
    return Metric(label or text.strip(), text, tree, tuple(dict.fromkeys(_names(tree))))


def parse_metrics(specs: Sequence[str]) -> list[Metric]:
    metrics = [parse_metric(s, i + 1) for i, s in enumerate(specs)]
    seen: set[str] = set()
    for m in metrics:
        if m.label in seen:
            raise DyadError(f"two metrics are called `{m.label}`", hint="name them: LABEL=EXPR")
        seen.add(m.label)
    return metrics


def _split_label(spec: str) -> tuple[str | None, str]:
    match = re.match(r"^\s*([A-Za-z_]\w*)\s*=(.*)$", spec, re.S)
    return (match.group(1), match.group(2)) if match else (None, spec)


def _tokenize(text: str, source: str) -> list[tuple[str, str, int]]:
    tokens, pos = [], 0
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if not match:
            raise _error(f"unexpected character `{text[pos]}` in metric", source, pos)
        if match.lastgroup != "space":
            tokens.append((match.lastgroup, match.group(), pos))
        pos = match.end()
    return tokens


def _error(message: str, source: str, pos: int) -> DyadError:
    return DyadError(message, Span(source, 1, pos + 1, 1, pos + 1),
                     hint=f"a metric is an expression of signals with + - * / ^ and "
                          f"{', '.join(FUNCTIONS)}, e.g. max(abs(tip.y))")


class _Parser:
    """Recursive descent; `^` binds tighter than unary minus and is right-associative (Julia)."""

    def __init__(self, tokens, text, source):
        self.tokens, self.pos, self.text, self.source = tokens, 0, text, source

    def peek(self):
        return self.tokens[self.pos] if self.pos < len(self.tokens) else None

    def take(self):
        token = self.peek()
        if token is None:
            self.fail("the metric ends too early", len(self.text))
        self.pos += 1
        return token

    def fail(self, message, pos):
        raise _error(message, self.source, pos)

    def accept(self, op: str) -> bool:
        token = self.peek()
        if token is not None and token[0] == "op" and token[1] == op:
            self.pos += 1
            return True
        return False

    def expression(self):
        node = self.term()
        while (token := self.peek()) is not None and token[1] in ("+", "-") and token[0] == "op":
            self.pos += 1
            node = ("bin", token[1], node, self.term())
        return node

    def term(self):
        node = self.unary()
        while (token := self.peek()) is not None and token[1] in ("*", "/") and token[0] == "op":
            self.pos += 1
            node = ("bin", token[1], node, self.unary())
        return node

    def unary(self):
        if self.accept("-"):
            return ("neg", self.unary())
        if self.accept("+"):
            return self.unary()
        return self.power()

    def power(self):
        base = self.atom()
        if self.accept("^") or self.accept("**"):
            return ("bin", "^", base, self.unary())
        return base

    def atom(self):
        kind, text, pos = self.take()
        if kind == "number":
            return ("num", float(text))
        if kind == "name":
            if self.accept("("):
                return self.call(text, pos)
            return ("name", re.sub(r"\s+", "", text))
        if text == "(":
            node = self.expression()
            if not self.accept(")"):
                self.fail("missing `)`", self.peek()[2] if self.peek() else len(self.text))
            return node
        self.fail(f"unexpected `{text}`", pos)

    def call(self, name: str, pos: int):
        if name not in FUNCTIONS:
            self.fail(f"unknown function `{name}`", pos)
        args = [self.expression()]
        while self.accept(","):
            args.append(self.expression())
        if not self.accept(")"):
            self.fail("missing `)` after the arguments", self.peek()[2] if self.peek() else len(self.text))
        allowed = (1, 2) if name in ("max", "min") else (1,)
        if len(args) not in allowed:
            self.fail(f"`{name}` takes {' or '.join(map(str, allowed))} argument(s), got {len(args)}", pos)
        return ("call", name, tuple(args))


def _names(tree) -> list[str]:
    if tree[0] == "name":
        return [tree[1]]
    if tree[0] == "call":
        return [n for arg in tree[2] for n in _names(arg)]
    if tree[0] == "bin":
        return _names(tree[2]) + _names(tree[3])
    if tree[0] == "neg":
        return _names(tree[1])
    return []


_BINARY = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.divide, "^": np.power}


def _evaluate(tree, signal, time):
    kind = tree[0]
    if kind == "num":
        return tree[1]
    if kind == "name":
        return np.asarray(time if tree[1] == "time" else signal(tree[1]), dtype=float)
    if kind == "neg":
        return -_evaluate(tree[1], signal, time)
    if kind == "bin":
        with np.errstate(all="ignore"):             # 1/0 is inf, like a signal would be
            return _BINARY[tree[1]](_evaluate(tree[2], signal, time), _evaluate(tree[3], signal, time))
    name, args = tree[1], [_evaluate(a, signal, time) for a in tree[2]]
    if len(args) == 2:
        return (np.maximum if name == "max" else np.minimum)(*args)
    x = np.asarray(args[0], dtype=float)
    if name in _ELEMENTWISE:
        with np.errstate(all="ignore"):
            return _ELEMENTWISE[name](x)
    series = np.broadcast_to(x, time.shape) if x.ndim == 0 else x
    if name == "max":
        return float(np.max(series))
    if name == "min":
        return float(np.min(series))
    if name == "mean":
        return float(np.mean(series))
    if name == "rms":
        return float(np.sqrt(np.mean(series * series)))
    if name == "final":
        return float(series[-1])
    if name == "initial":
        return float(series[0])
    if name == "integral":
        return float(np.sum(0.5 * (series[1:] + series[:-1]) * np.diff(time)))
    return float(time[int(np.argmax(series) if name == "argmax" else np.argmin(series))])
