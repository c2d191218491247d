"""Hypothesis strategies of hostile input: values that must be refused, and valid values at the
edges of what float64 and NumPy allow, in every layout a caller can hand over.

Two kinds of strategy, kept apart so that a test knows which outcome to demand:

- *valid* strategies give values the package documents as allowed, as extreme as allowed
  (subnormals, 1e±300, signed zeros, integers, NumPy scalars) and in every memory layout that
  holds the same numbers (lists, tuples, strided, reversed, read-only, Fortran-ordered,
  big-endian, float32 or int64 when exact);
- *hostile* strategies give only values that must be refused: NaN, ±inf, wrong shapes, wrong
  dtypes (complex, object, str, bool, datetime), ragged lists, None, strings, integers too
  large for the core, values out of range.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

import numpy as np
from hypothesis import strategies as st

TINY = 5e-324
"""The smallest subnormal."""
SMALLEST_NORMAL = 2.2250738585072014e-308
LARGEST = 1.7976931348623157e308

SPECIAL_FLOATS = (0.0, -0.0, math.nan, math.inf, -math.inf, TINY, -TINY, SMALLEST_NORMAL,
                  -SMALLEST_NORMAL, 1e-300, -1e-300, 1e300, -1e300, LARGEST, -LARGEST, 1.0, -1.0)

any_float = st.one_of(st.sampled_from(SPECIAL_FLOATS), st.floats())
"""Any float64: NaN, ±inf, ±0, subnormals, the extremes."""

non_finite = st.sampled_from([math.nan, -math.nan, math.inf, -math.inf])


class Opaque:
    """An object that is nothing the package knows."""

    def __repr__(self) -> str:
        return "Opaque()"


def _gen() -> Any:
    return (x for x in (1.0, 2.0, 3.0))


JUNK = st.sampled_from([
    None, "", "1.0", "nan", b"1.0", 1j, complex(1, 0), Opaque(), {}, {"a": 1}, set(), frozenset(),
    Ellipsis, NotImplemented, object, int, slice(1), range(0), type, print,
])
"""Things that are not numbers, arrays or names."""

too_big_ints = st.sampled_from([2**64, 2**64 + 1, 10**30, 10**400, -(2**64), -(10**400)])


# -- scalars ----------------------------------------------------------------------------------

def as_number_types(x: float) -> st.SearchStrategy[Any]:
    """`x` as every real-number type the package accepts, where the type holds `x` exactly."""
    forms: list[Any] = [x, np.float64(x)]
    with np.errstate(all="ignore"):
        if float(np.float32(x)) == x or math.isnan(x):
            forms.append(np.float32(x))
    if math.isfinite(x) and x == int(x):
        forms += [int(x)]
        if abs(x) < 2**62:
            forms += [np.int64(int(x))]
        if 0 <= x < 255:
            forms += [np.uint8(int(x))]
    if math.isfinite(x) and x != 0 and abs(x) < 1e300 and abs(x) > 1e-300:
        frac = Fraction(x)
        if float(frac) == x:
            forms.append(frac)
    return st.sampled_from(forms)


def positive_floats(low: float = TINY, high: float = LARGEST) -> st.SearchStrategy[float]:
    """Positive finite floats in [low, high], extremes included, log-uniform in between."""
    specials = [v for v in (TINY, SMALLEST_NORMAL, 1e-300, 1e-150, 1e-3, 1.0, 1e150, 1e300, LARGEST)
                if low <= v <= high]
    return st.one_of(
        st.sampled_from(specials) if specials else st.nothing(),
        st.floats(min_value=low, max_value=high, allow_subnormal=low < SMALLEST_NORMAL),
        log_uniform(low, high),
    )


def log_uniform(low: float, high: float) -> st.SearchStrategy[float]:
    """Floats in [low, high], uniform in their logarithm."""
    lo, hi = math.log10(low), math.log10(high)

    def power(e: float) -> float:
        try:
            return min(max(10.0**e, low), high)
        except OverflowError:
            return high

    return st.floats(min_value=lo, max_value=hi).map(power)


def valid_positive(low: float = TINY, high: float = LARGEST) -> st.SearchStrategy[Any]:
    """A positive finite number in any accepted type."""
    return positive_floats(low, high).flatmap(as_number_types)


def hostile_real(*, positive: bool) -> st.SearchStrategy[Any]:
    """Values a real-number argument must refuse (non-positive ones too, if `positive`)."""
    bad_values = [non_finite, JUNK, st.booleans(), st.just(np.bool_(True)),
                  st.just(np.array(1.0)), st.just(np.array([1.0])), st.just([1.0]),
                  st.just(10**400), st.just(-(10**400)), st.just(Fraction(10**400)),
                  st.just(np.longdouble("1e4000") if np.finfo(np.longdouble).max > 1e4000
                          else math.inf)]
    if positive:
        bad_values.append(st.sampled_from([0.0, -0.0, -TINY, -1e-300, -1.0, -1e300, 0, -1])
                          .flatmap(as_number_types))
        bad_values.append(st.floats(max_value=0.0, allow_nan=False, allow_infinity=False))
    return st.one_of(bad_values)


def valid_int(low: int, high: int) -> st.SearchStrategy[Any]:
    """An integer in [low, high] as int or a NumPy integer (not bool)."""
    return st.integers(low, high).flatmap(
        lambda n: st.sampled_from([n, np.int64(n)] + ([np.uint32(n)] if 0 <= n < 2**32 else [])
                                  + ([np.int16(n)] if -(2**15) <= n < 2**15 else [])))


def hostile_int(minimum: int, *, huge: bool = True) -> st.SearchStrategy[Any]:
    """Values an integer argument of at least `minimum` must refuse."""
    below = st.integers(max_value=minimum - 1).flatmap(
        lambda n: st.sampled_from([n, np.int64(n)] if n > -(2**63) else [n]))
    floats = st.one_of(
        st.sampled_from([2.0, 2.5, 1e3, math.nan, math.inf]).flatmap(as_number_types)
        .filter(lambda v: not isinstance(v, (int, np.integer))),
        st.floats(),
    )
    options = [below, floats, st.booleans(), st.just(np.bool_(False)), JUNK,
               st.just("3"), st.just([3]), st.just(np.array(3)), st.just(Fraction(7, 2))]
    if huge:
        options.append(too_big_ints.filter(lambda n: n > 0))
    return st.one_of(options)


# -- arrays -----------------------------------------------------------------------------------

def layouts(values: np.ndarray) -> st.SearchStrategy[Any]:
    """`values` (float64) in every layout and type that holds exactly the same numbers."""
    values = np.asarray(values, dtype=np.float64)
    forms: list[Callable[[], Any]] = [
        lambda: values.copy(),
        lambda: values.tolist(),
        lambda: _tuples(values.tolist()),
        lambda: [np.float64(v) for v in values.ravel()] if values.ndim == 1 else values.tolist(),
        lambda: _strided(values),
        lambda: _reversed(values),
        lambda: _read_only(values),
        lambda: values.astype(">f8"),
        lambda: np.asfortranarray(values),
    ]
    finite = bool(np.isfinite(values).all())
    with np.errstate(all="ignore"):
        if np.array_equal(values.astype(np.float32).astype(np.float64), values):
            forms.append(lambda: values.astype(np.float32))
        if finite and np.array_equal(np.trunc(values), values) and (np.abs(values) < 2**53).all():
            forms.append(lambda: values.astype(np.int64))
            forms.append(lambda: _tuples(values.astype(np.int64).tolist()))
            if ((values >= 0) & (values < 256)).all():
                forms.append(lambda: values.astype(np.uint8))
    if values.size and (values == values.flat[0]).all() and values.ndim >= 1:
        forms.append(lambda: np.broadcast_to(np.float64(values.flat[0]), values.shape))
    return st.sampled_from(range(len(forms))).map(lambda k: forms[k]())


def _tuples(x: Any) -> Any:
    return tuple(_tuples(v) for v in x) if isinstance(x, list) else x


def _strided(values: np.ndarray) -> np.ndarray:
    """A view with every other element, over a buffer full of NaN in between."""
    buf = np.full(values.shape[:-1] + (2 * values.shape[-1],) if values.ndim else (2,), np.nan)
    view = buf[..., ::2] if values.ndim else buf[0:1].reshape(())
    view[...] = values
    return view


def _reversed(values: np.ndarray) -> np.ndarray:
    """A view with negative strides."""
    if values.ndim == 0:
        return values.copy()
    return values[::-1].copy()[::-1]


def _read_only(values: np.ndarray) -> np.ndarray:
    arr = values.copy()
    arr.flags.writeable = False
    return arr


def wrong_dtypes(values: np.ndarray) -> st.SearchStrategy[Any]:
    """`values` with a dtype that is not real numbers: complex, object, str, bool, datetime."""
    values = np.asarray(values, dtype=np.float64)
    forms: list[Callable[[], Any]] = [
        lambda: values.astype(complex),
        lambda: values.astype(object),
        lambda: values.astype(str),
        lambda: values.astype(bool),
        lambda: np.zeros(values.shape, dtype="datetime64[s]"),
        lambda: np.zeros(values.shape, dtype="timedelta64[s]"),
        lambda: np.zeros(values.shape, dtype=[("a", "f8")]),
        lambda: [complex(v, 1.0) for v in values.ravel()],
        lambda: [str(v) for v in values.ravel()],
        lambda: [True] * values.size,
        lambda: [None] * values.size,
    ]
    return st.sampled_from(range(len(forms))).map(lambda k: forms[k]())


def real_arrays(shape: tuple[int, ...], elements: st.SearchStrategy[float]) -> st.SearchStrategy[np.ndarray]:
    n = int(np.prod(shape))
    return st.lists(elements, min_size=n, max_size=n).map(
        lambda xs: np.array(xs, dtype=np.float64).reshape(shape))


def hostile_array(shape: Sequence[int | None], valid: st.SearchStrategy[np.ndarray],
                  *, extra: Sequence[st.SearchStrategy[Any]] = ()) -> st.SearchStrategy[Any]:
    """Values an array argument of `shape` (None: any length on that axis) must refuse: valid
    arrays spoilt by a NaN or an infinity, of the wrong shape or dtype, ragged lists, junk."""

    def spoil(arr: np.ndarray) -> st.SearchStrategy[Any]:
        if arr.size == 0:
            return st.nothing()
        return st.tuples(st.integers(0, arr.size - 1), non_finite).map(
            lambda kv: _with(arr, *kv)).flatmap(layouts)

    def reshape(arr: np.ndarray) -> st.SearchStrategy[Any]:
        n = shape[-1] or 1
        shapes: list[tuple[int, ...]] = [(), (0,), (n + 1,), (n - 1,) if n > 1 else (2,),
                                         (1, 1, n), (n, 1), (2, n + 1)]
        if len(shape) == 1:
            shapes += [(1, n), (2, n)]
        shapes = [s for s in shapes if s != tuple(arr.shape) and
                  not (len(s) == len(shape) and s[-1] == n)]
        return st.sampled_from(shapes).flatmap(
            lambda s: real_arrays(s, st.floats(-10, 10)).flatmap(layouts))

    return st.one_of(
        valid.flatmap(spoil),
        valid.flatmap(reshape),
        valid.flatmap(wrong_dtypes),
        st.just([[1.0, 2.0, 3.0], [1.0, 2.0]]),  # ragged
        st.just([1.0, [2.0], 3.0]),
        st.just("1, 2, 3"),
        st.builds(_gen),
        JUNK,
        st.sampled_from([0.0, 1.0, math.nan, 3]),
        *extra,
    )


def _with(arr: np.ndarray, k: int, value: float) -> np.ndarray:
    out = arr.copy()
    out.flat[k] = value
    return out


# -- the package's own kinds of values --------------------------------------------------------

component = st.one_of(
    st.sampled_from([0.0, -0.0, TINY, -TINY, 1e-300, 1e-150, 1e-15, 1.0, -1.0, 0.5]),
    st.floats(-1.0, 1.0),
)
"""A component of a direction, before scaling: zeros, subnormals, tiny perturbations."""


@st.composite
def inertias(draw: st.DrawFn) -> np.ndarray:
    """Principal moments the package accepts: positive, within a ratio of 1e150, as extreme
    as float64 allows; equal and nearly equal pairs (symmetric tops) and triangle-breaking
    sets among them."""
    kind = draw(st.sampled_from(["log", "symmetric", "near", "paper", "rod", "extreme"]))
    scale = draw(st.sampled_from([1.0, 1e-300, 1e-150, 1e150, 1e300, TINY * 2**60]))
    if kind == "log":
        exps = draw(st.lists(st.floats(-4, 4), min_size=3, max_size=3))
        moments = [10.0**e for e in exps]
    elif kind == "symmetric":
        a, b = draw(st.floats(0.1, 10)), draw(st.floats(0.1, 10))
        moments = draw(st.permutations([a, a, b]))
    elif kind == "near":
        a = draw(st.floats(0.5, 2))
        eps = draw(st.sampled_from([1e-15, 1e-12, 1e-8, 2.2e-16]))
        moments = draw(st.permutations([a, a * (1 + eps), draw(st.floats(0.5, 3))]))
    elif kind == "paper":
        moments = [52.0833, 27.0833, 41.6666]
    elif kind == "rod":
        moments = draw(st.permutations([1e-6, 1.0, 1.0 + 1e-6]))
    else:
        moments = draw(st.permutations([1.0, draw(st.sampled_from([1e-100, 1e100, 1e149, 1e-149])),
                                        draw(st.floats(0.5, 2))]))
    with np.errstate(all="ignore"):
        arr = np.array(moments, dtype=np.float64) * scale
    if not (np.isfinite(arr).all() and (arr > 0).all()) or arr.max() / arr.min() > 1e150:
        arr = np.array(moments, dtype=np.float64)
    return arr


@st.composite
def directions(draw: st.DrawFn, n: int) -> np.ndarray:
    """n components: random, along an axis, near an axis, or zero."""
    kind = draw(st.sampled_from(["random", "axis", "near-axis", "zero", "special"]))
    if kind == "random":
        v = draw(st.lists(st.floats(-1, 1), min_size=n, max_size=n))
    elif kind == "axis":
        v = [0.0] * n
        v[draw(st.integers(0, n - 1))] = draw(st.sampled_from([1.0, -1.0]))
    elif kind == "near-axis":
        v = draw(st.lists(st.sampled_from([1e-15, -1e-15, 1e-8, 5e-6, 0.0, TINY]),
                          min_size=n, max_size=n))
        v[draw(st.integers(0, n - 1))] = 1.0
    elif kind == "zero":
        v = [draw(st.sampled_from([0.0, -0.0])) for _ in range(n)]
    else:
        v = draw(st.lists(component, min_size=n, max_size=n))
    return np.array(v, dtype=np.float64)


def scaled(v: np.ndarray, exponent: int) -> np.ndarray:
    """`v · 2^exponent` without overflow warnings (underflow to subnormals and zero is fine)."""
    return np.array([math.ldexp(float(x), exponent) for x in v])


@st.composite
def quaternions(draw: st.DrawFn) -> np.ndarray:
    """Non-zero finite quaternions, of any norm float64 holds."""
    q = draw(directions(4))
    if not q.any():
        q = np.array([1.0, 0.0, 0.0, 0.0])
    e = draw(st.sampled_from([0, 0, 0, -1000, -500, 500, 1000, -1070]))
    out = scaled(q, e)
    return out if out.any() else q


def hostile_quaternion() -> st.SearchStrategy[Any]:
    zeros = st.sampled_from([np.zeros(4), np.array([-0.0, 0.0, -0.0, 0.0]),
                             (0, 0, 0, 0)]).flatmap(layouts)
    return hostile_array((4,), quaternions(), extra=[zeros])


def hostile_vector3(positive: bool = False, *, moments: bool = False) -> st.SearchStrategy[Any]:
    """Values a 3-vector must refuse; with `positive`, non-positive components too, and with
    `moments`, principal moments further apart than the 1e150 the core allows."""
    extra = []
    if positive:
        extra.append(st.lists(st.floats(-1e300, 0.0), min_size=1, max_size=1).map(
            lambda x: np.array([1.0, x[0], 2.0])).flatmap(layouts))
    if moments:
        extra.append(st.just(np.array([1e-200, 1.0, 1e200])).flatmap(layouts))
    valid = inertias() if positive else directions(3)
    return hostile_array((3,), valid, extra=extra)


def hostile_name(allowed: Sequence[str]) -> st.SearchStrategy[Any]:
    return st.one_of(
        st.text(max_size=12).filter(lambda s: s not in allowed),
        st.sampled_from([a.upper() for a in allowed] + [a + " " for a in allowed] + ["", "RK4"])
        .filter(lambda s: s not in allowed),
        JUNK.filter(lambda v: not isinstance(v, str)),
        st.just(list(allowed)),
        st.just(allowed[0].encode()),
        st.integers(),
    )
