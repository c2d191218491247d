"""Run options typed once in studies and maps (issue 29): ``dz.monte_carlo`` and the maps take
a ``dz.RunOptions`` as ``options=``, their old keywords still work and override it, and no
run option is retyped in their signatures."""

from __future__ import annotations

import dataclasses
import inspect

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov.plotting import maps

TOPS = lambda rng: (1.0, 3.0, rng.uniform(2.7, 3.7))  # noqa: E731
SPIN = (1e-3, 1e-3, 1.0)


@pytest.mark.parametrize("function", [dz.monte_carlo, maps.map_sweep, maps.render_maps])
def test_no_run_option_is_retyped_in_a_signature(function):
    parameters = inspect.signature(function).parameters
    fields = {f.name for f in dataclasses.fields(dz.RunOptions)}
    assert "options" in parameters and not fields & set(parameters)
    assert any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values())


def test_a_study_with_options_is_the_study_with_keywords():
    options = dz.RunOptions(t_end=50.0, method="rk4", dt=0.05, frames=3, threads=1)
    by_options = dz.monte_carlo(TOPS, SPIN, 12, seed=3, options=options)
    by_keywords = dz.monte_carlo(TOPS, SPIN, 12, seed=3, t_end=50.0, method="rk4", dt=0.05,
                                 frames=3, threads=1)
    np.testing.assert_array_equal(by_options.outcomes, by_keywords.outcomes)
    for name in ("t_end", "method", "dt", "frames"):
        assert getattr(by_options, name) == getattr(by_keywords, name)
    assert (by_options.method, by_options.dt, by_options.frames) == ("rk4", 0.05, 3)
    # a keyword overrides its field
    longer = dz.monte_carlo(TOPS, SPIN, 4, seed=3, options=options, t_end=80.0)
    assert longer.t_end == 80.0 and longer.method == "rk4"


def test_without_options_a_study_keeps_its_own_defaults():
    study = dz.monte_carlo(TOPS, SPIN, 4, seed=3, t_end=1e6)
    assert study.method == "exact" and study.frames == 2   # the closed form, one number a run
    # options are taken as they are (RunOptions' own method and frames)
    study = dz.monte_carlo(TOPS, SPIN, 4, seed=3, options=dz.RunOptions(t_end=20.0, dt=0.05))
    assert study.method == "rk4" and study.frames == 201


def test_a_study_s_max_steps_is_an_option_now():
    # it reaches the runs: 1000 steps of 0.05 are refused before any runs, by name
    with pytest.raises(dz.TooLargeError, match=r"more than the limit max_steps = 10"):
        dz.monte_carlo(TOPS, SPIN, 4, seed=3, t_end=50.0, method="rk4", dt=0.05, max_steps=10)


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(), TypeError, r"monte_carlo\(\) needs `t_end`"),
    (dict(t_end=1.0, flips=True), TypeError,
     r"unexpected keyword argument 'flips' \(its run options: t_end"),
    (dict(options={"t_end": 1.0}), TypeError, r"`options` must be a dz.RunOptions, got dict"),
    (dict(options=dz.RunOptions(t_end=-1.0)), ValueError, r"`t_end` must be positive"),
])
def test_bad_options_are_refused_by_name(kwargs, error, match):
    with pytest.raises(error, match=match):
        dz.monte_carlo(TOPS, SPIN, 4, seed=3, **kwargs)


def test_a_map_with_options_is_the_map_with_keywords():
    options = dz.RunOptions(t_end=5.0, dt=0.05, method="rk4", threads=1)
    a = maps.map_sweep("rates", size=3, options=options, progress=False)
    b = maps.map_sweep("rates", size=3, t_end=5.0, dt=0.05, method="rk4", threads=1,
                       progress=False)
    np.testing.assert_array_equal(a.tilt, b.tilt)
    np.testing.assert_array_equal(a.flips, b.flips)
    assert a.t_end == 5.0 and a.dt.max() == 0.05
    # its defaults without options: 200 time units at a step of 0.01
    assert maps.MAP_OPTIONS.t_end == 200.0 and maps.MAP_OPTIONS.dt == 0.01
    with pytest.raises(TypeError, match=r"map_sweep\(\) got an unexpected keyword argument "
                                        r"'frames'"):
        maps.map_sweep("rates", size=3, frames=5)
