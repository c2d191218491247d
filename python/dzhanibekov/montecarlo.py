"""Monte Carlo studies: will it tumble?

:func:`monte_carlo` draws `n` samples of a system and its start — fixed values, callables
``rng -> value`` (dispersions such as :class:`~dzhanibekov.InertiaDispersion`) or scipy.stats
distributions — runs each in the package's batch paths (:func:`~dzhanibekov.sweep` when one
number per run is asked, :func:`~dzhanibekov.simulate` batches when frames are) and returns a
:class:`MonteCarlo`: the outcomes, the probability with a confidence interval, the inputs
drawn, an ``xarray.Dataset``, and :meth:`MonteCarlo.rerun` of any sample.

**Seeding.** Sample ``k`` draws from its own generator,
``numpy.random.Generator(PCG64(SeedSequence(seed).spawn(n)[k]))`` — built directly as
``SeedSequence(seed, spawn_key=(k,))``, the same child — taking the system, then ``omega0``,
then ``q0``, in that order. So sample ``k`` is the same whatever `n`, the threads, the chunks
or the cluster, and ``study.rerun(k)`` runs it again bit for bit.

**Intervals.** Wilson's score interval (Wilson 1927) by default, or the Clopper–Pearson
interval (Clopper & Pearson 1934, from the beta distribution: at least the level asked,
conservative); see :func:`binomial_interval`.

**Rare events.** With ``runs < n`` the study draws all `n` samples (cheap: no runs), measures
each one's distance to the separatrix by the closed form (:func:`separatrix_distance`), and
runs only `runs` of them: the ``runs // 2`` nearest to the separatrix (every one of them), and
the rest drawn at random among the others. The estimate weights each stratum by its share of
the `n` draws — unbiased, since which samples run depends on their inputs only, never on an
outcome — and its interval is the binomial one at the effective sample size of its variance
(Korn & Graubard 1998). Where the event happens only near the separatrix, the study has the
interval of a plain study of `n` runs for the cost of `runs`.

References
----------
E. B. Wilson, "Probable inference, the law of succession, and statistical inference", JASA 22
(1927) 209–212. C. J. Clopper, E. S. Pearson, "The use of confidence or fiducial limits
illustrated in the case of the binomial", Biometrika 26 (1934) 404–413. W. G. Cochran,
*Sampling Techniques*, 3rd ed. (1977), §12.2 (double sampling for stratification).
E. L. Korn, B. I. Graubard, "Confidence intervals for proportions with small expected number
of positive counts estimated from survey data", Survey Methodology 24 (1998) 193–201.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from tqdm.auto import tqdm

from . import _core, _tables
from ._args import as_array, as_float, as_int, check_size
from .body import Body, principal_body
from .damper import Damper, flat_spin_time
from .deployment import Deployment
from .ensemble import DEFAULT_BLOCK, Batch, DeploymentSweep, Sweep, sweep
from .errors import DzhanibekovError
from .lvlh import lvlh_angles, nadir_angles
from .methods import DEFAULT_MAX_STEPS, DEFAULT_METHOD, METHODS, check_method
from .options import NAMES, RunKeywords, RunOptions, merged
from .parts import params_of
from .orbit import GravityGradient
from .results import Trajectory
from .rotations import quaternions_of
from .simulate import simulate
from .system import System

if TYPE_CHECKING:
    from typing_extensions import Unpack

__all__ = ["monte_carlo", "MonteCarlo", "StudyError", "binomial_interval",
           "separatrix_distance", "sample_rng", "ASKS", "INTERVALS", "DEFAULT_LEVEL", "PILOT",
           "KEEP_INPUTS"]

ASKS = ("tumbles", "flat_spin", "flips", "lvlh_angle", "leaves_nadir")
"""The questions a study asks by name (any other is a callable ``traj -> value``)."""

_YES_OR_NO = ("tumbles", "flat_spin", "leaves_nadir")
_IN_ORBIT = ("lvlh_angle", "leaves_nadir")
"""The asks of a system in the gravity gradient (its orbit defines the frame they measure from)."""

INTERVALS = ("wilson", "clopper-pearson")
"""The confidence intervals on offer."""

DEFAULT_LEVEL = 0.95
"""The confidence level of a study's interval unless told otherwise."""

PILOT = 16
"""Samples ``0 … PILOT − 1`` plan a fixed-step method's step when ``dt=None`` (drawn whatever
`n` is, so that the step depends on the seed only)."""

KEEP_INPUTS = 1_000_000
"""A study of at most this many samples keeps every sample's inputs by default (about 200
bytes each); a larger one keeps the outcomes only, and draws a sample's inputs again when
asked (:meth:`MonteCarlo.inputs_of`)."""

_PROGRESS_DELAY = 1.0
"""Seconds before the progress bar shows (``progress=None``): quick studies show none."""

_SELECTION_KEY = 2**64 - 1
"""The spawn key of the stream that picks which far samples run (a rare-event study): no
sample's key, since samples are numbered below 2**63."""


# -- intervals ---------------------------------------------------------------------------------


def binomial_interval(successes: Any, n: Any, level: float = DEFAULT_LEVEL,
                      method: str = "wilson") -> tuple[Any, Any]:
    """A confidence interval for a probability from `successes` in `n` trials.

    ``"wilson"``: Wilson's score interval, the set of ``p`` whose score test does not reject,
    ``(x + z²/2 ± z √(x (n − x) / n + z²/4)) / (n + z²)`` with ``z`` the normal quantile of
    ``(1 + level) / 2``; its coverage stays near the level even for a few successes.
    ``"clopper-pearson"``: the beta quantiles ``B(α/2; x, n − x + 1)`` and
    ``B(1 − α/2; x + 1, n − x)``, ``α = 1 − level`` (0 and 1 at ``x = 0`` and ``x = n``),
    which cover at least the level for every ``p``: wider, conservative.

    Counts may be non-integer (an effective number of successes in an effective number of
    trials, as a weighted study gives them).

    Parameters
    ----------
    successes, n : float or array_like
        Successes ``0 ≤ x ≤ n`` and trials ``n > 0``, broadcast together.
    level : float
        The confidence level, in (0, 1).
    method : {"wilson", "clopper-pearson"}

    Returns
    -------
    (lower, upper) : floats or ndarrays

    Examples
    --------
    >>> lo, hi = binomial_interval(30, 100)
    >>> round(lo, 4), round(hi, 4)
    (0.2189, 0.3958)
    >>> lo, hi = binomial_interval(0, 100, method="clopper-pearson")
    >>> float(lo), round(float(hi), 4)
    (0.0, 0.0362)
    """
    level = _level(level)
    method = _interval_method(method)
    x = np.asarray(successes, dtype=np.float64)
    m = np.asarray(n, dtype=np.float64)
    if not (np.isfinite(x).all() and np.isfinite(m).all()):
        raise ValueError("`successes` and `n` must be finite")
    if (m <= 0).any() or (x < 0).any() or (x > m * (1 + 1e-12)).any():
        raise ValueError("`successes` and `n` must have 0 <= successes <= n and n > 0")
    x = np.minimum(x, m)
    alpha = 1.0 - level
    if method == "wilson":
        from scipy.stats import norm  # type: ignore[import-untyped, unused-ignore]

        z = float(norm.ppf(1.0 - alpha / 2))
        centre = (x + z * z / 2) / (m + z * z)
        half = z / (m + z * z) * np.sqrt(x * (m - x) / m + z * z / 4)
        lower, upper = np.clip(centre - half, 0.0, 1.0), np.clip(centre + half, 0.0, 1.0)
    else:
        from scipy.stats import beta

        with np.errstate(invalid="ignore"):
            lower = np.where(x > 0, beta.ppf(alpha / 2, np.maximum(x, 1e-300), m - x + 1), 0.0)
            upper = np.where(x < m, beta.ppf(1 - alpha / 2, x + 1, np.maximum(m - x, 1e-300)),
                             1.0)
    if np.ndim(lower) == 0:
        return float(lower), float(upper)
    return lower, upper


def _level(level: Any) -> float:
    value = as_float("level", level)
    if not 0 < value < 1:
        raise ValueError(f"`level` must lie in (0, 1), got {value!r}")
    return value


def _interval_method(method: Any) -> str:
    if not isinstance(method, str) or method.lower() not in INTERVALS:
        raise ValueError(f"`interval` must be one of {INTERVALS}, got {method!r}")
    return method.lower()


# -- the closed-form distance to the separatrix -------------------------------------------------


