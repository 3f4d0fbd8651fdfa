"""What an integrator without root finding (sampled_idas.py) does with the watched functions
(watches.py): find the first crossing between check times, locate it by a root search on short
IDAS runs, predict how far the next call of a state-set model should reach, and where to cut a
call that failed; and which sign changes count (root_directions)."""
from __future__ import annotations

import numpy as np

from .errors import SimulationFailed
from .model import CompiledModel
from .outputs import evaluate_outputs, polish_algebraics
from .state_sets import SWITCH_RATIO, degraded_level
from .watches import Watch

ROOT_ITERATIONS = 60
ROOT_TOLERANCE = 1e-12           # relative, on the time of a located crossing


def before_failure(watch, checks: list[float], failure: SimulationFailed, t: float) -> float | None:
    """The last check time before an IDAS failure inside a watched segment (None: not watched, or
    the failure came before the first check)."""
    if watch is None or failure.time_reached is None or not np.isfinite(failure.time_reached):
        return None
    # the failure time is where IDAS's last step ended (SUNDIALS's own message): every check up
    # to it was passed
    before = [c for c in checks if t < c <= failure.time_reached]
    return before[-1] if before else None


def watched_values(watch: Watch, t0, x0, z0, p, times, checks, segment) -> np.ndarray:
    """The watched functions at the segment's start and at its check times (rows x 1 + checks)."""
    at = np.searchsorted(times, checks)
    xs = np.column_stack([np.asarray(x0, dtype=float).reshape(-1, 1), segment.xs[:, at]])
    zs = np.column_stack([np.asarray(z0, dtype=float).reshape(-1, 1), segment.zs[:, at]])
    return watch.values(xs, zs, p, np.concatenate([[t0], checks]))


