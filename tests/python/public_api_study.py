"""The hostile-input table, part three: Monte Carlo studies and the dispersions.

A study is held to its promises for any valid arguments: one outcome per sample that ran, a
probability in [0, 1] inside its interval, and each sample's rerun giving its outcome. A
dispersion's every draw is a physical body (a positive definite tensor whose moments keep the
triangle inequality), deployment or damper.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from hypothesis import strategies as st

import dzhanibekov as dz
from dzhanibekov import _core
from hostile import JUNK, hostile_int, hostile_real, valid_int
from public_api import Entry

BODIES = [(1.0, 2.0, 3.0), (1.0, 2.0, 2.05), (27.083, 52.083, 41.667), (1.0, 1.0, 1.5)]


def _spin(rng: np.random.Generator) -> np.ndarray:
    return np.array([rng.normal(0, 0.1), rng.normal(0, 0.1), 1.0])


def _last_u(traj: dz.Trajectory) -> float:
    return float(traj.omega[-1, 0])


@st.composite
def study_args(draw: st.DrawFn) -> dict[str, Any]:
    """A small study (at most 8 samples of at most 5000 steps): any system kind of the free
    body, any ask, method, interval, chunking and rare-event design."""
    n = draw(valid_int(1, 8))
    body = draw(st.sampled_from(BODIES))
    system: Any = draw(st.sampled_from([
        body, dz.Body(body), dz.System(body),
        dz.InertiaDispersion(body, moments=0.05, axes_deg=draw(st.sampled_from([0.0, 2.0])))]))
    kwargs: dict[str, Any] = dict(
        system=system,
        omega0=draw(st.sampled_from([(0.01, 0.01, 1.0), (0.3, -0.2, 1.0), _spin])),
        n=n, seed=draw(st.integers(0, 2**64)), t_end=draw(st.floats(1.0, 50.0)),
        ask=draw(st.sampled_from(["tumbles", "flips", _last_u])),
    )
    method = draw(st.sampled_from([None, "exact", "rk4", "dopri5"]))
    if method is not None:
        kwargs["method"] = method
    if method == "rk4":
        kwargs["dt"] = draw(st.sampled_from([0.01, 0.05]))
    if n > 4 and draw(st.booleans()):
        kwargs["runs"] = draw(st.integers(4, n - 1))
    if draw(st.booleans()):
        kwargs["level"] = draw(st.floats(0.5, 0.999))
    kwargs["interval"] = draw(st.sampled_from(["wilson", "clopper-pearson"]))
    kwargs["chunk"] = draw(valid_int(1, 5))
    kwargs["threads"] = draw(st.sampled_from([None, 1, 2]))
    kwargs["progress"] = draw(st.sampled_from([None, False]))
    return kwargs


def study_hostile() -> dict[str, st.SearchStrategy[Any]]:
    return {
        "system": st.one_of(JUNK, st.sampled_from(["box", (1.0, 2.0), np.eye(3), (1.0, -2.0, 3.0),
                                                   (1.0, 1.0, 5.0), (1.0, math.nan, 1.0)])),
        "omega0": st.one_of(JUNK, st.sampled_from([(1.0, 2.0), (math.nan, 0.0, 1.0), "x",
                                                   np.zeros((2, 3))])),
        "n": hostile_int(1),
        "seed": st.sampled_from([-1, "x", 1.5, [1, -2], object(), True]),
        "t_end": hostile_real(positive=True),
        "ask": st.one_of(JUNK, st.sampled_from(["tumble", "", "FLIPS"])),
        "runs": st.one_of(st.sampled_from([0, 3, -1, 2.5, "x", 8, 100]), JUNK.filter(
            lambda v: v is not None)),
        "level": st.one_of(hostile_real(positive=True), st.sampled_from([1.0, 2.0, 0.0])),
        "interval": st.one_of(JUNK, st.sampled_from(["exact", "Wald"])),
        "chunk": hostile_int(1),
        "threads": hostile_int(1),
        "progress": st.sampled_from([1, 0, "yes", np.array([True])]),
    }


def check_study(kwargs: dict[str, Any], study: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(study, dz.MonteCarlo)
    n = int(kwargs["n"])
    runs = kwargs.get("runs")
    assert study.n == n and study.runs == (n if runs is None else int(runs))
    assert len(study.outcomes) == len(study.samples) == study.runs
    assert (np.diff(study.samples) > 0).all() and study.samples.max() < n
    assert math.isclose(study.weights.sum(), 1.0, rel_tol=1e-12)
    for values in study.inputs.values():
        assert len(values) == study.runs
    if study.is_boolean:
        lo, hi = study.interval
        assert 0 <= lo <= study.p <= hi <= 1
    else:
        assert np.isfinite(study.mean)
    k = int(study.samples[-1])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        traj = study.rerun(k)
    if kwargs["ask"] in ("tumbles", "flips"):
        flips = len(traj.flip_times)
        assert study.outcomes[-1] == (flips > 0 if kwargs["ask"] == "tumbles" else flips)
    else:
        assert study.outcomes[-1] == _last_u(traj)


def inertia_dispersion(body: Any, moments: Any, axes_deg: Any, seed: int) -> dz.Body:
    return dz.InertiaDispersion(body, moments, axes_deg)(np.random.default_rng(seed))


@st.composite
def dispersion_args(draw: st.DrawFn) -> dict[str, Any]:
    body = draw(st.sampled_from(BODIES + [dz.Body.box(20, 10, 15), dz.Body.from_tensor(
        [[2.0, -0.3, 0.0], [-0.3, 2.5, 0.1], [0.0, 0.1, 3.0]])]))
    return dict(body=body, moments=draw(st.one_of(st.floats(0, 0.2), st.lists(
        st.floats(0, 0.2), min_size=3, max_size=3))),
                axes_deg=draw(st.floats(0, 20)), seed=draw(st.integers(0, 2**32)))


def check_body(kwargs: dict[str, Any], body: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(body, dz.Body)
    tensor = body.tensor
    moments = np.linalg.eigvalsh(tensor)
    assert np.array_equal(tensor, tensor.T) and moments.min() > 0
    assert 2 * moments.max() <= moments.sum() * (1 + _core.TRIANGLE_SLACK) * (1 + 1e-12)


def deployment_dispersion(start: Any, duration: Any, moments: Any, seed: int) -> dz.Deployment:
    nominal = dz.Deployment([10.0, 20.0], [(1.0, 2.0, 2.5), (1.0, 2.5, 2.0)])
    return dz.DeploymentDispersion(nominal, start=start, duration=duration,
                                   moments=moments)(np.random.default_rng(seed))


def check_deployment(kwargs: dict[str, Any], d: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(d, dz.Deployment) and (np.diff(d.times) > 0).all()
    for tensor in d.tensors:
        check_body(kwargs, dz.Body.from_tensor(tensor), caught)


def damper_dispersion(inertia: Any, damping: Any, seed: int) -> dz.Damper:
    return dz.DamperDispersion(dz.Damper(0.05, 0.02), inertia=inertia,
                               damping=damping)(np.random.default_rng(seed))


def check_damper(kwargs: dict[str, Any], d: Any, caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(d, dz.Damper) and d.inertia > 0 and d.damping > 0


def part_dispersion(part: Any, damping: Any, stiffness: Any, seed: int) -> dz.System:
    nominal = dz.System(dz.Body.box(1.0, 2.0, 3.0, mass=2.0), parts=[
        dz.Damper(0.05, 0.02),
        dz.SpringMassDamper(0.1, (0.0, 0.0, 0.5), (1.0, 0.0, 0.0), 4.0, 0.2)])
    return dz.PartDispersion(nominal, part, damping=damping,
                             stiffness=stiffness)(np.random.default_rng(seed))


def check_part_dispersion(kwargs: dict[str, Any], s: Any,
                          caught: list[warnings.WarningMessage]) -> None:
    assert isinstance(s, dz.System) and [p.model for p in s.parts] == ["damper", "spring_mass"]
    assert s.parts[0] == dz.Damper(0.05, 0.02)   # the part not named is the nominal one
    assert s.parts[1].damping > 0 and s.parts[1].stiffness > 0


ENTRIES: dict[str, Entry] = {
    "monte_carlo": Entry(
        call=dz.monte_carlo,
        valid=study_args(),
        hostile=study_hostile(),
        check=check_study,
        covers=(dz.monte_carlo, dz.MonteCarlo, dz.StudyError),
        warns=(dz.StepSizeWarning,),
        examples=60,
        min_success=0.9,
    ),
    "InertiaDispersion": Entry(
        call=inertia_dispersion,
        valid=dispersion_args(),
        hostile={"body": st.one_of(JUNK, st.sampled_from(["box", (1.0, -1.0, 2.0), np.eye(3)])),
                 "moments": st.one_of(hostile_real(positive=False), st.sampled_from(
                     [-0.1, (0.1, 0.2), (0.1, -0.1, 0.1)])),
                 "axes_deg": st.one_of(hostile_real(positive=False), st.just(-1.0))},
        check=check_body,
        covers=(dz.InertiaDispersion,),
        warns=(dz.InertiaWarning,),
        min_success=0.9,
    ),
    "DeploymentDispersion": Entry(
        call=deployment_dispersion,
        valid=st.fixed_dictionaries({"start": st.floats(0, 5), "duration": st.floats(0, 0.5),
                                     "moments": st.floats(0, 0.05),
                                     "seed": st.integers(0, 2**32)}),
        hostile={"start": st.one_of(hostile_real(positive=False), st.just(-1.0)),
                 "duration": st.one_of(hostile_real(positive=False), st.just(-0.1)),
                 "moments": st.one_of(hostile_real(positive=False), st.just(-0.1))},
        check=check_deployment,
        covers=(dz.DeploymentDispersion,),
        min_success=0.9,
    ),
    "DamperDispersion": Entry(
        call=damper_dispersion,
        valid=st.fixed_dictionaries({"inertia": st.floats(0, 0.5), "damping": st.floats(0, 0.5),
                                     "seed": st.integers(0, 2**32)}),
        hostile={"inertia": st.one_of(hostile_real(positive=False), st.just(-0.1)),
                 "damping": st.one_of(hostile_real(positive=False), st.just(-0.1))},
        check=check_damper,
        covers=(dz.DamperDispersion,),
        min_success=0.9,
    ),
    "PartDispersion": Entry(
        call=part_dispersion,
        valid=st.fixed_dictionaries({"part": st.sampled_from([1, -1, "spring_mass"]),
                                     "damping": st.floats(0, 0.5),
                                     "stiffness": st.floats(0, 0.5),
                                     "seed": st.integers(0, 2**32)}),
        hostile={"part": st.one_of(JUNK, st.sampled_from([0, 2, -3, "damper", "hinge", True, 0.5])),
                 "damping": st.one_of(hostile_real(positive=False), st.just(-0.1)),
                 "stiffness": st.one_of(hostile_real(positive=False), st.just(-0.1))},
        check=check_part_dispersion,
        covers=(dz.PartDispersion,),
        min_success=0.9,
    ),
}