def separatrix_distance(inertia: Any, omega: Any) -> np.ndarray:
    """How far free motions are from the separatrix: ``(D − I_mid) / (I_max − I_min)`` with
    ``D = L² / 2E``.

    ``D`` is constant along the exact free motion and lies between the least and the largest
    principal moment; the separatrix, the motion through the intermediate axis, is
    ``D = I_mid``. The distance is 0 there, positive for motions about the axis of the
    largest moment (up to ``(I_max − I_mid) / (I_max − I_min)`` for spin about it), negative
    about the smallest (down to ``−(I_mid − I_min) / (I_max − I_min)``): so it also nears 0 as
    the intermediate moment nears another one, where the growth rate of a wobble vanishes.
    ``inf`` for a body at rest or with three equal moments (nothing ever flips).

    Parameters
    ----------
    inertia : array_like, shape (..., 3)
        Principal moments, positive.
    omega : array_like, shape (..., 3)
        Body rates in those principal axes.

    Returns
    -------
    ndarray, shape (...)

    Examples
    --------
    >>> separatrix_distance((1.0, 2.0, 4.0), [(0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)])
    array([ 0.66666667, -0.33333333,  0.        ])
    """
    i = np.asarray(inertia, dtype=np.float64)
    w = np.asarray(omega, dtype=np.float64)
    i, w = np.broadcast_arrays(i, w)
    order = np.argsort(i, axis=-1, kind="stable")
    i = np.take_along_axis(i, order, axis=-1)
    w = np.take_along_axis(w, order, axis=-1)
    # in units of the largest moment and rate: no square over- or underflows
    top = np.max(i, axis=-1, keepdims=True)
    big = np.max(np.abs(w), axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        i = i / top
        w = np.where(big > 0, w / big, 0.0)
        d = (i * i * w * w).sum(axis=-1) / (i * w * w).sum(axis=-1)
        out: np.ndarray = (d - i[..., 1]) / (i[..., 2] - i[..., 0])
    return np.where(np.isfinite(out), out, np.inf)


# -- seeding ------------------------------------------------------------------------------------


def sample_rng(seed: Any, k: int) -> np.random.Generator:
    """The generator of sample `k` of a study with `seed`: the `k`-th child of
    ``SeedSequence(seed)``, as ``SeedSequence(seed).spawn(n)[k]`` gives it for any ``n > k``.

    Examples
    --------
    >>> import numpy as np
    >>> a = sample_rng(2026, 7).random()
    >>> b = np.random.default_rng(np.random.SeedSequence(2026).spawn(10)[7]).random()
    >>> a == b
    True
    """
    root = _seed_sequence(seed)
    return _generator(root.entropy, tuple(root.spawn_key), as_int("k", k, minimum=0))


_SEED_KINDS = ("`seed` must be a non-negative integer, a sequence of them (list, tuple, range "
               "or a 1-D integer array), a numpy.random.SeedSequence or None")


def _seed_sequence(seed: Any) -> np.random.SeedSequence:
    """The root of a study's generators from `seed` (see :func:`monte_carlo`): only what the
    documentation names is taken — a string, bytes or a dict would be read by NumPy as a
    sequence of codes or keys — and a sequence becomes a list of Python ints, which
    :meth:`MonteCarlo.to_xarray` writes and :meth:`MonteCarlo.from_xarray` reads back."""
    if isinstance(seed, np.random.SeedSequence):
        return np.random.SeedSequence(_entropy(seed.entropy, "seed.entropy"),
                                      spawn_key=tuple(int(k) for k in seed.spawn_key))
    if seed is None:
        return np.random.SeedSequence()
    return np.random.SeedSequence(_entropy(seed, "seed"))


def _entropy(seed: Any, name: str) -> int | list[int]:
    def one(value: Any, where: str) -> int:
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
            raise TypeError(f"{_SEED_KINDS}, got {where} {value!r} ({type(value).__name__})")
        if int(value) < 0:
            raise ValueError(f"`{name}` must be non-negative, got {where} {int(value)}")
        return int(value)

    if isinstance(seed, numbers.Integral) and not isinstance(seed, (bool, np.bool_)):
        return one(seed, name)
    if isinstance(seed, np.ndarray):
        if seed.ndim != 1 or seed.dtype.kind not in "iu":
            raise TypeError(f"{_SEED_KINDS}, got an array of shape {seed.shape} and dtype "
                            f"{seed.dtype}")
    elif isinstance(seed, (str, bytes, bytearray, memoryview)) or not isinstance(
            seed, (list, tuple, range)):
        raise TypeError(f"{_SEED_KINDS}, got {type(seed).__name__} {seed!r:.60}")
    values = [one(v, f"{name}[{k}] =") for k, v in enumerate(seed)]
    if not values:
        raise ValueError(f"`{name}` must hold at least one integer, got an empty sequence")
    return values


def entropy_text(entropy: Any) -> str:
    """A seed's entropy as a file holds it: ``"123"``, or ``"[1, 2]"`` for a sequence."""
    if isinstance(entropy, numbers.Integral):
        return str(int(entropy))
    return "[" + ", ".join(str(int(v)) for v in entropy) + "]"


def entropy_of_text(text: str) -> int | list[int]:
    """The entropy :func:`entropy_text` wrote.

    Raises
    ------
    ValueError
        Text it never writes.

    Examples
    --------
    >>> entropy_of_text("[1, 2]"), entropy_of_text("123")
    ([1, 2], 123)
    """
    inner = text[1:-1] if text.startswith("[") and text.endswith("]") else None
    parts = (inner.split(",") if inner.strip() else []) if inner is not None else [text]
    if not parts or not all(re.fullmatch(r"\s*[0-9]+\s*", part) for part in parts):
        raise ValueError(f"must be a non-negative integer or a list of them, as "
                         f"'123' or '[1, 2]', got {text!r:.80}")
    values = [int(part) for part in parts]
    return values if inner is not None else values[0]


def spawn_key_of_text(text: str) -> tuple[int, ...]:
    """The spawn key a file holds: non-negative integers joined by commas (or nothing)."""
    if text == "":
        return ()
    if not all(re.fullmatch(r"[0-9]+", part) for part in text.split(",")):
        raise ValueError(f"must be non-negative integers joined by commas, got {text!r:.80}")
    return tuple(int(part) for part in text.split(","))


def _generator(entropy: Any, spawn_key: tuple[int, ...], k: int) -> np.random.Generator:
    return np.random.Generator(np.random.PCG64(
        np.random.SeedSequence(entropy, spawn_key=spawn_key + (k,))))


# -- errors -------------------------------------------------------------------------------------


class StudyError(DzhanibekovError):
    """A sample of a study failed: its dispersion or distribution gave a value the run
    cannot take, its run did not finish, or the `ask` callable raised.

    Attributes
    ----------
    sample : int
        The index of the sample that failed (also ``row``, as the core's errors name a run).
    samples : ndarray of int64
        The samples completed before it (for a plain study, ``0 … sample − 1``).
    outcomes : ndarray
        Their outcomes.
    study : MonteCarlo or None
        The completed samples as a study (its estimate and interval are those of the
        samples that ran); None for a rare-event study, whose estimate needs all its strata.
    """

    def __init__(self, message: str, row: int | None = None,
                 index: tuple[int, ...] | None = None) -> None:
        super().__init__(message, row, index)
        self.samples: np.ndarray = np.empty(0, dtype=np.int64)
        self.outcomes: np.ndarray = np.empty(0)
        self.study: MonteCarlo | None = None

    @property
    def sample(self) -> int | None:
        return self.row

    def __str__(self) -> str:
        return self.message if self.row is None else f"sample {self.row}: {self.message}"


# -- what a study runs --------------------------------------------------------------------------


class _Settings(NamedTuple):
    """What every run of a study shares."""

    t_end: float
    frames: int
    dt: float | None
    method: str
    rtol: float | None
    atol: float | None
    threads: int | None
    max_steps: int = DEFAULT_MAX_STEPS


@dataclass(frozen=True)
class _Spec:
    """Everything a chunk of a study needs, on this machine or a Dask worker."""

    system: Any
    omega0: Any
    q0: Any
    ask: str | Callable[[Trajectory], Any]
    kind: str
    entropy: Any
    spawn_key: tuple[int, ...]
    settings: _Settings
    keep_inputs: bool
    knots: int = 0
    """A deployment's number of knots (sample 0's: every sample must have as many)."""


@dataclass
class _Rows:
    """Drawn samples, ready for the run paths."""

    kind: str
    samples: np.ndarray
    moments: np.ndarray
    """(m, 3): principal moments (a deployment's: of the deployed body, ascending)."""
    bodies: list[Body | None]
    """Each sample's Body when it is not in principal axes (else None: its moments say it)."""
    deployments: list[Deployment]
    dampers: list[Damper]
    systems: list[System]
    """Each sample's system, for a study of systems with any parts (kind ``"system"``)."""
    omega: np.ndarray
    q: np.ndarray
    inputs: dict[str, np.ndarray]

    def __len__(self) -> int:
        return len(self.samples)

    def take(self, rows: slice) -> _Rows:
        def part(v: Any) -> Any:
            return v[rows]
        return _Rows(self.kind, part(self.samples), part(self.moments), part(self.bodies),
                     part(self.deployments), part(self.dampers), part(self.systems),
                     part(self.omega), part(self.q),
                     {k: part(v) for k, v in self.inputs.items()})

    def body_rows(self) -> Any:
        """The bodies as the run paths take them: moments (m, 3) when every sample is in its
        principal axes, else a list of Bodies."""
        # three rows of moments would read as one body's tensor: Bodies say what they are
        if all(b is None for b in self.bodies) and len(self.moments) != 3:
            return self.moments
        return self.bodies_of()

    def bodies_of(self) -> list[Body]:
        """Each sample's Body."""
        return [principal_body(m) if b is None else b for b, m in zip(self.bodies, self.moments)]


def _run(rows: _Rows, settings: _Settings, *, keep: str) -> Any:
    """Every call this module makes into the package's run paths (one place to change when
    they change): `rows` run with `settings`, keeping

    - ``"summary"``: one number per run, no frames (:func:`sweep`: a :class:`Sweep` of free
      bodies, a :class:`DeploymentSweep` of deployments);
    - ``"frames"``: a :class:`Batch` (:func:`simulate` of all rows at once);
    - ``"single"``: the first row's :class:`Trajectory` (:func:`simulate` of it alone).
    """
    s = settings
    options: dict[str, Any] = dict(t_end=s.t_end, frames=s.frames, dt=s.dt, method=s.method,
                                   rtol=s.rtol, atol=s.atol, max_steps=s.max_steps)
    system: Any
    if rows.kind == "deployment":
        system = rows.deployments
    elif rows.kind == "damper":
        system = [System(body, parts=[damper]) for body, damper in
                  zip(rows.bodies_of(), rows.dampers)]
    elif rows.kind == "system":
        system = rows.systems
    else:
        system = rows.body_rows()
    if keep == "single":
        first = system[0]
        if not isinstance(first, (System, Body, Deployment)):
            first = principal_body(first)
        return simulate(first, rows.omega[0], rows.q[0], **options)
    if keep == "summary":
        return sweep(system, rows.omega, rows.q, block=max(len(rows), 1), progress=False,
                     threads=s.threads, **options)
    return simulate(system, rows.omega, rows.q, progress=False, threads=s.threads, **options)


_KINDS: dict[tuple[str, ...], str] = {("free",): "free", ("deployment",): "deployment",
                                      ("damper",): "damper"}
"""A study's kinds of system, by the registry's kinds of a :class:`System`; any other
constant body with parts (wheels, torques, several parts, the parts of ``dz.MODELS``) is a
study of kind ``"system"``."""

STUDY_KINDS = (*_KINDS.values(), "system")
"""The kinds of system a study runs (``MonteCarlo.kind``)."""


def _kind(value: Any) -> str:
    """What kind of system a drawn (or given) value is: "free", "deployment", "damper" or
    "system" (a constant body with any other parts)."""
    if isinstance(value, Deployment):
        return "deployment"
    if isinstance(value, System):
        kind = _KINDS.get(value.kinds)
        if kind is None:
            if "deployment" in value.kinds:
                raise ValueError(f"`system` must be a body with parts, a deployment or a body, "
                                 f"got a deployment with parts ({value.kinds})")
            return "system"
        return kind
    if isinstance(value, tuple) and len(value) == 2 and isinstance(value[1], Damper):
        raise TypeError("`system` gave a (body, dz.Damper) pair: a body with a damper is "
                        "dz.System(body, parts=[damper])")
    return "free"


def _is_random(value: Any) -> bool:
    """Whether an input is drawn per sample: a distribution (``.rvs``) or a callable."""
    if isinstance(value, (System, Body, Deployment)):
        return False
    return hasattr(value, "rvs") or callable(value)


def _draw(value: Any, rng: np.random.Generator) -> Any:
    if hasattr(value, "rvs"):
        return value.rvs(random_state=rng)
    return value(rng)


def _vector(name: str, value: Any, width: int) -> np.ndarray:
    if name == "q0":
        value = quaternions_of(value)
    arr = as_array(name, value, f"({width},)", last=width, ndim=(1,))
    if name == "q0" and not arr.any():
        raise ValueError("`q0` must be a non-zero quaternion (Q, U, V, W), got (0, 0, 0, 0)")
    return arr


def _moments_of(value: Any) -> np.ndarray:
    """Three principal moments as given (checked, with the others of a chunk, by
    `_first_unphysical`)."""
    try:
        arr = np.asarray(value)
    except Exception as exc:  # ragged nesting and the like
        raise TypeError(f"`system` must give a dz.Body, principal moments, a dz.Deployment "
                        f"or a dz.System: {exc}") from None
    if arr.shape == (3, 3):
        raise ValueError("`system` gave a 3 × 3 array: for a tensor, return "
                         "dz.Body.from_tensor(tensor)")
    if arr.dtype.kind not in "iuf" or arr.shape != (3,):
        raise TypeError(f"`system` must give a dz.Body, principal moments (3,), a "
                        f"dz.Deployment or a dz.System, got {type(value).__name__}"
                        f" of shape {arr.shape} and dtype {arr.dtype}")
    return arr.astype(np.float64)


def _first_unphysical(moments: np.ndarray) -> tuple[int, str] | None:
    """The first row of moments (m, 3) that no body has, and why: not positive and finite,
    further apart than the core's ratio, or breaking the triangle inequality."""
    a, b, c = moments.T
    with np.errstate(invalid="ignore", over="ignore"):
        largest = np.maximum(np.maximum(a, b), c)
        least = np.minimum(np.minimum(a, b), c)
        total = a + b + c
        checks = (
            (~((least > 0) & np.isfinite(largest)), "moments that are not all positive and "
                                                    "finite"),
            (~(largest <= _core.MAX_MOMENT_RATIO * least),
             f"moments further apart than the core's ratio {_core.MAX_MOMENT_RATIO:.0e}"),
            (2 * largest > total + _core.TRIANGLE_SLACK * total,
             "moments no body has (one larger than the other two together: the triangle "
             "inequality breaks)"),
        )
    first: tuple[int, str] | None = None
    for bad, why in checks:
        hits = np.flatnonzero(bad)
        if hits.size and (first is None or hits[0] < first[0]):
            first = (int(hits[0]), f"`system` gave {why}: {moments[hits[0]].tolist()}")
    return first


class _Drawn(NamedTuple):
    kind: str
    moments: np.ndarray
    tensor: np.ndarray | None
    """The tensor in the body's own axes, if they are not its principal axes."""
    axes: np.ndarray | None
    """Its principal axes (columns, a proper rotation), if they are not the body's own."""
    body: Body | None
    deployment: Deployment | None
    damper: Damper | None
    omega_principal: np.ndarray
    """The rates in the principal axes of the body that decides (the deployed one, as if
    deployed at once), for the separatrix distance."""
    system: System | None = None
    """The whole system, for a study of kind "system"."""


def _system(value: Any, omega: np.ndarray, t_end: float) -> _Drawn:
    """A drawn system, with what the study records of it (its moments checked later, a
    chunk at once)."""
    kind = _kind(value)
    damper: Damper | None = None
    if kind == "system":
        whole: System = value
        body = whole.body
        assert isinstance(body, Body)
        moments = np.array(body.inertia)
        if body.is_principal:
            return _Drawn(kind, moments, None, None, None, None, None, omega, whole)
        axes = body.principal_axes
        return _Drawn(kind, moments, body.tensor, axes, body, None, None, axes.T @ omega, whole)
    if isinstance(value, System):
        if kind == "damper":  # a study's systems are of one kind: the damper is its one part
            damper = next(p for p in value.parts if isinstance(p, Damper))
        value = value.body
    if kind == "deployment":
        d: Deployment = value
        if d.times[-1] > t_end:
            raise ValueError(f"the deployment's last knot, at {d.times[-1]:g}, is after "
                             f"`t_end` {t_end:g}: the verdict is that of the free motion after "
                             "it, so `t_end` must reach it")
        # its knots' moments, its deployed axes and rates: a chunk's at once (_deployed)
        return _Drawn(kind, np.full(3, np.nan), d.tensors[-1], None, None, d, None, omega)
    if isinstance(value, Body):
        moments = np.array(value.inertia)
        if value.is_principal:
            return _Drawn(kind, moments, None, None, None, None, damper, omega)
        axes = value.principal_axes
        return _Drawn(kind, moments, value.tensor, axes, value, None, damper, axes.T @ omega)
    return _Drawn(kind, _moments_of(value), None, None, None, None, damper, omega)


def _deployed(drawn: list[_Drawn], samples: np.ndarray) -> tuple[list[_Drawn], _Failure | None]:
    """A chunk's deployments, checked and measured at once (one sample at a time made a study
    of deployments several times slower than the sweep of the same deployments): every knot's
    moments a body has, up to the first that does not; the deployed body's moments and axes
    (a proper rotation); the rates it has once deployed, as if deployed at once (``L = I_0 ω``
    kept in the body), in those axes."""
    knots = np.array([d.deployment.tensors for d in drawn])  # type: ignore[union-attr]
    m, k = knots.shape[:2]
    bad = _first_unphysical(np.linalg.eigvalsh(knots).reshape(m * k, 3))
    failure = None
    if bad is not None:
        i, j = divmod(bad[0], k)
        failure = _Failure(int(samples[i]), f"`system` failed: ValueError: knot {j}: {bad[1]}",
                           None)
        drawn, knots, m = drawn[:i], knots[:i], i
    if not m:
        return drawn, failure
    moments, axes = np.linalg.eigh(knots[:, -1])
    axes[np.linalg.det(axes) < 0, :, 0] *= -1.0
    omega = np.array([d.omega_principal for d in drawn])
    after = np.linalg.solve(knots[:, -1], (knots[:, 0] @ omega[:, :, None]))[:, :, 0]
    principal = np.einsum("mji,mj->mi", axes, after)  # Aᵀ · after
    return [d._replace(moments=moments[i], axes=axes[i], omega_principal=principal[i])
            for i, d in enumerate(drawn)], failure


class _Failure(NamedTuple):
    sample: int
    message: str
    cause: BaseException | None


class _Chunk(NamedTuple):
    """What a chunk returns: its samples' outcomes (or separatrix distances) and inputs, and
    the failure that stopped it, if one did (the samples before it are kept)."""

    samples: np.ndarray
    values: np.ndarray
    inputs: dict[str, np.ndarray]
    failure: _Failure | None


def _draw_rows(spec: _Spec, samples: np.ndarray) -> tuple[_Rows, _Failure | None]:
    """Draws `samples` (in order), stopping at the first that fails."""
    random_system = _is_random(spec.system)
    fixed_omega = None if _is_random(spec.omega0) else _vector("omega0", spec.omega0, 3)
    fixed_q = None if _is_random(spec.q0) else _vector("q0", spec.q0, 4)
    drawn: list[_Drawn] = []
    omegas, qs = [], []
    failure = None
    t_end = spec.settings.t_end
    for k in samples.tolist():
        stage = "system"
        try:
            rng = _generator(spec.entropy, spec.spawn_key, k)
            value = _draw(spec.system, rng) if random_system else spec.system
            stage = "omega0"
            omega = _vector("omega0", _draw(spec.omega0, rng), 3) if fixed_omega is None \
                else fixed_omega
            stage = "q0"
            q = _vector("q0", _draw(spec.q0, rng), 4) if fixed_q is None else fixed_q
            stage = "system"
            record = _system(value, omega, t_end)
            if record.kind != spec.kind:
                raise TypeError(f"`system` gave a {_KIND_NAMES[record.kind]} where sample 0 "
                                f"gave a {_KIND_NAMES[spec.kind]}: a study runs one kind")
            if record.system is not None and drawn and drawn[0].system is not None and \
                    record.system.kinds != drawn[0].system.kinds:
                raise TypeError(f"`system` gave a system of {record.system.kinds} where the "
                                f"chunk's first gave {drawn[0].system.kinds}: a study's systems "
                                "have the same kinds of parts")
            if record.deployment is not None and len(record.deployment.times) != spec.knots:
                raise ValueError(f"`system` gave a deployment of {len(record.deployment.times)} "
                                 f"knots where sample 0 gave {spec.knots}: a study's "
                                 "deployments have as many knots")
        except Exception as exc:  # a user's callable may raise anything: say which sample
            failure = _Failure(k, f"`{stage}` failed: {type(exc).__name__}: {exc}", exc)
            break
        drawn.append(record)
        omegas.append(omega)
        qs.append(q)
    if spec.kind == "deployment" and drawn:
        drawn, knot_failure = _deployed(drawn, samples)
        if knot_failure is not None:
            failure = knot_failure
            omegas, qs = omegas[:len(drawn)], qs[:len(drawn)]
    moments = np.array([d.moments for d in drawn]).reshape(len(drawn), 3)
    bad = _first_unphysical(moments)
    if bad is not None:
        failure = _Failure(int(samples[bad[0]]), bad[1], None)
        drawn, moments = drawn[:bad[0]], moments[:bad[0]]
        omegas, qs = omegas[:bad[0]], qs[:bad[0]]
    done = samples[:len(drawn)]
    m = len(drawn)
    omega_rows = np.array(omegas).reshape(m, 3)
    q_rows = np.array(qs).reshape(m, 4)
    principal = np.array([d.omega_principal for d in drawn]).reshape(m, 3)
    inputs: dict[str, np.ndarray] = {
        "inertia": moments,
        "tensor": _tensors(moments, [d.tensor for d in drawn]),
        "axes": _axes(m, [d.axes for d in drawn]),
        "omega0": omega_rows,
        "q0": q_rows,
        "separatrix": separatrix_distance(moments, principal),
    }
    if spec.kind == "deployment":
        inputs["knot_times"] = np.array([d.deployment.times for d in drawn])  # type: ignore[union-attr]
        inputs["knot_tensors"] = np.array([d.deployment.tensors for d in drawn])  # type: ignore[union-attr]
        if m == 0:
            inputs["knot_times"] = inputs["knot_times"].reshape(0, 0)
            inputs["knot_tensors"] = inputs["knot_tensors"].reshape(0, 0, 3, 3)
    if spec.kind == "damper":
        inputs["damper_inertia"] = np.array([d.damper.inertia for d in drawn])  # type: ignore[union-attr]
        inputs["damping"] = np.array([d.damper.damping for d in drawn])  # type: ignore[union-attr]
        # the sphere's start: its own, or co-rotating with the body (Damper's sigma0=None)
        inputs["damper_sigma0"] = np.array(
            [w if d.damper.sigma0 is None else d.damper.sigma0  # type: ignore[union-attr]
             for d, w in zip(drawn, omega_rows)], dtype=np.float64).reshape(m, 3)
    if spec.kind == "system":
        inputs.update(_part_inputs([d.system for d in drawn if d.system is not None]))
    rows = _Rows(spec.kind, done, moments, [d.body for d in drawn],
                 [d.deployment for d in drawn if d.deployment is not None],
                 [d.damper for d in drawn if d.damper is not None],
                 [d.system for d in drawn if d.system is not None], omega_rows, q_rows, inputs)
    return rows, failure


def _part_inputs(systems: list[System]) -> dict[str, np.ndarray]:
    """Every number parameter of every part of each system, by ``model_j.name`` (``j``
    counting the parts of that model in ``parts + torques`` order: ``hinge_0.damping``); NaN
    for an optional one left out. A chunk's systems have the same parts (checked as drawn):
    what a :class:`~dzhanibekov.PartDispersion`, or any callable, drew is recorded."""
    if not systems:
        return {}
    places: list[tuple[str, int, str]] = []
    seen: dict[str, int] = {}
    for k, part in enumerate((*systems[0].parts, *systems[0].torques)):
        j = seen[part.model] = seen.get(part.model, -1) + 1
        places += [(f"{part.model}_{j}.{p.name}", k, p.name)
                   for p in params_of(part.model) if p.kind == "scalar"]
    every = [(*s.parts, *s.torques) for s in systems]
    return {name: np.array([math.nan if (v := getattr(parts[k], param)) is None else float(v)
                            for parts in every], dtype=np.float64)
            for name, k, param in places}


def _is_part_input(name: str) -> bool:
    """Whether an input is a part's parameter (``model_j.name``, see :func:`_part_inputs`)."""
    return "." in name


def _axes(m: int, given: list[np.ndarray | None]) -> np.ndarray:
    """The principal axes (m, 3, 3): the identity, or as given."""
    axes = np.zeros((m, 3, 3))
    axes[:, [0, 1, 2], [0, 1, 2]] = 1.0
    for i, turn in enumerate(given):
        if turn is not None:
            axes[i] = turn
    return axes


def _tensors(moments: np.ndarray, given: list[np.ndarray | None]) -> np.ndarray:
    """The tensors (m, 3, 3): diagonal of the moments, or as given."""
    tensors = np.zeros((len(moments), 3, 3))
    tensors[:, [0, 1, 2], [0, 1, 2]] = moments
    for i, tensor in enumerate(given):
        if tensor is not None:
            tensors[i] = tensor
    return tensors


_KIND_NAMES = {"free": "body", "deployment": "deployment", "damper": "damped body",
               "system": "body with parts"}


def _chunk(spec: _Spec, samples: np.ndarray, mode: str) -> _Chunk:
    """Draws and (in mode "run") runs `samples`: their outcomes and inputs; in mode "score",
    only their distances to the separatrix. A failure stops the chunk at its sample, with the
    samples before it kept (run again if their call failed with it). Runs anywhere: it is
    also a Dask task."""
    samples = np.asarray(samples, dtype=np.int64)
    rows, failure = _draw_rows(spec, samples)
    if mode == "score":
        return _Chunk(rows.samples, rows.inputs["separatrix"], {}, failure)
    values, inputs, run_failure = _outcomes_of(spec, rows)
    if run_failure is not None:
        failure = run_failure
    if not spec.keep_inputs:
        inputs = {}
    return _Chunk(rows.samples[:len(values)], values, inputs, failure)


def _outcomes_of(spec: _Spec, rows: _Rows) -> tuple[np.ndarray, dict[str, np.ndarray],
                                                    _Failure | None]:
    """The outcomes of `rows`, from their first up to the first that fails (then its
    failure); the rows before a run that raised are run again without it."""
    if len(rows) == 0:
        return _empty_outcomes(spec), rows.inputs, None
    keep = _keep(spec)
    try:
        result = _run(rows, spec.settings, keep=keep)
    except DzhanibekovError as exc:
        if exc.row is None or not 0 <= exc.row < len(rows):
            raise
        k = int(rows.samples[exc.row])
        failure = _Failure(k, f"the run failed: {exc.message}", exc)
        before, inputs, _ = _outcomes_of(spec, rows.take(slice(0, exc.row)))
        return before, inputs, failure
    values: list[Any] = []
    status = getattr(result, "status", None)
    for i in range(len(rows)):
        if status is not None and status[i] != "ok":
            k = int(rows.samples[i])
            failure = _Failure(k, f"the run did not finish ({status[i]}): take a smaller `dt` "
                               "or a larger `max_steps`", None)
            return _values(spec, values), _taken(rows.inputs, i), failure
        try:
            value = _outcome(spec, result, i)
            if values and isinstance(value, bool) != isinstance(values[0], bool):
                raise _BadOutcome(_mixed(value, values[0]))
            values.append(value)
        except _BadOutcome as bad:
            k = int(rows.samples[i])
            return _values(spec, values), _taken(rows.inputs, i), _Failure(k, str(bad), None)
        except Exception as exc:  # the user's `ask` may raise anything: say which sample
            k = int(rows.samples[i])
            what = "`ask` raised" if callable(spec.ask) else "the outcome failed"
            failure = _Failure(k, f"{what} {type(exc).__name__}: {exc}", exc)
            return _values(spec, values), _taken(rows.inputs, i), failure
    return _values(spec, values), rows.inputs, None


def _taken(inputs: dict[str, np.ndarray], m: int) -> dict[str, np.ndarray]:
    return {k: v[:m] for k, v in inputs.items()}


def _keep(spec: _Spec) -> str:
    """What the runs of a study keep: a summary for the asks a sweep answers, else frames."""
    if spec.ask == "tumbles" and spec.kind in ("free", "deployment"):
        return "summary"
    if spec.ask == "flips" and spec.kind == "free":
        return "summary"
    return "frames"


def _outcome(spec: _Spec, result: Any, i: int) -> Any:
    """Run `i`'s answer to the study's question."""
    ask = spec.ask
    if isinstance(result, Sweep):
        flips = int(result.flips[i])
        return flips > 0 if ask == "tumbles" else flips
    if isinstance(result, DeploymentSweep):
        return bool(result.tumbles[i])
    assert isinstance(result, Batch)
    if ask in ("tumbles", "flips"):
        counts = result.flips
        assert counts is not None, "a study's runs locate the flips (for any tensor)"
        return bool(counts[i] > 0) if ask == "tumbles" else int(counts[i])
    traj = result[i]
    if ask == "flat_spin":
        return bool(np.isfinite(flat_spin_time(traj)))
    if ask == "lvlh_angle":
        return _checked_outcome(np.max(lvlh_angles(traj)))
    if ask == "leaves_nadir":
        return bool(np.max(nadir_angles(traj)) > math.pi / 2)
    assert callable(ask)
    return _checked_outcome(ask(traj))


class _BadOutcome(Exception):
    """What an `ask` returned that a study cannot hold (the message says what)."""


_EXACT_INTEGERS = 2**53
"""Integers float64 holds exactly: the outcomes are float64 (and so in a file)."""


def _checked_outcome(value: Any) -> bool | float:
    """An `ask`'s answer as an outcome: a bool, or a finite real number (an integer one
    float64 holds exactly); anything else is refused, saying what it was: a NaN or an
    infinity would make the estimate NaN or infinite, and save and load without complaint."""
    if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "biuf":
        value = value[()]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, numbers.Integral):
        if abs(int(value)) > _EXACT_INTEGERS:
            digits = str(int(value))
            shown = digits if len(digits) <= 24 else f"{digits[:8]}… ({len(digits)} digits)"
            raise _BadOutcome(f"`ask` must return a bool or a real number float64 holds, got "
                              f"the integer {shown} (beyond 2**53, float64 rounds it)")
        return float(value)
    if isinstance(value, numbers.Real):
        number = float(value)
        if not math.isfinite(number):
            raise _BadOutcome(f"`ask` must return a bool or a finite number, got {number!r}")
        return number
    raise _BadOutcome(f"`ask` must return a bool or a real number, got "
                      f"{type(value).__name__} {value!r:.60}")


