"""A seeded fuzz of the analysis functions (issue 37, item 10): each case
takes the valid call of one function (`test_hostile_input.VALID`) and
changes one to three of its arguments: shapes (empty, 0-length axes, a
missing or extra axis, a long broadcast series), dtypes, non-contiguous
layouts, extreme and non-finite values, values of the wrong type, and
`max_lag` from 0 to 2^70. Asserted for every case: the call returns or
raises `ValueError` or `TypeError` (never `InternalError` or another
type), every message starts by naming an argument, every number returned
is finite (the README: results that would overflow are refused), and no
case takes longer than `CASE_BOUND` seconds. Sizes and seed: `fuzzing`."""

from __future__ import annotations

import contextlib
import inspect
import re
import time
import warnings
from pathlib import Path

import numpy as np

import quatrot
from fuzzing import HOSTILE_FLOATS, HOSTILE_INTS, Failures, cases, hostile_scalar, pick
from test_hostile_input import VALID

#: The analysis API: the functions of the analysis guide's table.
GUIDE = Path(__file__).resolve().parents[2] / "docs" / "guide" / "analysis.md"
FUNCTIONS = tuple(re.findall(r"`quatrot\.(\w+)\(", GUIDE.read_text()))

CASES = 600
#: The longest a case may take, in seconds (the slowest seen take 0.1 s).
CASE_BOUND = 10.0
#: The longest series a case broadcasts an argument to (a few MB).
LONG = 100_000

DTYPES = (np.int64, np.int8, np.uint8, np.float16, np.float32, np.bool_, np.complex128, object, str)


def reshaped(v: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """`v` with an axis emptied, dropped, added, resized or made long."""
    kind = int(rng.integers(5))
    axis = int(rng.integers(v.ndim)) if v.ndim else 0
    if kind == 0 and v.ndim:
        return np.take(v, [], axis=axis)
    if kind == 1 and v.ndim and v.shape[axis]:
        return np.take(v, 0, axis=axis)
    if kind == 2:
        return v[None] if rng.random() < 0.5 else v[..., None]
    if kind == 3 and v.ndim:
        return np.resize(v, (*v.shape[:-1], int(rng.integers(6))))
    if not v.size:
        return v[None]
    return np.broadcast_to(v[:1] if v.ndim else v, (LONG, *v.shape[1:]))


def revalued(v: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """`v` scaled by a power of ten, or with some entries made hostile."""
    v = np.array(v, dtype=np.float64)
    if rng.random() < 0.5 or not v.size:
        with np.errstate(over="ignore", under="ignore"):
            return v * np.float64(10.0) ** int(rng.integers(-330, 330))
    flat = v.reshape(-1)
    for k in rng.integers(flat.size, size=int(rng.integers(1, 4))):
        flat[k] = pick(rng, HOSTILE_FLOATS)
    return v


def mutated(v, rng: np.random.Generator):
    """A hostile version of the argument value `v`."""
    if not isinstance(v, np.ndarray) or rng.random() < 0.15:
        return hostile_scalar(rng)
    kind = int(rng.integers(5))
    if kind == 0:
        return reshaped(v, rng)
    if kind == 1:
        with warnings.catch_warnings(), contextlib.suppress(ValueError, OverflowError):
            warnings.simplefilter("ignore")
            return v.astype(pick(rng, DTYPES))
        return v  # text that is not a number, already mutated
    if kind == 2:
        return pick(rng, (np.asfortranarray(v), v[::-1], v.T, np.repeat(v, 2, axis=-1)[..., ::2]))
    if kind == 3:
        return revalued(v, rng)
    return v.tolist() if rng.random() < 0.5 else [v.tolist(), "x"]


_RUN = None


def valid_call(name: str, rng: np.random.Generator) -> dict:
    global _RUN
    if name != "run_dielectric_constant":
        kwargs = VALID[name](None)
        if "dt" in kwargs and rng.random() < 0.5:
            kwargs["max_lag"] = pick(rng, HOSTILE_INTS)
        return kwargs
    if _RUN is None:
        _RUN = VALID[name](None)["run"]
    series = dict(_RUN["series"]["m"])
    run = {"summary": _RUN["summary"], "series": {"m": series}}
    kwargs = {"run": run}
    if rng.random() < 0.5:
        kwargs["temperature"] = float(pick(rng, HOSTILE_FLOATS))
    if rng.random() < 0.3:
        kwargs["series"] = hostile_scalar(rng)
    column = pick(rng, sorted(series))
    series[column] = mutated(np.asarray(series[column]), rng)
    return kwargs


def all_finite(value) -> bool:
    if isinstance(value, dict):
        return all(all_finite(v) for v in value.values())
    if isinstance(value, (float, np.floating, np.ndarray)):
        return bool(np.all(np.isfinite(value)))
    return True


#: Names of inputs other than the arguments: the fields of a run's summary.
OTHER_INPUTS = {"run_dielectric_constant": ("interactions",)}


def names_an_argument(message: str, arguments) -> bool:
    return any(message.startswith(a) and message[len(a) : len(a) + 1] in ("", "[", ":", ",", " ", ".") for a in arguments)


def test_the_guide_lists_the_analysis_functions():
    assert len(FUNCTIONS) == 9 and {"block_average", "run_dielectric_constant"} <= set(FUNCTIONS)


def test_hostile_arguments_are_refused_naming_the_argument_and_results_are_finite():
    refused, returned, failures = 0, 0, Failures()
    for case, rng in cases("analysis", CASES):
        name = pick(rng, FUNCTIONS)
        kwargs = valid_call(name, rng)
        for _ in range(int(rng.integers(1, 4))):
            arg = pick(rng, sorted(kwargs))
            if name != "run_dielectric_constant" or arg != "run":
                kwargs[arg] = mutated(kwargs[arg], rng)
        shown = f"{name}({', '.join(f'{k}={v!r:.200}' for k, v in kwargs.items())})"
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                result = getattr(quatrot, name)(**kwargs)
        except (ValueError, TypeError) as e:
            refused += 1
            inputs = (*inspect.signature(getattr(quatrot, name)).parameters, *OTHER_INPUTS.get(name, ()))
            if not names_an_argument(str(e), inputs):
                failures.add(case, f"{type(e).__name__} names no argument: {e}", shown)
        except Exception as e:  # noqa: BLE001 (the failure is the type)
            failures.add(case, f"raised {type(e).__name__}: {e}", shown)
        else:
            returned += 1
            if not all_finite(result):
                failures.add(case, f"returned a non-finite number: {result!r:.2000}", shown)
        if time.perf_counter() - start > CASE_BOUND:
            failures.add(case, f"took {time.perf_counter() - start:.1f} s", shown)
    failures.report()
    assert refused > 0 and returned > 0, "the mutations exercise both outcomes"
