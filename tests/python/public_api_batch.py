"""The hostile-input table, part two: batches (`simulate` with a leading batch axis), sweeps,
`grid` and the stability maps. `ENTRIES` here is the whole table (part one is `public_api.py`).

Every row of a batch or a sweep is held to what the single run of its inputs gives: the same
bits when the step is given (the batch's promise), and the physics checks of `check_run`.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from hypothesis import strategies as st

import dzhanibekov as dz
from dzhanibekov.plotting import maps
from hostile import (
    JUNK,
    hostile_array,
    hostile_int,
    hostile_real,
    layouts,
    quaternions,
    real_arrays,
    valid_int,
)
from public_api import ENTRIES as SINGLE_ENTRIES
from public_api_study import ENTRIES as STUDY_ENTRIES
from public_api import (
    Entry,
    _rate_rows,
    check_model_run,
    check_run,
    deployments_args,
    model_run_args,
    quiet_body,
    run_args,
    run_hostile,
)

# -- batches ------------------------------------------------------------------------------------


@st.composite
def batch_args(draw: st.DrawFn, *, flips: bool = True) -> dict[str, Any]:
    """A run's arguments (as extreme as `run_args` makes them) turned into a batch of 1 to 5
    runs: rates (M, 3) near the drawn ones (0.5 to 2 times, another direction among them),
    moments shared or (M, 3), attitudes shared or (M, 4)."""
    method = draw(st.sampled_from(tuple(m for m in dz.METHODS if "free" in dz.METHODS[m].models)))
    kwargs = draw(run_args(method, flips=flips))
    m = draw(st.integers(1, 5))
    body = kwargs["system"]
    inertia = np.array(body.inertia if isinstance(body, dz.Body) else np.asarray(body, float))
    omega0 = np.asarray(kwargs["omega0"], dtype=float)
    factors = draw(st.lists(st.sampled_from([1.0, 0.5, 2.0, 0.75, -1.0]), min_size=m, max_size=m))
    rows = np.stack([omega0 * f for f in factors])
    if m > 1 and draw(st.booleans()):
        rows[-1] = np.roll(rows[-1], 1)  # another direction at the same rate
    kwargs["omega0"] = draw(layouts(rows))
    if draw(st.booleans()):
        stretch = draw(st.lists(st.sampled_from([1.0, 0.5, 2.0]), min_size=m, max_size=m))
        per_row = np.stack([inertia * s for s in stretch])
        # three bodies' moments are said with a list of Bodies: a (3, 3) array is ambiguous
        # (one body's tensor?) and refused
        kwargs["system"] = [quiet_body(r) for r in per_row] if m == 3 else \
            draw(layouts(per_row))
    if draw(st.booleans()):
        kwargs["q0"] = draw(layouts(np.stack([draw(quaternions()) for _ in range(m)])))
    if draw(st.booleans()):
        kwargs["threads"] = draw(valid_int(1, 3))
    return kwargs


def looks_valid(value: Any, width: int, max_ndim: int, *, positive: bool = False) -> bool:
    """Whether `value` is real rows of `width` a batch of at most `max_ndim` leading axes
    takes (a single run's hostile shapes such as (2, 3) are a batch's valid ones)."""
    try:
        arr = np.asarray(value)
    except Exception:
        return False
    if arr.dtype.kind not in "iuf" or not 1 <= arr.ndim <= max_ndim + 1 or arr.shape[-1] != width:
        return False
    if arr.size == 0 or not np.isfinite(arr).all():
        return False
    rows = arr.reshape(-1, width).astype(float)
    if positive:
        with np.errstate(all="ignore"):
            return bool((rows > 0).all() and (rows.max(axis=1) / rows.min(axis=1) <= 1e150).all())
    return bool(rows.any(axis=1).all()) if width == 4 else True


def batch_hostile(*, flips: bool = True, max_ndim: int = 1) -> dict[str, st.SearchStrategy[Any]]:
    """A run's hostile values that are no batch either, plus batches spoilt in one row and
    mismatched batch axes."""
    hostile = dict(run_hostile(tuple(dz.METHODS), flips=flips))
    rows3 = real_arrays((3, 3), st.floats(0.5, 2.0))
    rows4 = real_arrays((3, 4), st.floats(0.5, 2.0))
    hostile["omega0"] = st.one_of(hostile["omega0"], hostile_array((None, 3), rows3),
                                  st.just(np.ones((0, 3)))).filter(
        lambda v: not looks_valid(v, 3, max_ndim))
    hostile["system"] = st.one_of(hostile["system"], hostile_array((None, 3), rows3),
                                st.just(np.array([[1.0, 2.0, 3.0], [1.0, -2.0, 3.0]]))).filter(
        lambda v: not looks_valid(v, 3, max_ndim, positive=True))
    hostile["q0"] = st.one_of(hostile["q0"], hostile_array((None, 4), rows4),
                              st.just(np.zeros((2, 4)))).filter(
        lambda v: not looks_valid(v, 4, max_ndim))
    hostile["threads"] = hostile_int(1).filter(lambda v: v is not None)  # None: the default
    return hostile


def row_kwargs(kwargs: dict[str, Any], i: int, m: int) -> dict[str, Any]:
    """The arguments of run `i` of a batch of `m` runs, alone."""
    one = {k: v for k, v in kwargs.items() if k not in ("threads", "block", "progress")}
    for name, width in (("system", 3), ("omega0", 3), ("q0", 4)):
        value = kwargs.get(name)
        if value is None or isinstance(value, dz.Body):
            continue
        if isinstance(value, list) and all(isinstance(b, dz.Body) for b in value):
            one[name] = value[i]
            continue
        arr = np.asarray(value, dtype=float)
        one[name] = arr.reshape(-1, width)[i] if arr.ndim == 2 else arr
    if not isinstance(one["system"], dz.Body):
        one["system"] = quiet_body(np.asarray(one["system"], dtype=float))
    return one


def same_bits(a: np.ndarray | None, b: np.ndarray | None) -> bool:
    if a is None or b is None:
        return a is b
    return a.shape == b.shape and bool(np.array_equal(a.view(np.uint64), b.view(np.uint64)))


def check_batch(kwargs: dict[str, Any], batch: Any, caught: list[warnings.WarningMessage]) -> None:
    """Every row passes the single-run checks, and is the single run bit for bit when the step
    is given (with `dt=None` the batch takes the smallest step its runs would pick alone)."""
    assert isinstance(batch, dz.Batch)
    m = len(batch)
    assert m == len(np.asarray(kwargs["omega0"], dtype=float).reshape(-1, 3))
    assert batch.omega.shape[:2] == batch.q.shape[:2] == (m, int(kwargs["frames"]))
    for d in batch.drift:
        assert isinstance(d, np.ndarray) and d.shape == (m,) and np.isfinite(d).all()
    for i in range(m):
        one = row_kwargs(kwargs, i, m)
        check_run(one, batch[i], caught)
        if kwargs.get("dt") is not None:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                alone = dz.simulate(**one)
            for name in ("omega", "q", "flip_times", "t"):
                assert same_bits(getattr(batch[i], name), getattr(alone, name)), (i, name)
            assert tuple(batch[i].drift) == tuple(alone.drift), i


# -- sweeps -------------------------------------------------------------------------------------


@st.composite
def sweep_args(draw: st.DrawFn) -> dict[str, Any]:
    kwargs = draw(batch_args(flips=False))
    if draw(st.booleans()):
        kwargs["block"] = draw(valid_int(1, 4))
    kwargs["progress"] = draw(st.sampled_from([None, False]))
    return kwargs


def sweep_hostile() -> dict[str, st.SearchStrategy[Any]]:
    hostile = batch_hostile(flips=False, max_ndim=8)
    hostile["block"] = hostile_int(1)
    hostile["progress"] = st.one_of(JUNK.filter(lambda v: v is not None),
                                    st.sampled_from([1, 0, "yes", np.array([True])]))
    return hostile


def check_sweep(kwargs: dict[str, Any], result: Any, caught: list[warnings.WarningMessage]) -> None:
    """Per-run numbers in range, NaN only where documented (no flip, fewer than two, a run
    that did not finish), and each row the summary of its run alone when the step is given
    (or, for a run that did not finish, the error of its run alone)."""
    assert isinstance(result, dz.Sweep)
    m = len(result)
    t_end = float(kwargs["t_end"])
    ok = result.ok
    assert set(result.status.ravel()) <= {"ok", "diverged", "too many steps", "too many flips"}
    assert (ok == (result.status == "ok")).all()
    flips, first, period = result.flips, result.first_flip, result.period
    assert flips.dtype == np.int64 and (flips[ok] >= 0).all() and (flips[~ok] == -1).all()
    for name in ("first_flip", "period", "tilt", "dt"):  # a run that did not finish: NaN
        assert np.isnan(getattr(result, name)[~ok]).all(), name
    assert (result.n_steps[~ok] == 0).all()
    flips, first, period = flips[ok], first[ok], period[ok]
    assert (np.isnan(first) == (flips == 0)).all() and (np.isnan(period) == (flips < 2)).all()
    assert ((first[flips > 0] >= 0) & (first[flips > 0] <= t_end)).all()
    assert (period[flips > 1] > 0).all() and np.isfinite(period[flips > 1]).all()
    assert not np.isnan(result.exact_period).any() and (result.exact_period > 0).all()
    tilt = result.tilt[ok]
    assert np.isfinite(tilt).all() and ((tilt >= 0) & (tilt <= math.pi)).all()
    for d in result.drift:
        assert np.isfinite(d[ok]).all() and (d[ok] >= 0).all() and np.isnan(d[~ok]).all()
    assert np.isfinite(result.dt[ok]).all() and (result.n_steps >= 0).all()
    for i in range(m):
        if kwargs.get("dt") is None:
            continue
        one = row_kwargs(kwargs, i, m)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if not ok.flat[i]:
                try:
                    dz.summarize(**one)
                except dz.TooLargeError:  # alone, refused before it runs: no run either
                    continue
                except ValueError as exc:  # the run alone fails as the sweep says
                    why = {"diverged": "diverged", "too many steps": "max_steps",
                           "too many flips": "flip"}[str(result.status.flat[i])]
                    assert why in str(exc), (i, str(exc))
                    continue
                raise AssertionError(f"row {i} did not finish in the sweep but does alone")
            alone = dz.summarize(**one)
        times = alone.flip_times
        assert result.flips.flat[i] == len(times), i
        if len(times):
            assert result.first_flip.flat[i] == times[0], i
        assert tuple(float(d.flat[i]) for d in result.drift) == tuple(alone.drift), i
        assert result.n_steps.flat[i] == alone.n_steps, i


# -- grid ---------------------------------------------------------------------------------------


@st.composite
def grid_args(draw: st.DrawFn) -> dict[str, Any]:
    axes = []
    for _ in range(draw(st.integers(1, 4))):
        if draw(st.booleans()):
            axes.append(draw(st.sampled_from([0.0, -0.0, 1.0, 1e-300, 5e-324, 1e300, 3, np.float32(2)])))
        else:
            n = draw(st.integers(1, 5))
            axes.append(draw(real_arrays((n,), st.floats(-1e300, 1e300)).flatmap(layouts)))
    return {"axes": tuple(axes)}


def call_grid(axes: Any) -> np.ndarray:
    """`dz.grid(*axes)`, keyword-callable for the table."""
    return dz.grid(*axes)


def check_grid(kwargs: dict[str, Any], out: Any, caught: list[warnings.WarningMessage]) -> None:
    axes = kwargs["axes"]
    varying = [np.asarray(a, dtype=float) for a in axes if np.ndim(a) == 1]
    assert isinstance(out, np.ndarray) and out.dtype == np.float64 and np.isfinite(out).all()
    assert out.shape == tuple(len(v) for v in varying) + (len(axes),)
    for j, a in enumerate(axes):  # each column holds that axis's values, and only them
        assert set(out[..., j].ravel()) == set(np.asarray(a, dtype=float).ravel())


def hostile_axes() -> st.SearchStrategy[Any]:
    def number(v: Any) -> bool:  # a finite real number, or a 0-d array of one, is an axis
        try:
            arr = np.asarray(v)
        except Exception:
            return False
        return arr.ndim == 0 and arr.dtype.kind in "iuf" and bool(np.isfinite(arr))

    def axis(v: Any) -> bool:  # a non-empty 1-D array of finite real numbers is one too
        try:
            arr = np.asarray(v)
        except Exception:
            return False
        return (arr.ndim == 1 and arr.size > 0 and arr.dtype.kind in "iuf"
                and bool(np.isfinite(arr).all()))

    bad = st.one_of(hostile_array((None,), real_arrays((3,), st.floats(-1, 1))).filter(
        lambda v: not number(v) and not axis(v)),
        st.just(np.ones((2, 2))), st.just(np.array([])), st.just([]))
    return st.one_of(st.just(()), st.tuples(bad), st.tuples(st.just([0.1, 0.2]), bad))


# -- stability maps -----------------------------------------------------------------------------


def map_sweep_args() -> st.SearchStrategy[dict[str, Any]]:
    return st.fixed_dictionaries({
        "kind": st.sampled_from(maps.MAPS), "size": valid_int(2, 4),
        "t_end": st.sampled_from([0.5, 2.0, 10.0]), "dt": st.sampled_from([0.05, 0.1, 0.01]),
        "progress": st.just(False)})


def check_map_sweep(kwargs: dict[str, Any], result: Any, caught: list[warnings.WarningMessage]) -> None:
    size = int(kwargs["size"])
    check_sweep({**kwargs, "dt": None}, result, caught)
    assert result.shape == (size, size)


def stability_map_args() -> st.SearchStrategy[dict[str, Any]]:
    def build(args: tuple[str, int, str, bool]) -> dict[str, Any]:
        kind, size, quantity, separatrix = args
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", dz.StepSizeWarning)
            result = maps.map_sweep(kind, size=size, t_end=30.0, dt=0.05, progress=False)
        return {"result": result,
                "quantity": quantity, "separatrix": separatrix}
    return st.tuples(st.sampled_from(maps.MAPS), st.integers(2, 4), st.sampled_from(maps.QUANTITIES),
                     st.booleans()).map(build)


def check_map(kwargs: dict[str, Any], fig: Any, caught: list[warnings.WarningMessage]) -> None:
    from matplotlib.figure import Figure
    assert isinstance(fig, Figure)
    fig.canvas.draw()


def separatrix_args() -> st.SearchStrategy[dict[str, Any]]:
    from hostile import directions, inertias, scaled
    return st.tuples(inertias(), directions(3), st.sampled_from([0, -500, 500])).map(
        lambda a: {"inertia": a[0], "omega": scaled(a[1], a[2])})


def check_gap(kwargs: dict[str, Any], gap: Any, caught: list[warnings.WarningMessage]) -> None:
    from fractions import Fraction as F
    gap = np.asarray(gap)
    assert gap.shape == () and np.isfinite(gap), gap
    # the formula in exact rational arithmetic (no overflow, no cancellation), rounded once
    inertia = [F(float(x)) for x in np.asarray(kwargs["inertia"], dtype=float)]
    omega = [F(float(x)) for x in np.asarray(kwargs["omega"], dtype=float)]
    mid = sorted(inertia)[1]
    l2 = sum((i * w) ** 2 for i, w in zip(inertia, omega))
    if l2 == 0:
        assert float(gap) == 0.0
        return
    exact = sum(i * (i - mid) * w * w for i, w in zip(inertia, omega)) / l2
    size = sum(abs(i * (i - mid)) * w * w for i, w in zip(inertia, omega)) / l2
    assert abs(F(float(gap)) - exact) <= F(1e-13) * size + F(1e-300), (float(gap), float(exact))


# -- batches and sweeps of bodies that change -----------------------------------------------------


@st.composite
def model_batch_args(draw: st.DrawFn) -> dict[str, Any]:
    """A batch of 1 to 3 deployments (a list) or damped bodies (moments or bodies, dampers
    shared or one per run), rates (M, 3) or shared: each run one `model_run_args` draws."""
    kind = draw(st.sampled_from(["deployment", "damper"]))
    runs = [draw(model_run_args(kind)) for _ in range(draw(st.integers(1, 3)))]
    kwargs = {k: v for k, v in runs[0].items() if k not in ("system", "omega0", "q0")}
    kwargs["omega0"] = np.stack([np.asarray(r["omega0"], float).reshape(3) for r in runs])
    kwargs["system"] = [r["system"] for r in runs]
    if kind == "damper" and draw(st.booleans()):
        kwargs["system"] = kwargs["system"][0]  # one damped body, a batch of starts
    return kwargs


def check_model_batch(kwargs: dict[str, Any], batch: Any,
                      caught: list[warnings.WarningMessage]) -> None:
    """Each row passes the single run's checks and, the step given, is its single run."""
    assert isinstance(batch, dz.Batch) and len(batch) == len(kwargs["omega0"])
    if any(issubclass(w.category, dz.StiffDamperWarning) for w in caught):
        return  # the step beyond RK4's limit for a row's damper, as warned: no physics
    systems = kwargs["system"] if isinstance(kwargs["system"], list) else \
        [kwargs["system"]] * len(batch)
    for i in range(len(batch)):
        one = dict(kwargs, system=systems[i], omega0=kwargs["omega0"][i])
        check_model_run(one, batch[i], caught)
        if i == len(batch) - 1 and kwargs.get("dt") is not None:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                single = dz.simulate(**one)
            np.testing.assert_array_equal(batch[i].omega, single.omega)
            np.testing.assert_array_equal(batch[i].energy, single.energy)


