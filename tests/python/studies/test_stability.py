"""Stability maps computed by runs, against the closed forms written here with their sources:
the gyrostat's dual-spin rule (Hughes, *Spacecraft Attitude Dynamics*, 1986, ch. 6) and the
gravity-gradient conditions on the moment ratios (Hughes §9.3; DeBra & Delp 1961)."""

import math

import matplotlib
import numpy as np
import pytest

import dzhanibekov as dz

matplotlib.use("Agg")

INERTIA = (1.0, 2.0, 3.0)


def unstable_momenta(inertia, k, rate):
    """Whether a wheel momentum h leaves a spin `rate` about axis k unstable, from the
    equations themselves: the transverse block of the Jacobian of
    f(ω) = I⁻¹ ((I ω + h e_k) × ω) at ω = Ω e_k (central differences; its diagonal is zero),
    whose eigenvalues ±√(J_ij J_ji) are real, one growing, exactly when J_ij J_ji > 0."""
    i, j = [m for m in range(3) if m != k]

    def unstable(h):
        tensor = np.diag(inertia)
        e = np.zeros(3)
        e[k] = 1.0

        def f(w):
            return np.linalg.solve(tensor, np.cross(tensor @ w + h * e, w))

        w0 = rate * e
        jac = np.empty((3, 3))
        for c in range(3):
            d = np.zeros(3)
            d[c] = 1e-6
            jac[:, c] = (f(w0 + d) - f(w0 - d)) / 2e-6
        return jac[i, j] * jac[j, i] > 0

    return unstable


@pytest.mark.parametrize("k", [0, 1, 2])
def test_the_dual_spin_map_agrees_with_the_closed_form_on_both_sides_of_each_threshold(k):
    low, high = dz.dual_spin_threshold(INERTIA, k, 1.0)
    others = [INERTIA[m] - INERTIA[k] for m in range(3) if m != k]
    assert (low, high) == (min(others), max(others))         # Ω (I_i − I_k), Ω (I_j − I_k)
    momenta = [f * t for t in (low, high) if t != 0.0 for f in (0.99, 1.01)]
    unstable = unstable_momenta(INERTIA, k, 1.0)
    m = dz.dual_spin_map(INERTIA, momenta, axes=(k,))
    expected = np.array([not unstable(h) for h in momenta])
    assert expected.any() and not expected.all()            # both sides are tested
    np.testing.assert_array_equal(m.stable[0], expected)
    np.testing.assert_array_equal(m.predicted[0], expected)
    # and clearly: a stable spin wobbles by about the nudge, an unstable one departs
    assert m.departure[0][expected].max() < 0.01
    assert m.departure[0][~expected].min() > 0.1   # 1 % inside: 0.117 rad at the least


def test_without_a_wheel_only_the_intermediate_axis_flips():
    m = dz.dual_spin_map(INERTIA, [0.0], t_end=200.0, frames=201)
    assert m.stable[:, 0].tolist() == [True, False, True]
    assert m.departure[1, 0] > 3.0                         # a flip reverses the spin: π


# -- gravity gradient ----------------------------------------------------------------------


def hughes_stable(k1, k3):
    """Hughes (1986) §9.3, the LVLH equilibrium with roll 1 along-track, pitch 2 along the
    orbit normal, yaw 3 nadir: pitch stable iff k1 > k3; roll–yaw (s⁴ + b n² s² + c n⁴,
    b = 1 + 3k1 + k1k3, c = 4k1k3) iff b > 0, c > 0, b² > 4c."""
    b, c = 1 + 3 * k1 + k1 * k3, 4 * k1 * k3
    return k1 > k3 and b > 0 and c > 0 and b * b > 4 * c


