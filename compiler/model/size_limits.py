"""How much a model may make the compiler build (issue 19, item 5), checked before anything is
allocated: an array size, a range, an unrolled `for` loop, a comprehension or a component array
has at most `max_elements()` elements, and an exact power of two constants is folded only while its
exact value stays small (beyond that it is evaluated as a float, and a float overflow is an error).

Every refusal is a located DyadError that gives the estimate and the limit. The limit comes from
`element_limit(N)` (the CLI's --max-elements), else $DYADC_MAX_ELEMENTS, else DEFAULT_MAX_ELEMENTS;
docs/security.md documents both. Measured on this machine: `dyadc check` of a model with an array
of 100,000 unknowns takes 12 s and 0.2 GB, of 1,000,000 unknowns 133 s and 1.5 GB: the default lets
the largest models that still compile in minutes through and stops sizes that could never finish.
"""
from __future__ import annotations

import math
import os
from contextlib import contextmanager
from contextvars import ContextVar
from typing import TYPE_CHECKING, Any, Iterator

from compiler.errors import DyadError, Span

if TYPE_CHECKING:        # imported where powers are folded: `dyadc` itself must not import sympy
    import sympy

DEFAULT_MAX_ELEMENTS = 1_000_000
MAX_ELEMENTS_ENV = "DYADC_MAX_ELEMENTS"

# An exact power whose numerator or denominator would need more bits than this is evaluated as a
# float instead: 10^400 (1329 bits) stays exact, 9^9^9 (1.2e9 bits, minutes of sympy) does not.
MAX_EXACT_BITS = 8192

_configured: ContextVar[int | None] = ContextVar("dyadc_max_elements", default=None)


@contextmanager
def element_limit(limit: int | None) -> Iterator[None]:
    """Use `limit` (None: the environment's or the default) for the compilations in this block."""
    if limit is not None and limit < 1:
        raise DyadError(f"--max-elements must be at least 1, got {limit}")
    token = _configured.set(limit)
    try:
        yield
    finally:
        _configured.reset(token)


def max_elements() -> int:
    configured = _configured.get()
    if configured is not None:
        return configured
    return positive_integer_setting(MAX_ELEMENTS_ENV, DEFAULT_MAX_ELEMENTS)


def positive_integer_setting(variable: str, default: int) -> int:
    """The positive integer in the environment variable `variable`, else `default`; anything else
    there is a clear error."""
    text = os.environ.get(variable)
    if text is None:
        return default
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise DyadError(f"${variable} must be a positive integer, got `{text}`")
    return value


def amount(count: int) -> str:
    """1,000,000 for a count a reader can take in; `about 1e+308` or `about 10^4999` beyond."""
    if abs(count) < 10**15:
        return f"{count:,}"
    try:
        return f"about {float(count):.3g}"
    except OverflowError:
        return f"about 10^{len(str(abs(count))) - 1}"


def check_elements(count: int, span: Span | None, what: str) -> None:
    """Refuse `what` (e.g. "the range `1:1000000000`") when `count` exceeds the limit."""
    limit = max_elements()
    if count > limit:
        raise DyadError(f"{what} would create {amount(count)} elements, more than the limit of "
                        f"{limit:,}", span,
                        hint=f"a model this large cannot be compiled in reasonable time and memory; "
                             f"if you mean it, raise the limit with --max-elements N or "
                             f"${MAX_ELEMENTS_ENV}")


def check_shape(shape: tuple[int, ...], span: Span | None, what: str) -> tuple[int, ...]:
    """An array shape: every size at least 0 and at most the limit in all."""
    for size in shape:
        if size < 0:
            raise DyadError(f"an array size cannot be negative, got {amount(size)}", span)
    check_elements(math.prod(shape), span, what)
    return shape


def range_length(start: int, stop: int, step: int) -> int:
    """len(range(start, stop inclusive, step)) without materializing it (exact for any size)."""
    if step > 0:
        return max(0, (stop - start) // step + 1)
    return max(0, (start - stop) // -step + 1)


def _bits(value: sympy.Rational) -> int:
    return max(int(value.p).bit_length(), int(value.q).bit_length())


def checked_power(base: Any, exponent: Any, span: Span | None) -> Any:
    """base ** exponent, except that a power of constants too large to fold exactly is evaluated
    as a float (a float operand makes it one anyway); a result beyond a float is a located error."""
    import sympy
    numbers = (sympy.Rational, sympy.Float)
    if not (isinstance(base, numbers) and isinstance(exponent, numbers)):
        return base ** exponent
    if abs(base) in (0, 1) or exponent.is_zero:
        return base ** exponent
    exact = isinstance(base, sympy.Rational) and isinstance(exponent, sympy.Rational)
    if exact and abs(exponent) * _bits(base) <= MAX_EXACT_BITS:
        return base ** exponent
    try:
        value = math.pow(float(base), float(exponent))
    except ValueError:
        raise DyadError(f"the power {_short(base)}^{_short(exponent)} is not a real number", span) from None
    except OverflowError:
        value = math.inf
    if not math.isfinite(value):
        digits = float(exponent) * float(sympy.log(abs(base), 10).evalf())
        raise DyadError(f"the power {_short(base)}^{_short(exponent)} is too large: about "
                        f"10^{_magnitude(digits)}, beyond a 64-bit float (at most about 1.8e308)", span,
                        hint="a constant this large is almost always a typo (`9^9^9` is 9^(9^9))")
    return sympy.Float(value)


def _short(value: Any) -> str:
    import sympy
    if isinstance(value, sympy.Float):
        text = repr(float(value)) if abs(value) < 1e308 else str(value)
        text = text if len(text) <= 12 else f"{float(value):.6g}"
        return text if value >= 0 else f"({text})"
    text = str(value) if value >= 0 and value.is_Integer else f"({value})"
    return text if len(text) <= 30 else f"({text[:12]}...{text[-6:]}, {len(text)} characters)"


def _magnitude(digits: float) -> str:
    """The decimal exponent of a too-large power: grouped digits, or in e-notation when longer."""
    return f"{int(digits):,}" if digits < 1e15 else f"{digits:.3g}"