def model_batch_hostile() -> dict[str, st.SearchStrategy[Any]]:
    return {"omega0": st.one_of(JUNK, st.just(np.zeros((2, 3, 3))), st.just([[1.0, np.nan, 0.0]]),
                                st.just(np.zeros((2, 3, 3)))),
            "q0": st.one_of(JUNK.filter(lambda v: v is not None), st.just(np.zeros((1, 4))),
                            st.just([[1.0, 0.0, 0.0]])),
            "t_end": hostile_real(positive=True),
            "frames": hostile_int(2),
            "method": st.sampled_from(["exact", "splitting", "splitting4", "RK4", ""])}


@st.composite
def deployment_sweep_args(draw: st.DrawFn) -> dict[str, Any]:
    """`deployments_args` as a sweep: `t_end` at or past every last knot, few frames."""
    kwargs = draw(deployments_args())
    last = max(float(d.times[-1]) for d in kwargs["system"])
    kwargs["t_end"] = last * draw(st.sampled_from([1.0, 1.5]))
    kwargs["frames"] = draw(valid_int(2, 5))
    return kwargs


def check_deployment_sweep(kwargs: dict[str, Any], s: Any,
                           caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(s, dz.DeploymentSweep) and len(s) == len(kwargs["system"])
    assert set(s.status) <= set(dz._core.RUN_STATUSES) and (s.ok == (s.status == "ok")).all()
    ok = s.ok
    assert (s.tumbles == np.isfinite(s.flip_period)).all()
    assert (s.flip_period[ok] > 0).all() and np.isnan(s.flip_period[~ok]).all()
    assert np.isfinite(s.energy_change[ok]).all() and (s.energy_change[ok] > -1).all()
    assert (s.inertia > 0).all()
    for d, moments in zip(kwargs["system"], s.inertia):  # the deployed body's, any order
        np.testing.assert_allclose(np.sort(moments), np.linalg.eigvalsh(d.tensors[-1]),
                                   rtol=1e-12)
    assert len(s.verdict) == len(s)


ENTRIES: dict[str, Entry] = {
    **SINGLE_ENTRIES,
    **STUDY_ENTRIES,
    "simulate[model batch]": Entry(
        call=dz.simulate,
        valid=model_batch_args(),
        hostile=model_batch_hostile(),
        check=check_model_batch,
        covers=(dz.Batch,),
        # the drawn step is fitted to the first run: it may be beyond RK4's limit for the
        # damper of another, and then the batch warns
        warns=(dz.InertiaWarning, dz.StiffDamperWarning, dz.StepSizeWarning),
        examples=30,
        min_success=0.5,
    ),
    "sweep[deployment]": Entry(
        call=dz.sweep,
        valid=deployment_sweep_args(),
        hostile={"system": st.sampled_from([[], "x", None, 1.0]),
                 "omega0": st.one_of(JUNK, st.just(np.zeros((2, 3, 3))),
                                     st.just([[1.0, np.nan, 0.0]])),
                 "t_end": hostile_real(positive=True),
                 "frames": hostile_int(2),
                 "method": st.sampled_from(["exact", "splitting", "splitting4", "RK4", ""])},
        check=check_deployment_sweep,
        covers=(dz.DeploymentSweep,),
        warns=(dz.InertiaWarning, dz.StepSizeWarning),
        examples=30,
        min_success=0.5,
    ),
    "simulate[batch]": Entry(
        call=dz.simulate,
        valid=batch_args(),
        hostile=batch_hostile(),
        check=check_batch,
        covers=(dz.Batch, dz.BatchDrift),
        warns=(dz.StepSizeWarning, dz.InertiaWarning),
        min_success=0.2,
    ),
    "sweep": Entry(
        call=dz.sweep,
        valid=sweep_args(),
        hostile=sweep_hostile(),
        check=check_sweep,
        covers=(dz.sweep, dz.Sweep),
        warns=(dz.StepSizeWarning, dz.InertiaWarning),
        min_success=0.2,
    ),
    "grid": Entry(
        call=call_grid,
        valid=grid_args(),
        hostile={"axes": hostile_axes()},
        check=check_grid,
        covers=(dz.grid,),
        min_success=0.9,
    ),
    "maps.map_sweep": Entry(
        call=maps.map_sweep,
        valid=map_sweep_args(),
        hostile={"kind": st.one_of(JUNK, st.sampled_from(["RATES", "", "iy"])),
                 "size": hostile_int(2), "t_end": hostile_real(positive=True),
                 "dt": hostile_real(positive=True)},
        check=check_map_sweep,
        warns=(dz.StepSizeWarning,),
        examples=60,
        min_success=0.9,
    ),
    "maps.stability_map": Entry(
        call=maps.stability_map,
        valid=stability_map_args(),
        hostile={"result": st.one_of(JUNK, st.just(np.zeros((3, 3)))),
                 "quantity": st.one_of(JUNK, st.sampled_from(["PERIOD", "", "drift"]))},
        check=check_map,
        examples=12,
        min_success=0.9,
    ),
    "maps.separatrix_gap": Entry(
        call=maps.separatrix_gap,
        valid=separatrix_args(),
        hostile={"inertia": st.one_of(JUNK, st.just(np.array([1.0, np.nan, 2.0])),
                                      st.just(np.array([1.0, -1.0, 2.0]))),
                 "omega": st.one_of(JUNK.filter(lambda v: not isinstance(v, range)),
                                    st.just(np.array([np.inf, 0.0, 1.0])))},
        check=check_gap,
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
}
