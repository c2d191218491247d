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

import io
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
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


# -- files ------------------------------------------------------------------------------------
#
# A corpus of files for every reader of the package: each valid file of each format, every
# one given to every reader (each other format), cut short, grown past the reader's bound,
# spoilt in its content, and paths that are no regular file (a FIFO, /dev/zero, a folder, a
# missing file). `test_hostile.py::test_every_reader_on_every_file` runs them all.

READERS = ("load", "read_aem", "load_scene", "Body.load")
"""The package's readers of files, by name (see `read_with`)."""


@dataclass(frozen=True)
class HostileFile:
    """One file (or path) of the corpus."""

    name: str
    path: Path
    category: str
    """valid, other format, truncated, oversized, bad content, or special (no regular file)."""
    valid_for: frozenset[str] = frozenset()
    """The readers that must return a result for it (none for a hostile file)."""


def read_with(reader: str, path: Path) -> Any:
    """Calls `reader` (one of `READERS`) on `path`."""
    import dzhanibekov as dz

    calls: dict[str, Callable[[Path], Any]] = {
        "load": dz.load, "read_aem": dz.io.read_aem, "load_scene": dz.load_scene,
        "Body.load": dz.Body.load}
    return calls[reader](path)


BOX_FACES = np.array([(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
                      (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)])
"""The 12 outward triangles of the box whose vertex k is ((k >> j) & 1 for j = 0, 1, 2)."""


def box_vertices(size: tuple[float, float, float] = (1.0, 2.0, 3.0)) -> np.ndarray:
    k = np.arange(8)
    return (np.stack([(k >> j) & 1 for j in range(3)], axis=1) - 0.5) * np.asarray(size)


def ascii_stl(vertices: np.ndarray, faces: np.ndarray) -> str:
    lines = ["solid box"]
    for f in faces:
        a, b, c = vertices[f]
        n = np.cross(b - a, c - a)
        n = n / np.linalg.norm(n)
        lines += [f"facet normal {n[0]:.9g} {n[1]:.9g} {n[2]:.9g}", "outer loop"]
        lines += [f"vertex {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}" for p in (a, b, c)]
        lines += ["endloop", "endfacet"]
    return "\n".join(lines + ["endsolid box"]) + "\n"


def _aem_mutations(text: str) -> dict[str, str]:
    """Spoilt copies of a valid AEM (version 2.0, one segment) of the package's writer."""
    lines = text.splitlines()
    data = lines.index("DATA_START")
    first = lines[data + 1].split()
    second = lines[data + 2].split()

    def row(k: int, fields: list[str]) -> str:
        out = list(lines)
        out[data + 1 + k] = " ".join(fields)
        return "\n".join(out) + "\n"

    def replace(old: str, new: str) -> str:
        assert old in text, old
        return text.replace(old, new, 1)

    def drop(prefix: str) -> str:
        return "\n".join(ln for ln in lines if not ln.startswith(prefix)) + "\n"

    epoch = first[0]
    day = epoch[:10]
    return {
        "nan quaternion": row(0, [epoch, "nan", *first[2:]]),
        "inf quaternion": row(0, [epoch, "inf", *first[2:]]),
        "1e999 quaternion": row(0, [epoch, "1e999", *first[2:]]),
        "non-unit quaternion": row(0, [epoch, "0.9", "0.9", "0.9", "0.9"]),
        "zero quaternion": row(0, [epoch, "0", "0", "0", "0"]),
        "time backwards": row(1, [epoch, *second[1:]]),
        "month 13": replace(day, day[:5] + "13" + day[7:]),
        "february 30": text.replace(day, day[:5] + "02-30"),
        "day of year 366 in 2026": text.replace(day, "2026-366"),
        "hour 25": text.replace(epoch, epoch[:11] + "25" + epoch[13:], 1),
        "second 61": text.replace(epoch, epoch[:17] + "61" + epoch[19:], 1),
        "year 10000": text.replace(day, "1" + day),
        "year 9999 day 400": text.replace(day, "9999-400"),
        "year 0000": text.replace(day, "0000" + day[4:]),
        "missing DATA_START": drop("DATA_START"),
        "missing DATA_STOP": drop("DATA_STOP"),
        "missing META_STOP": drop("META_STOP"),
        "missing META_START": drop("META_START"),
        "missing CCSDS_AEM_VERS": drop("CCSDS_AEM_VERS"),
        "missing REF_FRAME_A": drop("REF_FRAME_A"),
        "version 3.0": replace("CCSDS_AEM_VERS = 2.0", "CCSDS_AEM_VERS = 3.0"),
        "euler angles": replace("ATTITUDE_TYPE = QUATERNION", "ATTITUDE_TYPE = EULER_ANGLE"),
        "a field short": row(0, first[:-1]),
        "a field too many": row(0, first + ["0.0"]),
        "not a number": row(0, [epoch, "x", *first[2:]]),
        "underscore in a number": row(0, [epoch, "1_0", *first[2:]]),
        "non-ASCII byte": replace("OBJECT_NAME = BOX", "OBJECT_NAME = B\u00d6X"),
        "keyword twice": replace("REF_FRAME_B", "REF_FRAME_A = ICRF\nREF_FRAME_B"),
        "no data lines": "\n".join(lines[: data + 1] + [ln for ln in lines[data + 1:]
                                                         if not ln[:1].isdigit()]) + "\n",
        "epochs after STOP_TIME": replace("STOP_TIME", "STOP_TIME = " + epoch + "\nCOMMENT"),
        "data after DATA_STOP": text + "garbage\n",
        "keyword without value": replace("ORIGINATOR = DZHANIBEKOV", "ORIGINATOR ="),
        "a line with no keyword": replace("OBJECT_NAME = BOX", "OBJECT_NAME BOX"),
    }


def _netcdf_mutations(kind: str, ds: Any) -> dict[str, Any]:
    """Spoilt copies of a file that `dz.save` writes (of `kind`, whose dataset is `ds`): an
    edit of the file in place (a function of the open h5py file: fast), or a whole dataset
    (for changes of shape and layout)."""
    out: dict[str, Any] = {}

    def values(name: str, f: Callable[[np.ndarray], np.ndarray]) -> Callable[[Any], None]:
        def edit(h5: Any) -> None:
            data = h5[name][...]
            if data.dtype.kind == "O":
                data = np.array([v.decode() if isinstance(v, bytes) else v for v in data.ravel()],
                                dtype=object).reshape(data.shape)
            h5[name][...] = f(data)
        return edit

    def attr(name: str, value: Any) -> Callable[[Any], None]:
        def edit(h5: Any) -> None:
            if value is None:
                del h5.attrs[name]
            else:
                h5.attrs[name] = value
        return edit

    def spoil_q(q: np.ndarray) -> np.ndarray:
        q[..., 1, 0] = np.nan
        return q

    if kind in ("Trajectory", "Batch"):
        out["NaN in q"] = values("q", spoil_q)
        out["q of norm 1.5"] = values("q", lambda q: q * 1.5)
        out["NaN in omega"] = values("omega", lambda w: np.where(w == w.flat[0], np.nan, w))
        out["time reversed"] = values("time", lambda t: t[::-1].copy())
        out["time not from 0"] = values("time", lambda t: t + 1.0)
        out["time with NaN"] = values("time", lambda t: np.where(np.arange(len(t)) == 1,
                                                                 np.nan, t))
        out["method unknown"] = attr("method", "rk5")
        out["method missing"] = attr("method", None)
        out["quaternion labels reversed"] = values("quaternion", lambda a: a[::-1].copy())
        out["q as float32"] = ds.assign(q=ds.q.astype(np.float32))
        out["q with axis dims"] = ds.drop_vars("q").assign(
            q=(ds.omega.dims, ds.omega.values.copy()))
        out["omega missing"] = ds.drop_vars("omega")
        out["an unknown variable"] = ds.assign(extra=("time", ds.time.values.copy()))
    if kind == "Trajectory":
        out["(11, 3) q"] = ds.drop_vars("q").isel(time=slice(0, 11)).assign(
            q=(("time", "axis"), np.ones((11, 3))))
        out["flip time beyond t_end"] = values("flip_times", lambda t: t + 1e6)
        out["flip times decreasing"] = values("flip_times", lambda t: t[::-1].copy())
        out["flips_located without flip_times"] = ds.drop_vars("flip_times")
        out["flips_located 2"] = attr("flips_located", 2)
        out["inertia negative"] = attr("inertia", np.array([-1.0, 2.0, 3.0]))
        out["inertia of two"] = attr("inertia", np.array([1.0, 2.0]))
        out["n_steps negative"] = attr("n_steps", -1)
        out["drift negative"] = attr("drift_energy", -1.0)
        out["drift NaN"] = attr("drift_q_norm", np.nan)
        out["dt a string"] = attr("dt", "0.1")
        out["one frame"] = ds.isel(time=slice(0, 1))
        # the run's system and what it derives (issue 20's fields)
        out["energy edited"] = values("energy", lambda e: e * (1 + 1e-6))
        out["momentum_world edited"] = values("momentum_world", lambda m: m + 1e-3)
        out["inertia not the system's"] = attr("inertia", np.array([1.0, 2.0, 3.0]))
        out["body_tensor not positive definite"] = values("body_tensor", lambda t: -t)
        out["body_tensor missing"] = ds.drop_vars("body_tensor")
        out["knots beside the body"] = ds.assign(
            knot_times=("knot", np.array([0.0])),
            knot_tensors=(("knot", "axis", "axis_"), np.eye(3)[None]))
        out["parts names a damper"] = ds.assign_attrs(parts=["damper"])
        out["drift_kept unknown"] = ds.assign_attrs(drift_kept=["energy", "spin"])
    if kind == "Batch":
        out["flips one more"] = values("flips", lambda c: c + 1)
        out["flips one fewer"] = values("flips", lambda c: c - 1)
        out["flip_times without flips"] = ds.drop_vars("flips")
        out["run numbers shuffled"] = values("run", lambda r: r[::-1].copy())
        out["inertia NaN"] = values("inertia", lambda i: i * np.nan)
        out["energy edited"] = values("energy", lambda e: e * (1 + 1e-6))
        out["body_mass negative"] = values("body_mass", lambda m: np.full_like(m, -1.0))
    if kind == "Sweep":
        out["status unknown"] = values("status", lambda st: np.full(st.shape, "maybe",
                                                                    dtype=object))
        out["flips mismatch first_flip"] = values("first_flip", lambda f: f * np.nan)
        out["tilt beyond pi"] = values("tilt", lambda t: t + 4.0)
        out["q0 NaN"] = values("q0", lambda q: q * np.nan)
        out["flips negative"] = values("flips", lambda c: c - 5)
        out["t_end missing"] = attr("t_end", None)
    out["kind unknown"] = attr("dzhanibekov_result", "Movie")
    out["kind missing"] = attr("dzhanibekov_result", None)
    return out


def _spoilt(image: bytes, mutation: Any) -> bytes:
    """The netCDF file `image` with `mutation` (see `_netcdf_mutations`) applied."""
    buffer = io.BytesIO()
    if callable(mutation):
        import h5py

        buffer.write(image)
        with h5py.File(buffer, "r+") as h5:
            mutation(h5)
    else:
        mutation.to_netcdf(buffer, engine="h5netcdf")
    return buffer.getvalue()


def file_corpus(folder: Path) -> list[HostileFile]:
    """Writes the corpus into `folder` and lists it (a few hundred files, ~2 s)."""
    import warnings

    import xarray as xr
    from PIL import Image

    import dzhanibekov as dz

    folder.mkdir(parents=True, exist_ok=True)
    files: list[HostileFile] = []

    def add(name: str, data: bytes | str, category: str, suffix: str,
            valid_for: tuple[str, ...] = ()) -> Path:
        path = folder / f"{len(files):03d}-{name.replace(' ', '-').replace('/', '_')}{suffix}"
        if isinstance(data, str):
            path.write_text(data, encoding="utf-8", newline="")
        else:
            path.write_bytes(data)
        files.append(HostileFile(name, path, category, frozenset(valid_for)))
        return path

    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=100.0, frames=41, dt=1e-2)
    batch = dz.simulate(dz.PAPER_INERTIA, [(0.01, 0.01, 1.0), (0.0, 1.0, 0.01)], t_end=100.0,
                        frames=21, dt=1e-2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sweep = dz.sweep(dz.PAPER_INERTIA, [[0.01, 0.01, 1.0], [0.0, 1e3, 1.0],
                                            [0.2, 0.0, 1.0]], t_end=100.0, dt=0.5)
    valid: dict[str, tuple[bytes, str, tuple[str, ...]]] = {}
    for kind, result in (("Trajectory", traj), ("Batch", batch), ("Sweep", sweep)):
        path = dz.save(result, folder / f"valid-{kind}.nc")
        valid[f"netCDF {kind}"] = (path.read_bytes(), ".nc", ("load",))
        path.unlink()
    for version, rates in (("2.0", False), ("1.0", True)):
        path = dz.io.write_aem(traj, folder / "valid.aem", "BOX", "2026-001A",
                               "2026-01-01T00:00:00", ref_frame_a="EME2000", rates=rates,
                               version=version)
        valid[f"AEM {version}"] = (path.read_bytes(), ".aem", ("read_aem",))
    path = dz.io.write_aem(batch, folder / "valid.aem", "BOX", "2026-001A",
                           "2026-01-01T00:00:00", ref_frame_a="EME2000")
    valid["AEM of a batch (segments)"] = (path.read_bytes(), ".aem", ("read_aem",))
    path.unlink()
    valid["scene"] = (dz.SCENES["fig3a"].to_toml().encode(), ".toml", ("load_scene",))
    valid["ASCII STL box"] = (ascii_stl(box_vertices(), BOX_FACES).encode(), ".stl",
                              ("Body.load",))
    for name, (data, suffix, readers) in valid.items():
        add(name, data, "valid", suffix, readers)

    # other formats: each reader gets every one of them
    image = io.BytesIO()
    Image.new("RGB", (4, 4)).save(image, format="PNG")
    gif = io.BytesIO()
    Image.new("P", (4, 4)).save(gif, format="GIF")
    npy = io.BytesIO()
    np.save(npy, np.arange(4.0))
    nc3 = folder / "nc3.nc"
    xr.Dataset({"a": ("x", np.arange(3.0))}).to_netcdf(nc3, engine="scipy")
    plain_nc = folder / "plain.nc"
    xr.Dataset({"a": ("x", np.arange(3.0))}).to_netcdf(plain_nc, engine="h5netcdf")
    others = {
        "PNG image": (image.getvalue(), ".png"),
        "GIF image": (gif.getvalue(), ".gif"),
        "NumPy .npy": (npy.getvalue(), ".npy"),
        "netCDF-3 file": (nc3.read_bytes(), ".nc"),
        "netCDF-4 not from save": (plain_nc.read_bytes(), ".nc"),
        "HTML page": ("<!DOCTYPE html><html><body>viewer</body></html>\n", ".html"),
        "JSON summary": ('{"scene": "fig3a", "flips": 3}\n', ".json"),
        "empty file": (b"", ".nc"),
        "random bytes": (np.random.default_rng(7).bytes(4096), ".bin"),
        "NUL bytes": (b"\0" * 1024, ".aem"),
        "UTF-16 text": ("title = 'x'\n".encode("utf-16"), ".toml"),
        "plain text": ("hello\nworld\n", ".txt"),
        "CSV table": ("t,u,v,w\n0,0.01,0.01,1\n", ".csv"),
        "ZIP archive": (b"PK\x03\x04" + b"\0" * 60, ".zip"),
    }
    nc3.unlink()
    plain_nc.unlink()
    for name, (data, suffix) in others.items():
        add(name, data, "other format", suffix)
    # each valid file under the suffix of every other reader's format
    for name, (data, _, readers) in valid.items():
        for suffix in (".nc", ".aem", ".toml", ".stl"):
            # the readers go by content; trimesh alone by the suffix
            kept = tuple(r for r in readers if r != "Body.load" or suffix == ".stl")
            add(f"{name} named {suffix}", data, "other format", suffix, kept)
    # cut short: at half, at 100 bytes, at 1 byte
    for name, (data, suffix, _) in valid.items():
        for cut in (len(data) // 2, 100, 1):
            add(f"{name} cut to {cut} bytes", data[:cut], "truncated", suffix)
    # spoilt content
    aem_text = valid["AEM 2.0"][0].decode("ascii")
    for name, text in _aem_mutations(aem_text).items():
        add(f"AEM: {name}", text.encode("utf-8"), "bad content", ".aem")
    for kind, result in (("Trajectory", traj), ("Batch", batch), ("Sweep", sweep)):
        ds = result.to_xarray()
        ds.attrs["dzhanibekov_result"] = kind
        for name, mutation in _netcdf_mutations(kind, ds).items():
            add(f"netCDF {kind}: {name}", _spoilt(valid[f"netCDF {kind}"][0], mutation),
                "bad content", ".nc")
    # grown past the readers' bounds (sparse: no disk taken)
    for suffix, size in ((".aem", dz.io.MAX_AEM_BYTES + 1), (".toml", (1 << 20) + 1),
                         (".stl", (1 << 30) + 1), (".nc", 1 << 40)):
        path = add(f"{size} bytes {suffix}", b"", "oversized", suffix)
        with open(path, "r+b") as f:
            f.truncate(size)
    # paths that are no regular file
    for suffix in (".nc", ".aem", ".toml", ".stl"):
        fifo = folder / f"fifo{suffix}"
        if hasattr(os, "mkfifo"):
            os.mkfifo(fifo)
            files.append(HostileFile(f"FIFO {suffix}", fifo, "special"))
        files.append(HostileFile(f"missing {suffix}", folder / f"missing{suffix}", "special"))
        sub = folder / f"folder{suffix}"
        sub.mkdir()
        files.append(HostileFile(f"folder {suffix}", sub, "special"))
    if os.path.exists("/dev/zero"):
        files.append(HostileFile("/dev/zero", Path("/dev/zero"), "special"))
        for suffix in (".nc", ".aem", ".toml", ".stl"):
            link = folder / f"zero{suffix}"
            os.symlink("/dev/zero", link)
            files.append(HostileFile(f"link to /dev/zero {suffix}", link, "special"))
    return files