def next_horizon(watch: Watch, t0: float, checks: list[float], values: np.ndarray, horizon: float) -> float:
    """How far the next IDAS call of a state-set model reaches: a quarter past where the state-set
    indicators are predicted to cross, between an eighth and twice the last reach.

    An indicator is 1 - SWITCH_RATIO * r (state_sets.switch_indicators), r the largest entry of
    B^-1 A, which grows like the inverse of a coordinate going to zero (a pendulum's x at the
    bottom): 1 / r falls about linearly there, so it is 1 / r that is extrapolated (from the last
    quarter of the checks) to its value at the crossing, 1 / r = SWITCH_RATIO."""
    rows = [i for i, (kind, _) in enumerate(watch.labels) if kind == "state set"]
    grow = 2.0 * horizon
    if not rows or len(checks) < 2:
        return grow
    times = np.concatenate([[t0], checks])
    ratio = (1.0 - values[rows]) / SWITCH_RATIO
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = np.where(ratio > 0, 1.0 / ratio, np.inf)
    j = max(0, len(times) - 1 - len(checks) // 4)
    with np.errstate(invalid="ignore"):
        slope = (inverse[:, -1] - inverse[:, j]) / (times[-1] - times[j])
    falling = (slope < 0) & np.isfinite(slope) & np.isfinite(inverse[:, -1])
    if not falling.any():
        return grow
    gap = float(np.min((inverse[falling, -1] - SWITCH_RATIO) / -slope[falling]))
    return float(np.clip(1.25 * gap, horizon / 8.0, grow))


PERIOD_MATCH = 0.05       # relative agreement of the switch intervals of two repetitions
LONGEST_PERIOD = 8        # switches per period that are looked for
MARGIN_PERIODIC = 1.05    # reach past a stay predicted from a repeating pattern of switches
MARGIN_SAME_SET = 1.25    # past the last stay in the same state set (no pattern found)


def predicted_stay(intervals: list[float], last_in_set: float | None) -> float:
    """How far the first IDAS call after a state-set switch reaches: a little past the predicted
    time to the next switch. An oscillation switches in a repeating pattern (a pendulum released
    near the top: four switches per period, stays of 0.29, 0.24, 0.45 and 1.3 s), so where the
    last k intervals repeat the k before them, the next one is predicted to repeat the interval k
    back; otherwise a quarter more than the last stay in this state set (or the shortest recent
    interval). Each call that ends short costs a restart; each step past the switch is lost."""
    n = len(intervals)
    for k in range(1, LONGEST_PERIOD + 1):
        if n < 2 * k:
            break
        # plain floats, pair by pair (the arithmetic of numpy's elementwise test, without its
        # 10 us of array building per switch)
        if all(abs(recent - before) <= PERIOD_MATCH * max(recent, before)
               for recent, before in zip(intervals[n - k:], intervals[n - 2 * k:n - k])):
            return MARGIN_PERIODIC * intervals[n - k]
    if last_in_set is not None:
        return MARGIN_SAME_SET * last_in_set
    return min(intervals[-2:])


def root_directions(watch: Watch) -> np.ndarray:
    """Which sign changes of each watched row count, as IDAS's root directions: 0 both ways (a
    state event), -1 from positive to not positive (a bound left, a state set degrading)."""
    return np.array([0 if kind == "event" else -1 for kind, _ in watch.labels], dtype=int)


def first_crossing(model: CompiledModel, watch: Watch, t0, p, times, checks, segment, values,
                   ignored: set[int] = frozenset()):
    """(check time after the crossing, check time before it, row) of the first watched function
    that changes sign between two check times; None when none does. Rows in `ignored` are not
    looked at (bounds already warned of)."""
    at = np.searchsorted(times, checks)
    xs, zs = segment.xs[:, at], segment.zs[:, at]
    before, after = values[:, :-1], values[:, 1:]
    both_ways = (root_directions(watch) == 0)[:, None]
    crossed = np.where(both_ways, (before > 0) != (after > 0), (before > 0) & ~(after > 0))
    crossed &= np.isfinite(before)
    if ignored:
        crossed[sorted(ignored)] = False
    rows_of = {what: i for i, (kind, what) in enumerate(watch.labels) if kind == "state set"}
    multi = proposing_rows(model, watch)
    crossed[multi] = False
    hits = list(np.nonzero(crossed.any(axis=0))[0])
    proposed = list(np.nonzero((~(after[multi] > 0)).any(axis=0))[0]) if multi else []
    proposed = [j for j in proposed if not hits or j < hits[0]]
    if proposed:
        at_checks = np.asarray(checks)[proposed]
        polished = polish_algebraics(model, xs[:, proposed], zs[:, proposed], p, at_checks)
        outputs = evaluate_outputs(model, xs[:, proposed], polished, p, at_checks)
        first = _first_degraded(model, outputs, rows_of)
        if first is not None:
            column, level = first
            j = proposed[column]
            return float(checks[j]), float(t0 if j == 0 else checks[j - 1]), rows_of[level]
    if not hits:
        return None
    j = int(hits[0])
    row = int(np.nonzero(crossed[:, j])[0][0])
    return float(checks[j]), float(t0 if j == 0 else checks[j - 1]), row


def proposing_rows(model: CompiledModel, watch: Watch) -> list[int]:
    """The watched rows whose crossing only proposes a state-set switch. A single-row level's
    indicator is its quality test already (|pivot| against the largest alternative); a multi-row
    level's is not: the switch is taken where the chosen block's smallest singular value is below
    SWITCH_RATIO times that of the block pivoting would choose (state_sets.degraded_level; the
    determinant ratio behind the indicator depends on the columns' units)."""
    rows_of = {what: i for i, (kind, what) in enumerate(watch.labels) if kind == "state set"}
    return [rows_of[level] for level, spec in enumerate(model.state_sets)
            if level in rows_of and int(spec["rows"]) > 1]


QUALITY_PROBES = 8        # proposed checks whose pivot quality is computed first, evenly spread


def _first_degraded(model: CompiledModel, outputs: np.ndarray, rows_of: dict) -> tuple[int, int] | None:
    """The first column of `outputs` (proposed checks, in time order) where a multi-row level's
    pivot quality is below SWITCH_RATIO, with the level; None if there is none. The quality costs
    a pivoted Gram-Schmidt and two SVDs per point (an 8-body chain spent 97 % of its run on it when
    every proposed check was evaluated): evenly spread probes first, then a bisection between the
    last good probe and the first bad one (a degraded pivot stays degraded until the switch)."""
    def degraded(column: int):
        level = degraded_level(model.state_sets, outputs[:, column])
        return level if level in rows_of else None
    n = outputs.shape[1]
    probes = sorted(set(np.linspace(0, n - 1, min(n, QUALITY_PROBES)).round().astype(int).tolist()))
    good, bad = -1, None
    for column in probes:
        level = degraded(column)
        if level is not None:
            bad = (column, level)
            break
        good = column
    if bad is None:
        return None
    while bad[0] - good > 1:
        middle = (good + bad[0]) // 2
        level = degraded(middle)
        if level is not None:
            bad = (middle, level)
        else:
            good = middle
    return bad


def locate(add, integrator, watch: Watch, row: int, t_a: float, t_b: float, x_a, z_a, p):
    """The crossing of watch row `row` in (t_a, t_b] by the Illinois method on short IDAS runs
    from (t_a, x_a, z_a) (their counters go to `add`): the first time found on the far side, the point there and True; or t_b,
    the point there and False when the run from t_a does not cross at all."""
    def value_at(t):
        if t == t_a:
            return float(watch.values(np.asarray(x_a).reshape(-1, 1), np.asarray(z_a).reshape(-1, 1),
                                      p, [t])[row, 0]), x_a, z_a
        segment = integrator.run_to(t_a, t, x_a, z_a, p)
        add(segment.counters)
        xs, zs = segment.xs[:, -1], segment.zs[:, -1]
        return float(watch.values(xs.reshape(-1, 1), zs.reshape(-1, 1), p, [t])[row, 0]), xs, zs

    g_a, _, _ = value_at(t_a)
    g_b, x_b, z_b = value_at(t_b)
    if (g_b > 0) == (g_a > 0):
        return t_b, x_b, z_b, False
    lo, hi, g_lo, g_hi, side = t_a, t_b, g_a, g_b, 0
    for _ in range(ROOT_ITERATIONS):
        if hi - lo <= ROOT_TOLERANCE * max(1.0, abs(hi)):
            break
        guess = hi - g_hi * (hi - lo) / (g_hi - g_lo) if g_hi != g_lo else 0.5 * (lo + hi)
        if not lo < guess < hi:
            guess = 0.5 * (lo + hi)
        g, x_g, z_g = value_at(guess)
        if (g > 0) == (g_lo > 0):
            lo, g_lo = guess, g
            if side == -1:
                g_hi *= 0.5                         # Illinois: keep the stale end from stalling
            side = -1
        else:
            hi, g_hi, x_b, z_b = guess, g, x_g, z_g
            if side == 1:
                g_lo *= 0.5
            side = 1
    return hi, x_b, z_b, True