def _mixed(value: bool | float, first: bool | float) -> str:
    kinds = ("a bool", "a number")
    return (f"`ask` must return one kind of answer for every sample, got "
            f"{kinds[not isinstance(value, bool)]} ({value!r}) after {kinds[isinstance(value, bool)]} "
            f"({first!r})")


def _values(spec: _Spec, values: list[Any]) -> np.ndarray:
    if spec.ask in _YES_OR_NO:
        return np.array(values, dtype=bool)
    if spec.ask == "flips":
        return np.array(values, dtype=np.int64)
    if values and all(isinstance(v, bool) for v in values):
        return np.array(values, dtype=bool)
    return np.array(values, dtype=np.float64)


def _empty_outcomes(spec: _Spec) -> np.ndarray:
    return _values(spec, [])


# -- the study ---------------------------------------------------------------------------------


class Running(NamedTuple):
    """A plain study's estimate after its first ``n`` samples, with its interval."""

    n: np.ndarray
    estimate: np.ndarray
    lower: np.ndarray
    upper: np.ndarray


@dataclass(frozen=True, eq=False)
class MonteCarlo:
    """A Monte Carlo study: the outcome of every sample run, the estimate with its interval,
    the inputs drawn, and any sample again (see :func:`monte_carlo`).

    Attributes
    ----------
    ask : str
        The question: one of :data:`ASKS`, or the name of the callable.
    n : int
        Samples drawn (numbered ``0 … n − 1``).
    seed : numpy.random.SeedSequence
        The root of every sample's generator (sample ``k``: its ``k``-th child).
    samples : ndarray of int64, shape (runs,)
        The samples that ran, ascending: all `n` of a plain study.
    outcomes : ndarray, shape (runs,)
        Their outcomes: bool for ``"tumbles"``, ``"flat_spin"``, ``"leaves_nadir"`` and
        callables that return bools, int64 for ``"flips"``, float64 for ``"lvlh_angle"`` and
        other callables.
    inputs : dict of str to ndarray
        What each sample that ran drew, with a leading axis of length runs: ``inertia``
        (runs, 3) principal moments (for a deployment: of the deployed body, ascending),
        ``tensor`` (runs, 3, 3) in the body's own axes (the deployed one), ``axes`` (runs,
        3, 3) its principal axes as columns (a proper rotation; the identity for a body given
        by its principal moments), ``omega0``,
        ``q0``, ``separatrix`` (the distance of :func:`separatrix_distance`; a deployment's as
        if deployed at once), and ``knot_times``, ``knot_tensors`` (deployments),
        ``damper_inertia``, ``damping``, ``damper_sigma0`` (dampers: the sphere's start
        rates, the body's ``omega0`` when it co-rotates), and for systems with parts each
        number parameter of each part as the sample ran it, ``model_j.name`` (runs,):
        ``hinge_0.damping`` the first hinge's damping (parts, then torques, in order; NaN for
        an optional one left out). Empty if the inputs were not kept.
    weights : ndarray, shape (runs,)
        Each outcome's weight in the estimate ``Σ weights · outcomes``: ``1/n`` in a plain
        study, the stratum's share of the draws over its runs in a rare-event one.
    stratum : ndarray of int8, shape (runs,) or None
        A rare-event study's strata: 0 for the samples nearest the separatrix (all run), 1
        for the others (a random subset run); None for a plain study.
    kind : str
        ``"free"``, ``"deployment"`` or ``"damper"``.
    t_end, frames, method : float, int, str
    dt : float or None
        The step every run took (None: the method's own, for ``"exact"`` and adaptive ones).
    level : float
        The confidence level of :attr:`interval`.
    interval_method : str
        ``"wilson"`` or ``"clopper-pearson"``.
    """

    ask: str
    n: int
    seed: np.random.SeedSequence
    outcomes: np.ndarray
    inputs: Mapping[str, np.ndarray]
    kind: str
    t_end: float
    frames: int
    method: str
    dt: float | None
    level: float = DEFAULT_LEVEL
    interval_method: str = "wilson"
    _samples: np.ndarray | None = field(default=None, repr=False)
    stratum: np.ndarray | None = field(default=None, repr=False)
    _strata: tuple[int, int] | None = field(default=None, repr=False)
    """A rare-event study's draws per stratum (near, far)."""
    _spec: _Spec | None = field(default=None, repr=False)

    # -- what ran --------------------------------------------------------------------------

    @property
    def samples(self) -> np.ndarray:
        if self._samples is None:
            return np.arange(len(self.outcomes), dtype=np.int64)
        return self._samples

    @property
    def runs(self) -> int:
        """How many samples ran."""
        return len(self.outcomes)

    def __len__(self) -> int:
        return self.runs

    @property
    def weights(self) -> np.ndarray:
        if self.stratum is None or self._strata is None:
            return np.full(self.runs, 1.0 / max(self.runs, 1))
        draws = np.array(self._strata, dtype=np.float64)
        runs = np.bincount(self.stratum, minlength=2).astype(np.float64)
        per_run = np.divide(draws / self.n, runs, out=np.zeros(2), where=runs > 0)
        weights: np.ndarray = per_run[self.stratum]
        return weights

    # -- estimates -------------------------------------------------------------------------

    @property
    def is_boolean(self) -> bool:
        """Whether the outcomes are yes or no (a probability is estimated)."""
        return self.outcomes.dtype == np.bool_

    @property
    def mean(self) -> float:
        """The estimated mean outcome (the probability, for yes-or-no outcomes)."""
        if self.runs == 0:
            return math.nan
        if self.stratum is None:
            return float(self.outcomes.mean(dtype=np.float64))
        return float(np.dot(self.weights, self.outcomes.astype(np.float64)))

    @property
    def p(self) -> float:
        """The estimated probability of a yes-or-no outcome (``"tumbles"``, ``"flat_spin"``,
        ``"leaves_nadir"``, a callable returning bools)."""
        self._require_boolean("p")
        return self.mean

    @property
    def standard_error(self) -> float:
        """The estimate's standard error: ``√(p (1 − p) / n)`` of a plain study's yes-or-no
        outcomes (the sample standard deviation over ``√n`` for numbers); for a rare-event
        study, the two-phase stratified estimate's (Cochran 1977, §12.2):
        ``v = Σ_h W_h² s_h² / n_h + Σ_h W_h (ȳ_h − ȳ)² / n``."""
        return math.sqrt(self._variance())

    def _variance(self) -> float:
        y = self.outcomes.astype(np.float64)
        if self.runs < 2:
            return math.nan
        if self.stratum is None or self._strata is None:
            if self.is_boolean:
                p = float(y.mean())
                return p * (1 - p) / self.runs
            return float(y.var(ddof=1)) / self.runs
        total = 0.0
        between = 0.0
        mean = self.mean
        for h, drawn in enumerate(self._strata):
            yh = y[self.stratum == h]
            w = drawn / self.n
            if len(yh) == 0:
                continue
            s2 = float(yh.var(ddof=1)) if len(yh) > 1 else 0.0
            total += w * w * s2 / len(yh)
            between += w * (float(yh.mean()) - mean) ** 2
        return total + between / self.n

    @property
    def effective_runs(self) -> float:
        """The number of plain samples with the same variance: the runs of a plain study;
        ``p (1 − p) / v`` for a rare-event one (its runs when no run said yes)."""
        if self.stratum is None:
            return float(self.runs)
        p = self.mean
        v = self._variance()
        if not 0 < p < 1 or not v > 0:
            return float(self.runs)
        return p * (1 - p) / v

    @property
    def interval(self) -> tuple[float, float]:
        """The confidence interval of :attr:`p` at :attr:`level` by :attr:`interval_method`."""
        return self.confidence_interval()

    def confidence_interval(self, level: float | None = None,
                            method: str | None = None) -> tuple[float, float]:
        """The confidence interval of :attr:`p`.

        Parameters
        ----------
        level : float, optional
            The confidence level (default: the study's, 0.95 unless it was given).
        method : {"wilson", "clopper-pearson"}, optional
            Default: the study's. A rare-event study takes the binomial interval at its
            effective number of runs (Korn & Graubard 1998).
        """
        self._require_boolean("an interval")
        if self.runs == 0:
            return (0.0, 1.0)
        level = self.level if level is None else level
        method = self.interval_method if method is None else method
        n_eff = self.effective_runs
        lower, upper = binomial_interval(self.p * n_eff, n_eff, level, method)
        return float(lower), float(upper)

    def _require_boolean(self, what: str) -> None:
        if not self.is_boolean:
            raise TypeError(f"{what} is for yes-or-no outcomes; this study's are numbers "
                            f"(ask={self.ask!r}): see `mean` and `standard_error`")

    def running(self, points: int = 200) -> Running:
        """A plain study's estimate and interval after its first n samples, at about `points`
        values of n spaced evenly in log n (for the figure)."""
        self._require_boolean("the running estimate")
        if self.stratum is not None:
            raise ValueError("the running estimate is a plain study's: a rare-event study's "
                             "estimate needs all its strata")
        points = as_int("points", points, minimum=2)
        if self.runs == 0:
            empty = np.empty(0)
            return Running(np.empty(0, dtype=np.int64), empty, empty, empty)
        n = np.unique(np.geomspace(1, self.runs, points).round().astype(np.int64))
        hits = np.cumsum(self.outcomes, dtype=np.int64)[n - 1]
        lower, upper = binomial_interval(hits, n, self.level, self.interval_method)
        return Running(n, hits / n, np.asarray(lower), np.asarray(upper))

    # -- samples again ---------------------------------------------------------------------

    def rng(self, k: int) -> np.random.Generator:
        """Sample `k`'s generator, fresh (see :func:`sample_rng`): any `k`, run or not (the
        samples beyond `n` are those a larger study of the same seed draws)."""
        k = as_int("k", k, minimum=0)
        return _generator(self.seed.entropy, tuple(self.seed.spawn_key), k)

    def inputs_of(self, k: int) -> dict[str, np.ndarray]:
        """Sample `k`'s inputs, drawn again (any sample, run or not)."""
        rows = self._rows_of(k)
        return {name: value[0] for name, value in rows.inputs.items()}

    def rerun(self, k: int, frames: int | None = None) -> Trajectory:
        """Sample `k` run again alone, with its frames: bit for bit the run the study made of
        it (with the study's `frames`; other frames give the same motion for the exact method,
        and for a fixed-step method a grid of other substeps).

        Examples
        --------
        >>> import dzhanibekov as dz
        >>> study = dz.monte_carlo((1.0, 2.0, 3.0), lambda rng: rng.normal(0, 0.5, 3), 20,
        ...                        seed=1, t_end=50.0)
        >>> traj = study.rerun(3)
        >>> bool(len(traj.flip_times) > 0) == bool(study.outcomes[3])
        True
        """
        rows = self._rows_of(k)
        settings = self._spec.settings  # type: ignore[union-attr]
        if frames is not None:
            settings = settings._replace(frames=as_int("frames", frames, minimum=2))
        traj: Trajectory = _run(rows, settings, keep="single")
        return traj

    def _rows_of(self, k: Any) -> _Rows:
        if self._spec is None:
            raise ValueError("this study was loaded from a file: its dispersions are code, not "
                             "data; run dz.monte_carlo again with the same seed to rerun a "
                             "sample")
        k = as_int("k", k, minimum=0)
        rows, failure = _draw_rows(self._spec, np.array([k], dtype=np.int64))
        if failure is not None:
            raise _study_error(failure)
        return rows

    def columns(self, limit: int | None = None) -> dict[str, np.ndarray]:
        """Every scalar input that varies among the samples that ran (at most the first
        `limit`), by name: ``Ix, Iy, Iz`` (principal moments of bodies in their principal
        axes; ``I1, I2, I3`` as the bodies give them otherwise), ``Ixy, Ixz, Iyz`` (products of
        inertia), ``u0, v0, w0``, ``Q0, U0, V0, W0``, ``t0, t1, …`` (knot times), ``j, c``
        and ``su0, sv0, sw0`` (damper: the sphere's inertia, coefficient and start),
        ``separatrix`` (:func:`separatrix_distance`) and, in a study of systems with parts,
        each number parameter of each part by ``model_j.name`` (``hinge_0.damping``: the
        first hinge's damping, counting ``parts + torques`` in order). Drawn again when the
        study kept no inputs."""
        inputs = dict(self.inputs)
        count = self.runs if limit is None else min(self.runs, as_int("limit", limit,
                                                                      minimum=1))
        if not inputs and count:
            if self._spec is None:
                return {}
            rows, failure = _draw_rows(self._spec, self.samples[:count])
            if failure is not None:
                raise _study_error(failure)
            inputs = rows.inputs
        inputs = {k: v[:count] for k, v in inputs.items()}
        out: dict[str, np.ndarray] = {}
        if not inputs:
            return out
        tensor = inputs["tensor"]
        diagonal = not np.any(tensor - tensor * np.eye(3))
        names = ("Ix", "Iy", "Iz") if diagonal and self.kind != "deployment" else \
            ("I1", "I2", "I3")
        for j, name in enumerate(names):
            out[name] = inputs["inertia"][:, j]
        for (a, b), name in (((0, 1), "Ixy"), ((0, 2), "Ixz"), ((1, 2), "Iyz")):
            out[name] = -tensor[:, a, b]
        for j, name in enumerate(("u0", "v0", "w0")):
            out[name] = inputs["omega0"][:, j]
        for j, name in enumerate(("Q0", "U0", "V0", "W0")):
            out[name] = inputs["q0"][:, j]
        for j in range(inputs["knot_times"].shape[1] if "knot_times" in inputs else 0):
            out[f"t{j}"] = inputs["knot_times"][:, j]
        if "damper_inertia" in inputs:
            out["j"], out["c"] = inputs["damper_inertia"], inputs["damping"]
        if "damper_sigma0" in inputs:
            for j, name in enumerate(("su0", "sv0", "sw0")):
                out[name] = inputs["damper_sigma0"][:, j]
        out["separatrix"] = inputs["separatrix"]
        out.update({k: v for k, v in inputs.items() if _is_part_input(k)})
        return {k: v for k, v in out.items() if _varies(v)}

    def telling(self, count: int = 2, limit: int | None = 20_000) -> list[str]:
        """The `count` inputs (names of :meth:`columns`) that tell most about the outcome:
        ranked by the correlation ratio ``η²``, the share of the outcomes' variance between
        ten bins of equal counts of the input (0: the outcome does not depend on it; 1: the
        bins decide it; it sees non-monotone dependence too)."""
        columns = self.columns(limit)
        y = self.outcomes[:min(self.runs, limit or self.runs)].astype(np.float64)
        scores = {name: _correlation_ratio(x, y) for name, x in columns.items()}
        return sorted(scores, key=lambda name: -scores[name])[:count]

    # -- slices, tables, files -------------------------------------------------------------

    def __getitem__(self, key: slice) -> MonteCarlo:
        """The samples ``key`` of a plain study as a study of their own (say, the first
        half): their outcomes, inputs, estimate and interval."""
        if not isinstance(key, slice):
            raise TypeError(f"a study is sliced by samples (study[a:b]), got "
                            f"{type(key).__name__}; see `outcomes` for one sample")
        if self.stratum is not None:
            raise ValueError("a rare-event study's estimate needs all its strata: it is not "
                             "sliced")
        rows = range(self.runs)[key]
        take = slice(rows.start, rows.stop, rows.step) if len(rows) else slice(0, 0)
        return replace(self, n=len(rows), outcomes=self.outcomes[take],
                       inputs={k: v[take] for k, v in self.inputs.items()},
                       _samples=self.samples[take])

    def to_xarray(self) -> Any:
        """The study as an ``xarray.Dataset`` (the ``io`` extra): dim ``sample`` (the indices
        that ran as its coordinate), ``outcome``, ``weight``, the inputs, and the estimate,
        its interval and the settings as attributes. :func:`dzhanibekov.save` writes it."""
        xr = _tables.require("xarray", "`to_xarray`")
        dims = {"inertia": ("axis",), "tensor": ("axis", "axis2"), "axes": ("axis", "axis2"),
                "omega0": ("axis",),
                "q0": ("quaternion",), "separatrix": (), "knot_times": ("knot",),
                "knot_tensors": ("knot", "axis", "axis2"), "damper_inertia": (),
                "damping": (), "damper_sigma0": ("axis",)}
        names = {"inertia": "principal moments", "tensor": "inertia tensor in body axes",
                 "axes": "principal axes (columns) in body axes",
                 "omega0": "initial body rates", "q0": "initial " + _tables.Q_DOC,
                 "separatrix": "(L^2/2E - I_mid) / (I_max - I_min): 0 on the separatrix",
                 "knot_times": "deployment knot times",
                 "knot_tensors": "deployment knot tensors",
                 "damper_inertia": "damper sphere inertia j", "damping": "damper coefficient c",
                 "damper_sigma0": "initial damper sphere rates in body axes"}
        data: dict[str, Any] = {
            "outcome": (("sample",), self.outcomes, {"long_name": f"outcome of {self.ask}"}),
            "weight": (("sample",), self.weights,
                       {"long_name": "weight of the outcome in the estimate"}),
        }
        if self.stratum is not None:
            data["stratum"] = (("sample",), self.stratum,
                               {"long_name": "0 nearest the separatrix (all run), 1 others"})
        for name, values in self.inputs.items():
            long_name = names.get(name) or "parameter {1} of part {0}".format(*name.split("."))
            data[name] = (("sample",) + dims.get(name, ()), values, {"long_name": long_name})
        lower, upper = self.interval if self.is_boolean and self.runs else (math.nan, math.nan)
        attrs = {
            "ask": self.ask, "n": self.n, "runs": self.runs, "kind": self.kind,
            "seed_entropy": entropy_text(self.seed.entropy),
            "seed_spawn_key": ",".join(str(s) for s in self.seed.spawn_key),
            "t_end": self.t_end, "frames": self.frames, "method": self.method,
            "dt": math.nan if self.dt is None else self.dt, "level": self.level,
            "interval_method": self.interval_method, "estimate": self.mean,
            "lower": lower, "upper": upper,
            "design": "plain" if self.stratum is None else "near-separatrix",
            "outcome_type": {"b": "bool", "i": "int"}.get(self.outcomes.dtype.kind, "float"),
            "dzhanibekov_conventions": _tables.Q_DOC + "; omega in body axes",
        }
        if self._strata is not None:
            attrs["draws_near"], attrs["draws_far"] = self._strata
        coords = {"sample": ("sample", self.samples), "axis": ("axis", list(_tables.AXIS)),
                  "axis2": ("axis2", list(_tables.AXIS)),
                  "quaternion": ("quaternion", list(_tables.QUATERNION))}
        return xr.Dataset(data, coords=coords, attrs=attrs)

    @classmethod
    def from_xarray(cls, ds: Any) -> MonteCarlo:
        """A study as :meth:`to_xarray` wrote it (say, from :func:`dzhanibekov.load`): its
        outcomes, inputs and estimate; it cannot rerun a sample (its dispersions are code)."""
        a = ds.attrs
        entropy = entropy_of_text(str(a["seed_entropy"]))
        key = spawn_key_of_text(str(a["seed_spawn_key"]))
        outcomes = np.asarray(ds["outcome"].values)
        if (a["ask"] in _YES_OR_NO or outcomes.dtype == np.bool_
                or str(a.get("outcome_type", "")) == "bool"):
            outcomes = outcomes.astype(bool)
        inputs = {name: np.ascontiguousarray(ds[name].values) for name in
                  ("inertia", "tensor", "axes", "omega0", "q0", "separatrix", "knot_times",
                   "knot_tensors", "damper_inertia", "damping", "damper_sigma0") if name in ds}
        inputs.update({str(name): np.ascontiguousarray(ds[name].values) for name in ds.data_vars
                       if _is_part_input(str(name))})
        stratum = np.asarray(ds["stratum"].values, dtype=np.int8) if "stratum" in ds else None
        strata = (int(a["draws_near"]), int(a["draws_far"])) if "draws_near" in a else None
        dt = float(a["dt"])
        return cls(ask=str(a["ask"]), n=int(a["n"]),
                   seed=np.random.SeedSequence(entropy, spawn_key=key), outcomes=outcomes,
                   inputs=inputs, kind=str(a["kind"]), t_end=float(a["t_end"]),
                   frames=int(a["frames"]), method=str(a["method"]),
                   dt=None if math.isnan(dt) else dt, level=float(a["level"]),
                   interval_method=str(a["interval_method"]),
                   _samples=np.asarray(ds["sample"].values, dtype=np.int64), stratum=stratum,
                   _strata=strata)

    def __repr__(self) -> str:
        design = "" if self.stratum is None else f", runs={self.runs}"
        if self.is_boolean and self.runs:
            lo, hi = self.interval
            what = f"p={self.p:.4g} [{lo:.4g}, {hi:.4g}] at {self.level:g}"
        else:
            what = f"mean={self.mean:.4g}"
        return f"MonteCarlo(ask={self.ask!r}, n={self.n}{design}, {what})"


