"""Run options typed once (issue 29): `dz.RunOptions` is taken by simulate, summarize and
sweep as ``options=``, its fields overridden by the keywords of before (which still work);
`simulate` has at most 10 parameters."""

from __future__ import annotations

import inspect
import pickle

import numpy as np
import pytest

import dzhanibekov as dz

BODY = dz.Body((1.0, 2.0, 3.0))
W0 = (0.01, 1.0, 0.01)
OPTIONS = dz.RunOptions(t_end=20.0, frames=5, method="dop853", rtol=1e-10)


def test_simulate_takes_at_most_ten_parameters():
    assert len(inspect.signature(dz.simulate).parameters) <= 10
    for function in (dz.simulate, dz.summarize, dz.sweep):
        assert "options" in inspect.signature(function).parameters


def test_options_and_keywords_make_the_same_run():
    by_options = dz.simulate(BODY, W0, options=OPTIONS)
    by_keywords = dz.simulate(BODY, W0, t_end=20.0, frames=5, method="dop853", rtol=1e-10)
    assert by_options.method == "dop853" and len(by_options.t) == 5
    np.testing.assert_array_equal(by_options.q, by_keywords.q)
    # a keyword overrides the options' field
    shorter = dz.simulate(BODY, W0, options=OPTIONS, t_end=2.0)
    assert float(shorter.t[-1]) == 2.0 and shorter.method == "dop853"


def test_summarize_and_sweep_take_the_same_options():
    traj = dz.simulate(BODY, W0, options=OPTIONS)
    summary = dz.summarize(BODY, W0, options=OPTIONS)
    np.testing.assert_array_equal(summary.flip_times, traj.flip_times)
    swept = dz.sweep(BODY, [W0, W0], options=OPTIONS)
    assert list(swept.flips) == [len(traj.flip_times)] * 2


def test_options_are_a_value():
    assert pickle.loads(pickle.dumps(OPTIONS)) == OPTIONS
    assert OPTIONS.replace(frames=7) == dz.RunOptions(t_end=20.0, frames=7, method="dop853",
                                                       rtol=1e-10)
    with pytest.raises(AttributeError):
        OPTIONS.t_end = 1.0  # type: ignore[misc]


@pytest.mark.parametrize("call, message", [
    (lambda: dz.simulate(BODY, W0, t_ned=1.0), r"simulate\(\) got an unexpected keyword "
                                                r"argument 't_ned' \(its run options: t_end"),
    (lambda: dz.summarize(BODY, W0, flips=False), r"summarize\(\) got an unexpected keyword "
                                                   r"argument 'flips'"),
    (lambda: dz.sweep(BODY, W0, flips=False), r"sweep\(\) got an unexpected keyword"),
    (lambda: dz.simulate(BODY, W0, options={"t_end": 1.0}), r"`options` must be a "
                                                            r"dz.RunOptions, got dict"),
    (lambda: OPTIONS.replace(step=1.0), r"replace\(\) got an unexpected keyword"),
])
def test_a_bad_option_is_refused_by_name(call, message):
    with pytest.raises(TypeError, match=message):
        call()


def test_an_option_of_a_bad_value_is_refused_as_before():
    with pytest.raises(ValueError, match="t_end"):
        dz.simulate(BODY, W0, options=dz.RunOptions(t_end=-1.0))
    with pytest.raises(TypeError, match="`frames`"):
        dz.simulate(BODY, W0, frames=2.5)
