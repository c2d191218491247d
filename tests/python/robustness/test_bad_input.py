"""Bad input: a clear ValueError or TypeError naming the argument, before any big allocation."""

import numpy as np
import pytest

import dzhanibekov as dz

W = (0.01, 0.01, 1.0)


@pytest.mark.parametrize("inertia, match", [
    ((1.0, 0.0, 1.0), "inertia"),
    ((1.0, -2.0, 1.0), "inertia"),
    ((1.0, np.nan, 1.0), "`inertia` must be finite"),
    ((1.0, np.inf, 1.0), "`inertia` must be finite"),
    ((1e-200, 1.0, 1e200), "ratio of largest to smallest"),
    ((1.0, 2.0), r"`inertia` must have shape \(3,\)"),
])
def test_bad_moments(inertia, match):
    with pytest.raises(ValueError, match=match):
        dz.Body(inertia)


def test_moments_no_body_has_warn():
    with pytest.warns(dz.InertiaWarning, match="triangle inequality"):
        dz.Body((1.0, 1.0, 3.0))


@pytest.mark.parametrize("args", [(0, 10, 15), (20, -1, 15), (20, 10, np.inf)])
def test_bad_box(args):
    with pytest.raises(ValueError, match="must be positive and finite"):
        dz.Body.box(*args)


def test_bad_box_mass():
    with pytest.raises(ValueError, match="`mass` must be positive"):
        dz.Body.box(1, 2, 3, mass=0.0)
    with pytest.raises(TypeError, match="`a` must be a real number"):
        dz.Body.box("20", 10, 15)


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(omega0=(np.nan, 0, 1)), ValueError, "`omega0` must be finite"),
    (dict(omega0=(0, np.inf, 1)), ValueError, "`omega0` must be finite"),
    (dict(omega0=(0, 1)), ValueError, r"`omega0` must have shape \(3,\)"),
    (dict(omega0="abc"), TypeError, "`omega0` must hold real numbers"),
    (dict(q0=(0, 0, 0, 0)), ValueError, "`q0` must be a non-zero quaternion"),
    (dict(q0=(1, 0, 0)), ValueError, r"`q0` must have shape \(4,\)"),
    (dict(q0=(1, 0, np.nan, 0)), ValueError, "`q0` must be finite"),
    (dict(dt=0.0), ValueError, "`dt` must be positive and finite"),
    (dict(dt=-1e-3), ValueError, "`dt` must be positive and finite"),
    (dict(dt=np.nan), ValueError, "`dt` must be positive and finite"),
    (dict(dt="0.1"), TypeError, "`dt` must be a real number"),
    (dict(t_end=0.0), ValueError, "`t_end` must be positive and finite"),
    (dict(t_end=-5.0), ValueError, "`t_end` must be positive and finite"),
    (dict(t_end=np.inf), ValueError, "`t_end` must be positive and finite"),
    (dict(frames=1), ValueError, "`frames` must be at least 2"),
    (dict(frames=2.5), TypeError, "`frames` must be an integer"),
    (dict(frames=True), TypeError, "`frames` must be an integer"),
    (dict(method="euler"), ValueError, "`method` must be one of"),
    (dict(frames=10**13), ValueError, "more than this machine's"),
    (dict(t_end=1e300), ValueError, r"t_end / dt = 1e300 / .* overflows"),
    (dict(max_steps=0), ValueError, "`max_steps` must be at least 1"),
])
def test_bad_simulate_arguments(paper_body, kwargs, error, match):
    args = dict(omega0=W)
    args.update(kwargs)
    with pytest.raises(error, match=match):
        dz.simulate(paper_body, **args)


def test_a_step_far_beyond_stability_is_an_error_not_nan(paper_body):
    with pytest.warns(dz.StepSizeWarning, match="stability limit"):
        with pytest.raises(ValueError, match="diverged"):
            dz.simulate(paper_body, (3.0, 5.0, 40.0), t_end=1e3, frames=2, dt=10.0)


def test_max_steps_bounds_the_run(paper_body):
    with pytest.raises(ValueError, match="1.000e6 steps"):
        dz.simulate(paper_body, W, t_end=1000.0, dt=1e-3, max_steps=999_999)
    assert dz.simulate(paper_body, W, t_end=1000.0, dt=1e-3, max_steps=10**6).n_steps == 10**6


@pytest.mark.parametrize("q, points, error, match", [
    (np.zeros((3, 4)), np.ones((2, 3)), ValueError, "`q` rows must be non-zero"),
    (np.ones((3, 3)), np.ones((2, 3)), ValueError, r"`q` must have shape \(N, 4\)"),
    (np.ones((3, 4)), np.ones((2, 2)), ValueError, r"`points` must have shape \(P, 3\)"),
    (np.ones((3, 4)), np.full((2, 3), np.nan), ValueError, "`points` must be finite"),
    (np.full((3, 4), np.inf), np.ones((2, 3)), ValueError, "`q` must be finite"),
    (np.ones((3, 4), dtype=complex), np.ones((2, 3)), TypeError, "`q` must hold real numbers"),
    (np.ones((2, 3, 4)), np.ones((2, 3)), ValueError, r"`q` must have shape \(N, 4\)"),
    (np.ones((10**6, 4)), np.ones((10**6, 3)), ValueError, "more than this machine's"),
])
def test_bad_rotate_arguments(q, points, error, match):
    with pytest.raises(error, match=match):
        dz.rotate(q, points)


def test_strided_and_integer_input_is_accepted():
    q = np.zeros((4, 8))
    q[:, ::2] = [1, 0, 0, 1]
    points = np.arange(12).reshape(4, 3)
    np.testing.assert_allclose(dz.rotate(q[:, ::2], points), dz.rotate(np.tile([1.0, 0, 0, 1], (4, 1)), points.astype(float)))


@pytest.mark.parametrize("name, value", [("t_end", np.timedelta64(5, "s")),
                                         ("dt", np.timedelta64(5, "ms")),
                                         ("frames", np.timedelta64(5, "s")),
                                         ("t_end", np.datetime64("2026-01-01"))])
def test_numpy_times_are_refused_clearly(paper_body, name, value):
    """`t_end=np.timedelta64(5, "s")` (a NumPy integer to `numbers`) was not refused clearly:
    float() of it failed on a `datetime.timedelta`."""
    with pytest.raises(TypeError, match=rf"`{name}` must be .*numpy\.(timedelta64|datetime64)"
                                        r".*plain numbers in the user's own unit"):
        dz.simulate(paper_body, (0.01, 0.01, 1.0), **{name: value})


def test_messages_of_huge_spans_and_tiny_times_are_short_and_true(paper_body):
    """`t_end=1e300` said "needs inf steps"; a divergence time was printed as a 300-digit
    decimal (Rust's Display of f64)."""
    import warnings

    with pytest.raises(dz.TooLargeError, match=r"more steps than float64 counts \(t_end / dt "
                                               r"= 1e300 / .* overflows\)") as caught:
        dz.simulate(paper_body, (0.01, 0.01, 1.0), t_end=1e300)
    assert "inf steps" not in str(caught.value) and "raise max_steps" not in str(caught.value)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.StepSizeWarning)
        with pytest.raises(dz.DivergedError, match=r"at t = 1e-28\d:") as caught:
            dz.simulate(paper_body, (1e290, 1e290, 1e290), t_end=1e-280, dt=1e-280)
    assert len(str(caught.value)) < 200