def _varies(values: np.ndarray) -> bool:
    finite = values[np.isfinite(values)]
    return bool(finite.size) and bool(finite.min() != finite.max())


def _correlation_ratio(x: np.ndarray, y: np.ndarray, bins: int = 10) -> float:
    """``η²`` of `y` over ten bins of equal counts of `x` (0 for a constant `y`)."""
    finite = np.isfinite(x) & np.isfinite(y)
    x, y = x[finite], y[finite]
    total = float(((y - y.mean()) ** 2).sum()) if len(y) else 0.0
    if not total > 0:
        return 0.0
    edges = np.unique(np.quantile(x, np.linspace(0, 1, bins + 1)))
    which = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, max(len(edges) - 2, 0))
    counts = np.bincount(which)
    sums = np.bincount(which, weights=y)
    means = np.divide(sums, counts, out=np.zeros_like(sums), where=counts > 0)
    between = float((counts * (means - y.mean()) ** 2).sum())
    return between / total


def _study_error(failure: _Failure) -> StudyError:
    error = StudyError(failure.message, failure.sample)
    error.__cause__ = failure.cause
    return error


# -- the entry point ---------------------------------------------------------------------------


def monte_carlo(
    system: Any,
    omega0: Any,
    n: int,
    *,
    seed: Any,
    ask: str | Callable[[Trajectory], Any] = "tumbles",
    q0: Any = (1.0, 0.0, 0.0, 0.0),
    runs: int | None = None,
    level: float = DEFAULT_LEVEL,
    interval: str = "wilson",
    chunk: int = DEFAULT_BLOCK,
    keep_inputs: bool | None = None,
    client: Any = None,
    options: RunOptions | None = None,
    **keywords: Unpack[RunKeywords],
) -> MonteCarlo:
    """Will it tumble? A Monte Carlo study of `n` samples of a system and its start.

    Each sample draws its system, then `omega0`, then `q0` from its own generator (sample
    ``k``: the ``k``-th child of ``SeedSequence(seed)``), runs in the package's batch paths
    (all cores; RK4 in SIMD lanes), and answers `ask`. The samples run in chunks of `chunk`,
    so memory stays bounded (no frames are kept unless the question needs them); each
    chunk is one call to the core, or one task on a Dask cluster with `client`. No sample
    depends on `n`, the threads, the chunks or the cluster.

    Parameters
    ----------
    system : System, Body, array_like (3,), Deployment, or callable ``rng -> system``
        What turns: a body (or its principal moments), a deployment, a body with a damper
        inside (``dz.System(body, parts=[dz.Damper(j, c)])``), a body with any other parts
        and torques (wheels, the gravity gradient, tables, …: a study of kind ``"system"``,
        which records the body's inertia, the starts and the separatrix distance of each
        sample, not its parts), or a dispersion drawing one per sample
        (:class:`~dzhanibekov.InertiaDispersion`, :class:`~dzhanibekov.DeploymentDispersion`,
        or your own ``rng -> dz.System(...)``, which disperses any part's parameter). Every
        sample must be of the kind of sample 0 (for ``"system"``, the same kinds of parts
        within a chunk).
    omega0 : array_like (3,), callable ``rng -> (3,)``, or a distribution
        Initial body rates in the body's own axes: fixed, drawn by a callable, or by a
        scipy.stats distribution (anything with ``.rvs(random_state=rng)``, e.g.
        ``scipy.stats.multivariate_normal``) giving shape (3,).
    n : int
        Samples, at least 1.
    seed : int, sequence of int, numpy.random.SeedSequence or None
        The root of the samples' generators (None: fresh entropy, kept in ``study.seed``).
    ask : {"tumbles", "flat_spin", "flips", "lvlh_angle", "leaves_nadir"} or callable
        ``"tumbles"``: a constant body (free or damped) flips at least once in
        ``[0, t_end]`` (see Notes); a deployment tumbles after its last knot, the closed
        form's verdict on the deployed body as :func:`~dzhanibekov.sweep` gives it.
        ``"flat_spin"`` (a body with a part that dissipates: a damper, a hinged appendage, a
        spring–mass damper, a slosh tank): the major axis carries
        :data:`~dzhanibekov.FLAT_SHARE` of ``|L|`` at a frame before `t_end`.
        ``"flips"``: how many flips in ``[0, t_end]``. In the gravity gradient,
        ``"lvlh_angle"``: the largest angle from the orbiting frame at a frame (radians,
        :func:`~dzhanibekov.lvlh_angles`), and ``"leaves_nadir"``: the body's z axis more
        than 90° from nadir at a frame (:func:`~dzhanibekov.nadir_angles`), past which the
        gravity gradient holds it on zenith instead. A callable gets each sample's
        trajectory (its frames: see `frames`) and returns a bool or a number.
    q0 : array_like (4,), scipy Rotation, callable or distribution
        Initial attitude, scalar first, as `omega0` is drawn.
    options : RunOptions, optional
        The runs' options as one value (:class:`~dzhanibekov.RunOptions`, its fields taken as
        they are), overridden by the keywords below; a study locates flips as its question
        needs them. Without `options`, the keywords not given take the study's defaults.
    t_end : float
        How long each sample runs (for a deployment: past its last knot): a keyword, or
        `options`' own; required.
    method : str, optional
        Default: ``"exact"`` (the closed form: exact and cheapest) for a free body, the
        package's default (``"rk4"``) for deployments and dampers.
    dt : float, optional
        The step of a fixed-step method. With None, the smallest of the steps the runs of
        samples ``0 … 15`` (:data:`PILOT`, drawn whatever `n` is) would pick alone for
        `rtol`, so that the step depends on the seed only.
    frames : int, optional
        Frames per run: 2 (default) when one number per run is asked, 201 for ``"flat_spin"``,
        the orbit asks and callables. A fixed-step run's substeps follow the frames; :meth:`~MonteCarlo.rerun`
        uses the same.
    rtol, atol, max_steps : optional
        As for :func:`~dzhanibekov.simulate`.
    threads : int, optional
        Threads per call to the core (default: all cores of the machine that runs it).
    progress : bool, optional
        A progress bar (tqdm): None shows it on a terminal for a study of more than a second.
    runs : int, optional
        Run only this many of the `n` samples, chosen by their distance to the separatrix (a
        rare-event study, see the module): at least 4, below `n`. Default: all.
    level : float
        The confidence level of ``study.interval`` (default 0.95).
    interval : {"wilson", "clopper-pearson"}
        Its method (see :func:`binomial_interval`).
    chunk : int
        Samples per call to the core (per Dask task), default 4096.
    keep_inputs : bool, optional
        Keep every sample's inputs in the study (default: for at most :data:`KEEP_INPUTS`
        samples); a sample's inputs can always be drawn again (:meth:`~MonteCarlo.inputs_of`).
    client : dask.distributed.Client, optional
        Run the chunks as tasks on this cluster (draws included); the same numbers.

    Returns
    -------
    MonteCarlo

    Raises
    ------
    TypeError, ValueError
        Bad arguments (before any run): `n` not positive, `runs` out of range, an unknown
        `ask`, `"flat_spin"` without a damper.
    StudyError
        A sample whose draw failed (a dispersion returning no body, or a non-physical one; a
        distribution of the wrong shape), whose run did not finish, or whose `ask` raised:
        naming the sample, with the samples completed before it (``.samples``,
        ``.outcomes``, ``.study``). A ValueError.
    KeyboardInterrupt
        On Ctrl-C, within a fraction of a second.

    Notes
    -----
    **What "tumbles" means.** A body spun near its intermediate axis flips first after about
    ``ln(1/ε)/λ`` (``ε`` the relative size of the perturbation, ``λ`` the growth rate of the
    linearised motion) and then every :func:`~dzhanibekov.flip_period`. As the intermediate
    moment nears another one, ``λ → 0`` and the first flip comes later than any `t_end`: so
    the probability of flipping within `t_end` is below that of spinning about the
    intermediate axis by the share of samples within that margin. Take `t_end` long enough
    (the exact method's cost does not grow with it). A motion about a stable axis also
    counts as flipping when it swings wide enough that the intermediate axis comes nearest to
    ``L`` (the definition of the flips, see :func:`~dzhanibekov.simulate`).

    Examples
    --------
    Moments (1, 3, I_z) with I_z uniform on (2.7, 3.7), spun about z: z is the intermediate
    axis, and the body tumbles, when I_z < 3 — with probability 0.3.

    >>> import dzhanibekov as dz
    >>> study = dz.monte_carlo(lambda rng: (1.0, 3.0, rng.uniform(2.7, 3.7)),
    ...                        (1e-3, 1e-3, 1.0), 2000, seed=7, t_end=1e6)
    >>> round(study.p, 3), [round(x, 3) for x in study.interval]
    (0.322, [0.302, 0.343])
    """
    given = merged("monte_carlo", options, keywords, _TAKES)
    if options is None and "t_end" not in keywords:
        raise TypeError("monte_carlo() needs `t_end`, how long each sample runs (a keyword, "
                        "or a field of `options`)")
    own = options is not None   # its fields are taken as they are; else the study's defaults
    method = given.method if own or "method" in keywords else None
    frames = given.frames if own or "frames" in keywords else None
    dt, rtol, atol, max_steps = given.dt, given.rtol, given.atol, given.max_steps
    threads, progress = given.threads, given.progress
    n = as_int("n", n, minimum=1)
    seq = _seed_sequence(seed)
    t_end = as_float("t_end", given.t_end, positive=True)
    level = _level(level)
    interval = _interval_method(interval)
    chunk = as_int("chunk", chunk, minimum=1)
    if isinstance(ask, str):
        if ask not in ASKS:
            raise ValueError(f"`ask` must be one of {ASKS} or a callable traj -> value, got "
                             f"{ask!r}")
    elif not callable(ask):
        raise TypeError(f"`ask` must be one of {ASKS} or a callable traj -> value, got "
                        f"{type(ask).__name__}")
    if runs is not None:
        runs = as_int("runs", runs, minimum=4)
        if runs >= n:
            raise ValueError(f"`runs` must be below `n` ({n}) for a rare-event study, or None "
                             f"to run every sample, got {runs}")
    for name, value in (("progress", progress), ("keep_inputs", keep_inputs)):
        if value is not None and not isinstance(value, bool):
            raise TypeError(f"`{name}` must be True, False or None, got {value!r}")
    threads = None if threads is None else as_int("threads", threads, minimum=1)
    frames_ = None if frames is None else as_int("frames", frames, minimum=2)
    if dt is not None:
        dt = as_float("dt", dt, positive=True)
    entropy, key = seq.entropy, tuple(seq.spawn_key)
    # sample 0 says the kind of system (the draw is made again with the others)
    kind, knots, dissipates = _first_kind(system, entropy, key)
    if ask == "flat_spin" and not dissipates:
        raise ValueError("`ask='flat_spin'` needs a part that dissipates (a damper, a hinge or "
                         "spring with damping, a slosh tank): pass the system as "
                         "dz.System(body, parts=[dz.Damper(j, c)]) or a callable giving such "
                         "systems")
    method_ = method if method is not None else "exact" if kind == "free" else DEFAULT_METHOD
    check_method(method_)
    if ask in _IN_ORBIT and not _in_gravity_gradient(system, entropy, key):
        raise ValueError(f"`ask={ask!r}` needs a system in the gravity gradient: pass "
                         "dz.System(body, torques=[dz.GravityGradient(n)]) or a callable "
                         "giving such systems")
    if frames_ is None:
        frames_ = 201 if (ask in ("flat_spin", *_IN_ORBIT) or callable(ask)) else 2
    keep_inputs_ = n <= KEEP_INPUTS if keep_inputs is None else keep_inputs
    max_steps = as_int("max_steps", max_steps, minimum=1)
    settings = _Settings(t_end, frames_, dt, method_, rtol, atol, threads, max_steps)
    spec = _Spec(system, omega0, q0, ask, kind, entropy, key, settings, keep_inputs_, knots)
    spec = replace(spec, settings=_planned(spec))
    # outcomes (8 bytes), and inputs (about 25 float64 values) if kept, for every sample
    check_size(n * (8 + (200 if keep_inputs_ else 0)), f"a study of {n} samples",
               "keep fewer inputs (`keep_inputs=False`) or take fewer samples")
    runner = _Runner(spec, chunk, client, progress)
    if runs is None:
        return runner.plain(n, level, interval)
    return runner.near_separatrix(n, runs, level, interval)


