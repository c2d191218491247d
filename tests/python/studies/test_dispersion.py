"""Dispersions draw physical bodies, deployments and dampers with the spread they state.

Every tolerance is a number of standard errors of the quantity tested (4 unless said), computed
from the normal law the dispersion states; the references are numpy's own eigen-decomposition
and the Maxwell law of the angle of a normal rotation vector (scipy.stats.maxwell).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

import dzhanibekov as dz
from dzhanibekov import _core

DRAWS = 2000


def physical(tensor: np.ndarray) -> bool:
    """Symmetric, positive definite, its eigenvalues keeping the triangle inequality."""
    if not np.array_equal(tensor, tensor.T):
        return False
    moments = np.linalg.eigvalsh(tensor)
    total = moments.sum()
    return bool(moments.min() > 0 and 2 * moments.max() <= total * (1 + _core.TRIANGLE_SLACK))


def test_moments_have_the_mean_and_spread_asked_for():
    nominal = np.array([1.0, 2.0, 2.5])
    spread = np.array([0.05, 0.02, 0.04])
    disperse = dz.InertiaDispersion(dz.Body(nominal), moments=spread)
    rng = np.random.default_rng(1)
    drawn = np.array([disperse(rng).inertia for _ in range(DRAWS)])
    sd = spread * nominal
    # the mean within 4 standard errors σ/√N; the standard deviation within 4 of σ/√(2N)
    assert (np.abs(drawn.mean(axis=0) - nominal) < 4 * sd / math.sqrt(DRAWS)).all()
    assert (np.abs(drawn.std(axis=0, ddof=1) - sd) < 4 * sd / math.sqrt(2 * DRAWS)).all()
    # independent moments: no correlation beyond 4/√N
    corr = np.corrcoef(drawn.T)
    assert (np.abs(corr[np.triu_indices(3, 1)]) < 4 / math.sqrt(DRAWS)).all()


def test_the_axes_turn_by_the_maxwell_law_of_a_normal_rotation_vector():
    disperse = dz.InertiaDispersion((1.0, 2.0, 3.0), moments=0.01, axes_deg=2.0)
    rng = np.random.default_rng(2)
    angles = []
    for _ in range(DRAWS):
        body = disperse(rng)
        assert physical(body.tensor)
        axes = body.principal_axes   # near ±e_k (the moments stay in their order)
        signs = np.sign(np.diag(axes))
        turn = axes * signs           # a proper rotation near the identity
        angles.append(math.degrees(math.acos(np.clip((np.trace(turn) - 1) / 2, -1, 1))))
    law = stats.maxwell(scale=2.0)
    angles = np.array(angles)
    assert abs(angles.mean() - law.mean()) < 4 * law.std() / math.sqrt(DRAWS)
    # and the whole law, by Kolmogorov–Smirnov
    assert stats.kstest(angles, law.cdf).pvalue > 1e-3


def test_bodies_at_the_edge_stay_physical():
    # a flat plate: I_z = I_x + I_y exactly, so half of a plain normal law would break it
    plate = dz.Body.box(2.0, 1.0, 0.0001)
    disperse = dz.InertiaDispersion(plate, moments=0.05, axes_deg=5.0)
    rng = np.random.default_rng(3)
    for _ in range(500):
        assert physical(disperse(rng).tensor)


def test_a_spread_that_leaves_no_physical_body_is_refused():
    # a thin rod: I_x ≪ I_y = I_z, so I_y and I_z dispersed apart by more than I_x break the
    # triangle inequality in all but about 1e-5 of the draws
    disperse = dz.InertiaDispersion((1e-6, 1.0, 1.0), moments=0.05)
    with pytest.raises(ValueError, match="no physical body"):
        disperse(np.random.default_rng(0))


def test_the_same_generator_gives_the_same_body():
    disperse = dz.InertiaDispersion(dz.Body.box(20, 10, 15), moments=0.03, axes_deg=1.0)
    a = disperse(np.random.default_rng(7))
    b = disperse(np.random.default_rng(7))
    assert a == b


def test_a_deployment_is_shifted_and_stretched_as_stated():
    nominal = dz.Deployment([100.0, 110.0, 130.0], [(1, 2, 3), (1, 2.5, 2.5), (1, 3, 2)])
    disperse = dz.DeploymentDispersion(nominal, start=4.0, duration=0.1)
    rng = np.random.default_rng(4)
    times = np.array([disperse(rng).times for _ in range(DRAWS)])
    shift = times[:, 0] - 100.0
    stretch = (times[:, 2] - times[:, 0]) / 30.0
    assert abs(shift.mean()) < 4 * 4.0 / math.sqrt(DRAWS)
    assert abs(shift.std(ddof=1) - 4.0) < 4 * 4.0 / math.sqrt(2 * DRAWS)
    assert abs(stretch.mean() - 1.0) < 4 * 0.1 / math.sqrt(DRAWS)
    assert abs(stretch.std(ddof=1) - 0.1) < 4 * 0.1 / math.sqrt(2 * DRAWS)
    # every knot stretched by the same factor
    assert np.allclose((times[:, 1] - times[:, 0]) / 10.0, stretch, rtol=1e-12)


def test_a_deployments_knots_are_dispersed_bodies():
    # bodies six spreads from the triangle's edge, where the truncation changes nothing
    nominal = dz.Deployment([1.0, 2.0], [(1.5, 2, 3), (1.5, 3, 2)])
    disperse = dz.DeploymentDispersion(nominal, moments=0.02, axes_deg=1.0)
    rng = np.random.default_rng(5)
    drawn = [disperse(rng) for _ in range(1000)]
    assert all(physical(t) for d in drawn for t in d.tensors)
    last = np.array([np.linalg.eigvalsh(d.tensors[-1]) for d in drawn])
    # the deployed moments (ascending: 1.5, 2, 3) with their relative spread of 2%
    nominal_sorted = np.array([1.5, 2.0, 3.0])
    sd = 0.02 * nominal_sorted
    assert (np.abs(last.mean(axis=0) - nominal_sorted) < 4 * sd / math.sqrt(1000)).all()
    assert np.array_equal(drawn[0].times, nominal.times)


def test_a_damper_is_dispersed_as_stated():
    disperse = dz.DamperDispersion(dz.Damper(0.05, 0.02), inertia=0.1, damping=0.3)
    rng = np.random.default_rng(6)
    drawn = [disperse(rng) for _ in range(DRAWS)]
    j = np.array([d.inertia for d in drawn])
    c = np.array([d.damping for d in drawn])
    assert abs(j.mean() - 0.05) < 4 * 0.005 / math.sqrt(DRAWS)
    assert abs(j.std(ddof=1) - 0.005) < 4 * 0.005 / math.sqrt(2 * DRAWS)
    # truncated at 0 (3.3 spreads away: a share of 5e-4 redrawn), the mean barely moves
    assert abs(c.mean() - 0.02) < 4 * 0.006 / math.sqrt(DRAWS) and (c > 0).all()
    # no damping stays none
    assert dz.DamperDispersion(dz.Damper(0.05, 0.0), damping=0.3)(rng).damping == 0.0


@pytest.mark.parametrize("make, match", [
    (lambda: dz.InertiaDispersion((1, 2, 3), moments=-0.1), "`moments` must be non-negative"),
    (lambda: dz.InertiaDispersion((1, 2, 3), moments=(0.1, 0.2)), "`moments` must have shape"),
    (lambda: dz.InertiaDispersion((1, 2, 3), axes_deg=-1.0), "`axes_deg` must be non-negative"),
    (lambda: dz.InertiaDispersion((1, 2, 3), axes_deg=math.nan), "`axes_deg` must be finite"),
    (lambda: dz.DeploymentDispersion(dz.Deployment([1.0], [(1, 2, 3)]), start=-1.0),
     "`start` must be non-negative"),
    (lambda: dz.DamperDispersion(dz.Damper(0.1, 0.1), damping=-0.1),
     "`damping` must be non-negative"),
])
def test_bad_spreads_are_refused(make, match):
    with pytest.raises(ValueError, match=match):
        make()


@pytest.mark.parametrize("make, match", [
    (lambda: dz.InertiaDispersion("box"), "`body` must be a Body"),
    (lambda: dz.DeploymentDispersion((1, 2, 3)), "`deployment` must be a dz.Deployment"),
    (lambda: dz.DamperDispersion(0.1), "`damper` must be a dz.Damper"),
])
def test_the_wrong_kind_of_nominal_is_refused(make, match):
    with pytest.raises((TypeError, ValueError), match=match):
        make()