def test_the_moments_have_the_ratios_asked_for():
    k1, k3 = np.array([0.6, -0.05, 0.3]), np.array([0.3, -0.5, -0.7])
    i1, i2, i3 = np.moveaxis(dz.gravity_gradient_moments(k1, k3), -1, 0)
    np.testing.assert_allclose((i2 - i3) / i1, k1, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose((i2 - i1) / i3, k3, rtol=1e-14, atol=1e-15)
    # a body's moments: the triangle inequality holds inside the square
    assert (i1 + i2 >= i3).all() and (i2 + i3 >= i1).all() and (i1 + i3 >= i2).all()


POINTS = [((0.6, 0.3), "lagrange"), ((0.8, 0.5), "lagrange"),
          ((-0.05, -0.5), "debra_delp"), ((-0.03, -0.8), "debra_delp"),
          ((0.3, 0.6), "unstable"),      # pitch: I1 < I3
          ((0.5, -0.5), "unstable"),     # roll–yaw: k1 k3 < 0
          ((-0.3, -0.9), "unstable"),    # roll–yaw: b² < 4c, between the two regions
          ((-0.5, 0.5), "unstable")]


@pytest.mark.parametrize("point, region", POINTS, ids=[r + str(p) for p, r in POINTS])
def test_runs_stay_near_lvlh_exactly_where_the_closed_form_says(point, region):
    k1, k3 = point
    assert str(dz.gravity_gradient_region(k1, k3)) == region
    assert (region != "unstable") == hughes_stable(k1, k3)
    m = dz.gravity_gradient_map([k1], [k3], orbits=10.0, frames=201)
    deviation = m.deviation[0, 0]
    if region == "unstable":
        assert deviation > 0.5, deviation                        # departed
    else:
        assert deviation < 0.1, deviation                        # started at √3·0.01 rad
    assert bool(m.stable[0, 0]) == (region != "unstable")


def test_a_stable_spin_without_momentum_along_its_axis_is_still_stable():
    # h = −I_y Ω: the total angular momentum along the spin axis vanishes; the rates stay by
    # the spin (stable by the closed form), though the axis wanders in space
    m = dz.dual_spin_map(INERTIA, [-2.0], axes=(1,))
    assert m.predicted[0, 0] and m.stable[0, 0] and m.departure[0, 0] < 0.01


def test_the_figures_draw_the_runs_and_the_closed_form():
    from dzhanibekov.plotting import dual_spin_figure, gravity_gradient_figure

    m = dz.dual_spin_map(INERTIA, np.linspace(-2.5, 2.5, 6), t_end=60.0, frames=31)
    fig = dual_spin_figure(m)
    labels = [line.get_label() for line in fig.axes[0].get_lines()]
    assert sum(label.startswith("spin about") for label in labels) == 3
    g = dz.gravity_gradient_map(np.linspace(-0.5, 0.8, 5), np.linspace(-0.8, 0.7, 4),
                                orbits=3.0, frames=41)
    assert g.deviation.shape == (4, 5) and g.region.shape == (4, 5)
    fig = gravity_gradient_figure(g)
    assert fig.axes[0].collections            # the map and the closed form's outline


@pytest.mark.parametrize("call, error, match", [
    (lambda: dz.dual_spin_map(INERTIA, [np.nan]), ValueError, "momenta"),
    (lambda: dz.dual_spin_map(INERTIA, "1"), TypeError, "momenta"),
    (lambda: dz.dual_spin_map(INERTIA, [1.0], axes=(3,)), ValueError, "axes"),
    (lambda: dz.dual_spin_map(INERTIA, [1.0], axes=(1, 1)), ValueError, "axes"),
    (lambda: dz.dual_spin_map(INERTIA, [1.0], rate=0.0), ValueError, "rate"),
    (lambda: dz.dual_spin_map(INERTIA, [1.0], nudge=2.0), ValueError, "nudge"),
    (lambda: dz.dual_spin_map(INERTIA, [1.0], limit=4.0), ValueError, "limit"),
    (lambda: dz.gravity_gradient_map([1.0], [0.0]), ValueError, "k1"),
    (lambda: dz.gravity_gradient_map([0.5], [[0.1]]), ValueError, "k3"),
    (lambda: dz.gravity_gradient_map([0.5], [0.1], orbit_rate=-1.0), ValueError, "orbit_rate"),
    (lambda: dz.gravity_gradient_map([0.5], [0.1], perturbation=1.0), ValueError,
     "perturbation"),
    (lambda: dz.gravity_gradient_region(0.5, np.inf), ValueError, "k3"),
    (lambda: dz.gravity_gradient_moments(-1.0, 0.0), ValueError, "k1"),
])
def test_bad_input_is_refused_by_name(call, error, match):
    with pytest.raises(error, match=match):
        call()