_TAKES = tuple(n for n in NAMES if n != "flips")
"""The run options a study takes: it locates the flips as its question needs them."""


def _first_kind(system: Any, entropy: Any, key: tuple[int, ...]) -> tuple[str, int, bool]:
    """The kind of system of sample 0 (a fixed system's own), its knots if a deployment, and
    whether its parts dissipate (a flat spin can be asked of it)."""
    value = system
    if _is_random(system):
        value = _sample_zero(system, entropy, key)
    knots = len(value.times) if isinstance(value, Deployment) else 0
    kind = _kind(value)
    dissipates = kind == "damper" or (
        kind == "system" and "energy_balance" in value.conserved)
    return kind, knots, dissipates


def _in_gravity_gradient(system: Any, entropy: Any, key: tuple[int, ...]) -> bool:
    """Whether sample 0's system is in the gravity gradient (what the orbit asks measure)."""
    value = _sample_zero(system, entropy, key) if _is_random(system) else system
    return any(isinstance(t, GravityGradient) for t in getattr(value, "torques", ()))


def _sample_zero(system: Any, entropy: Any, key: tuple[int, ...]) -> Any:
    rng = _generator(entropy, key, 0)
    try:
        value = _draw(system, rng)
    except Exception as exc:  # the user's callable: say which sample
        raise _study_error(_Failure(0, f"`system` failed: {type(exc).__name__}: {exc}",
                                    exc)) from exc
    return value


def _planned(spec: _Spec) -> _Settings:
    """The settings with a fixed-step method's step fixed (see `dt` of `monte_carlo`): from
    the pilot samples' runs when not given."""
    s = spec.settings
    if s.method == "exact":
        return s._replace(dt=None, rtol=None, atol=None)
    if METHODS[s.method].adaptive or s.dt is not None:
        return s
    rows, failure = _draw_rows(spec, np.arange(PILOT, dtype=np.int64))
    if failure is not None:
        error = _study_error(failure._replace(
            message=failure.message + f" (drawn to plan the step: samples 0 … {PILOT - 1})"))
        raise error
    pilot = _run(rows, s, keep="summary" if _keep(spec) == "summary" else "frames")
    steps = np.asarray(pilot.dt, dtype=np.float64)
    steps = steps[np.isfinite(steps)]
    if steps.size == 0:
        raise StudyError(f"no run of samples 0 … {PILOT - 1} finished to plan the step: give "
                         "`dt`")
    # the step is given from now on: the planner's tolerance is spent
    return s._replace(dt=float(steps.min()), rtol=None)


class _Runner:
    """Runs a study's chunks in order, here or on a Dask cluster, with a progress bar."""

    def __init__(self, spec: _Spec, chunk: int, client: Any, progress: bool | None) -> None:
        self.spec = spec
        self.chunk = chunk
        self.submit = None if client is None else _dask(client)
        self.progress = progress

    def map(self, pieces: Iterable[np.ndarray], total: int, mode: str, desc: str, *,
            numbered: bool = True) -> tuple[list[_Chunk], _Failure | None]:
        """The chunks `pieces` run in order, up to the first that failed (its part kept);
        without their sample numbers unless `numbered` (a plain study's are 0, 1, …)."""
        bar = tqdm(total=total, desc=desc, unit="sample", leave=False,
                   disable=None if self.progress is None else not self.progress,
                   delay=_PROGRESS_DELAY if self.progress is None else 0.0)
        with bar:
            done: list[_Chunk] = []
            failure: _Failure | None = None
            if self.submit is not None:
                done, failure = self.submit(self.spec, list(pieces), mode, bar.update)
            else:
                for piece in pieces:
                    part = _chunk(self.spec, piece, mode)
                    bar.update(len(part.samples))
                    done.append(part)
                    if part.failure is not None:
                        failure = part.failure
                        break
        if mode == "run":
            done, failure = _one_kind(done, failure)
        if not numbered:
            done = [part._replace(samples=part.samples[:0]) for part in done]
        return done, failure

    def _range(self, n: int) -> Iterator[np.ndarray]:
        """Samples 0 … n − 1 in chunks, made as they are needed."""
        for start in range(0, n, self.chunk):
            yield np.arange(start, min(start + self.chunk, n), dtype=np.int64)

    def plain(self, n: int, level: float, interval: str) -> MonteCarlo:
        done, failure = self.map(self._range(n), n, "run", "study", numbered=False)
        study = self._study(done, n, level, interval)
        if failure is not None:  # the samples before it ran: 0 … failure.sample - 1
            error = _study_error(failure)
            error.samples, error.outcomes = study.samples, study.outcomes
            error.study = replace(study, n=study.runs)
            raise error
        return study

    def near_separatrix(self, n: int, runs: int, level: float, interval: str) -> MonteCarlo:
        """Phase 1: every sample's distance to the separatrix; phase 2: the nearest half of
        `runs` and a random half of the others, run."""
        check_size(n * 24, f"the separatrix distances of {n} samples", "take fewer samples")
        done, failure = self.map(self._range(n), n, "score", "draws")
        if failure is not None:
            raise _study_error(failure)
        distance = np.abs(np.concatenate([c.values for c in done]))
        del done
        near_count = runs // 2
        order = np.argsort(distance, kind="stable")
        near, rest = order[:near_count], np.sort(order[near_count:])
        del order, distance
        pick = np.random.Generator(np.random.PCG64(np.random.SeedSequence(
            self.spec.entropy, spawn_key=self.spec.spawn_key + (_SELECTION_KEY,))))
        far = rest[pick.choice(len(rest), runs - near_count, replace=False)]
        del rest
        chosen = np.sort(np.concatenate([near, far]))
        pieces = [chosen[a:a + self.chunk] for a in range(0, runs, self.chunk)]
        ran, failure = self.map(pieces, runs, "run", "study")
        if failure is not None:
            error = _study_error(failure)
            error.samples = _concatenate([c.samples for c in ran], np.empty(0, np.int64))
            error.outcomes = _concatenate([c.values for c in ran], _empty_outcomes(self.spec))
            raise error
        samples = np.concatenate([c.samples for c in ran])
        stratum = np.isin(samples, far).astype(np.int8)
        return self._study(ran, n, level, interval, samples=samples, stratum=stratum,
                           strata=(near_count, n - near_count))

    def _study(self, done: list[_Chunk], n: int, level: float, interval: str, *,
               samples: np.ndarray | None = None, stratum: np.ndarray | None = None,
               strata: tuple[int, int] | None = None) -> MonteCarlo:
        spec = self.spec
        outcomes = _concatenate([c.values for c in done], _empty_outcomes(spec))
        inputs: dict[str, np.ndarray] = {}
        drawn = [c for c in done if c.inputs]  # (a chunk whose task failed drew nothing)
        if spec.keep_inputs and drawn:
            # every chunk's names (a chunk that drew no system has no part's parameters)
            for name in drawn[0].inputs:
                if all(name in c.inputs for c in drawn):
                    inputs[name] = np.concatenate([c.inputs[name] for c in drawn])
        ask = spec.ask if isinstance(spec.ask, str) else getattr(spec.ask, "__name__",
                                                                  type(spec.ask).__name__)
        return MonteCarlo(
            ask=ask, n=n, seed=np.random.SeedSequence(spec.entropy, spawn_key=spec.spawn_key),
            outcomes=outcomes, inputs=inputs, kind=spec.kind, t_end=spec.settings.t_end,
            frames=spec.settings.frames, method=spec.settings.method, dt=spec.settings.dt,
            level=level, interval_method=interval, _samples=samples, stratum=stratum,
            _strata=strata, _spec=spec)


def _one_kind(done: list[_Chunk], failure: _Failure | None
              ) -> tuple[list[_Chunk], _Failure | None]:
    """The chunks up to the first whose outcomes are of another kind (bools, numbers) than
    the first's, which fails at its first sample; the chunks before it are kept. (A chunk's
    own outcomes are of one kind: see `_outcomes_of`.)"""
    first: Any = None
    for i, part in enumerate(done):
        if not part.values.size:
            continue
        if first is None:
            first = part.values[0]
        elif (part.values.dtype == np.bool_) != isinstance(first, np.bool_):
            value = part.values[0]
            value = bool(value) if isinstance(value, np.bool_) else float(value)
            first_ = bool(first) if isinstance(first, np.bool_) else float(first)
            return done[:i], _Failure(int(part.samples[0]), _mixed(value, first_), None)
    return done, failure


def _concatenate(parts: Sequence[np.ndarray], empty: np.ndarray) -> np.ndarray:
    return np.concatenate(parts) if parts else empty


def _same(value: Any) -> Any:
    return value


def _lost(spec: _Spec, piece: np.ndarray, mode: str, exc: BaseException) -> _Chunk:
    """A chunk whose Dask task failed as a whole (its worker died on every try: Dask's
    ``KilledWorker``; its data lost): no sample of it kept, the failure at its first."""
    first, last = int(piece[0]), int(piece[-1])
    empty = _empty_outcomes(spec) if mode == "run" else np.empty(0)
    why = (f"the Dask task of the chunk of samples {first}–{last} failed "
           f"({type(exc).__name__}: {exc}); the samples before the chunk are kept")
    return _Chunk(piece[:0], empty, {}, _Failure(first, why, exc))


def _dask(client: Any) -> Callable[..., tuple[list[_Chunk], _Failure | None]]:
    """Maps chunks on a Dask cluster, one task each, gathered in order up to the first that
    failed."""
    try:
        import distributed
    except ImportError:
        raise ImportError("`client` needs dask.distributed: pip install dzhanibekov[dask]") \
            from None
    if not isinstance(client, distributed.Client):
        raise TypeError(f"`client` must be a dask.distributed.Client, got "
                        f"{type(client).__name__}")
    cluster: Any = client  # distributed is untyped

    def submit(spec: _Spec, pieces: list[np.ndarray], mode: str,
               advance: Callable[[int], Any]) -> tuple[list[_Chunk], _Failure | None]:
        if not pieces:
            return [], None
        # the spec as a task's result, not scattered: a worker that dies with it loses data
        # the scheduler can make again (scattered data it cannot, and every chunk that needed
        # it was then cancelled: "FutureCancelledError … already forgotten")
        shared = cluster.submit(_same, spec, pure=False)
        futures = cluster.map(_chunk, [shared] * len(pieces), pieces, [mode] * len(pieces),
                              pure=False)
        index = {f.key: k for k, f in enumerate(futures)}
        results: dict[int, _Chunk] = {}
        stop = len(pieces)  # chunks from here on are not needed (one before it failed)
        try:
            completed: Any = distributed.as_completed(futures)  # type: ignore[no-untyped-call]
            for done in completed:
                k = index[done.key]
                if k >= stop:
                    continue
                try:
                    part: _Chunk = done.result()
                except Exception as exc:  # noqa: BLE001 - the task, not a sample, failed
                    part = _lost(spec, pieces[k], mode, exc)
                results[k] = part
                advance(len(part.samples))
                if part.failure is not None:
                    stop = k + 1
                    cluster.cancel(futures[stop:])
                if all(j in results for j in range(stop)):
                    break
        except BaseException:
            cluster.cancel(futures)
            raise
        ordered = [results[k] for k in range(stop)]
        return ordered, ordered[-1].failure

    return submit
