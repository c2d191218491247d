"""The energy sinks' references checked against each other (slow: each sympy derivation takes
seconds): Lagrange's equations derived by sympy (sinks_reference.Lagrange) against Routh's
amended potential for small oscillations and against the free swing's quadrature. The package's
parts are checked against these references where they run (phase 2 of issue 31)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq, least_squares

from sinks_reference import Lagrange, amended_frequency, free_swing_time

pytestmark = pytest.mark.slow

HUB, MASS = np.array([2.0, 3.0, 4.0]), 5.0
TIMES = np.linspace(0.0, 60.0, 6001)


def frequency(t, x, guess):
    """The angular frequency of a small sinusoid `x(t)` by a least-squares fit."""
    def residual(p):
        return (p[1] * np.cos(p[0] * t) + p[2] * np.sin(p[0] * t) + p[3] - x) / x.std()
    fit = least_squares(residual, [guess, x[0] - x.mean(), 0.0, x.mean()], xtol=1e-15,
                        ftol=1e-15, gtol=1e-15)
    return fit.x[0]


def test_a_radial_spring_oscillates_at_the_amended_potentials_frequency():
    m, a, k = 0.2, 1.0, 3.0
    mu = m * MASS / (MASS + m)
    ref = Lagrange(HUB, MASS, [dict(kind="spring", mass=m, anchor=[a, 0, 0],
                                    direction=[1.0, 0, 0], stiffness=k, damping=0.0)])
    x0 = mu * a / (k - mu)
    y0 = ref.start([0, 0, 1.0], [1, 0, 0, 0], [[x0 + 1e-5]], [[0.0]])
    h = np.linalg.norm(ref.momentum_world(y0)[0])

    def spin_inertia(x):
        return HUB[2] + mu * (a + x) ** 2

    xe = brentq(lambda x: k * x - h**2 * mu * (a + x) / spin_inertia(x) ** 2, 0.0, 1.0)
    w = amended_frequency(spin_inertia(xe), 0.0, mu, 2 * mu * (a + xe), 2 * mu, k, h)
    measured = frequency(TIMES, ref.coordinates(ref.solve(y0, TIMES), 0), w)
    assert measured == pytest.approx(w, rel=3e-8)  # measured 6e-9


@pytest.mark.parametrize("kind", ["lead-lag hinge", "in-plane pendulum"])
def test_a_swing_in_the_spin_plane_has_the_amended_potentials_frequency(kind):
    # a hinge whose axis is the spin axis, or a pendulum in the spin plane: I(θ), b(θ), j
    radius = 1.0
    if kind == "lead-lag hinge":
        m, arm, js, je, jg, k = 0.2, 0.5, 0.001, 0.02, 0.019, 0.3
        part = dict(kind="hinge", mass=m, moments=[js, je, jg], hinge=[radius, 0, 0],
                    axis=[0, 0, 1.0], arm=[1.0, 0, 0], length=arm, stiffness=k, damping=0.0)
        config, rate = [[1e-5]], [[0.0]]
    else:
        m, arm, je, k = 0.3, 0.4, 0.0, 0.0
        part = dict(kind="slosh", mass=m, pivot=[radius, 0, 0], length=arm, damping=0.0,
                    start=[1.0, 0, 0])
        config, rate = [[1.0, 0, 0]], [[0, 0, 1e-5]]
    ref = Lagrange(HUB, MASS, [part])
    mu = m * MASS / (MASS + m)
    y0 = ref.start([0, 0, 1.0], [1, 0, 0, 0], config, rate)
    h = np.linalg.norm(ref.momentum_world(y0)[0])
    spin = HUB[2] + mu * (radius + arm) ** 2 + je
    w = amended_frequency(spin, mu * arm * (radius + arm) + je, mu * arm**2 + je, 0.0,
                          -2 * mu * radius * arm, k, h)
    y = ref.solve(y0, TIMES)
    x = ref.coordinates(y, 0) if kind == "lead-lag hinge" else ref.coordinates(y, 0)[:, 1]
    assert frequency(TIMES, x, w) == pytest.approx(w, rel=3e-8)  # measured 8e-9, 3e-10


def test_two_flapping_rods_have_johnsons_frequency_on_a_free_hub():
    # two opposite rods flapping together keep the spin about z; their frequency is
    # Johnson's with the hub's share of the mass centre's motion:
    # ω² = (k + Ω² (m ℓ (R + ℓ) + j_g − j_s)) / (m ℓ² + j_e − 2 m² ℓ² / M)
    m, radius, arm, js, je, jg, k = 0.2, 1.0, 0.5, 0.0005, 0.02, 0.018, 0.3
    parts = [dict(kind="hinge", mass=m, moments=[js, je, jg], hinge=[s * radius, 0, 0],
                  axis=[0, s, 0], arm=[s, 0, 0], length=arm, stiffness=k, damping=0.0)
             for s in (1.0, -1.0)]
    ref = Lagrange(HUB, MASS, parts)
    total = MASS + 2 * m
    w = np.sqrt((k + (m * arm * (radius + arm) + jg - js))
                / (m * arm**2 + je - 2 * m**2 * arm**2 / total))
    y = ref.solve(ref.start([0, 0, 1.0], [1, 0, 0, 0], [[1e-5], [1e-5]], [[0.0], [0.0]]),
                  TIMES)
    assert frequency(TIMES, ref.coordinates(y, 0), w) == pytest.approx(w, rel=1e-8)
    assert np.abs(ref.omega(y)[:, :2]).max() < 1e-15  # the spin stays about z


def test_a_free_mass_and_a_free_pendulum_follow_the_quadrature_of_h_and_e():
    times = np.linspace(0.0, 6.0, 61)
    m, a = 0.2, 0.5
    mu = m * MASS / (MASS + m)
    ref = Lagrange(HUB, MASS, [dict(kind="spring", mass=m, anchor=[a, 0, 0],
                                    direction=[1.0, 0, 0], stiffness=0.0, damping=0.0)])
    y0 = ref.start([0, 0, 1.0], [1, 0, 0, 0], [[0.0]], [[0.05]])
    h, e = np.linalg.norm(ref.momentum_world(y0)[0]), ref.energy(y0)[0]
    x = ref.coordinates(ref.solve(y0, times), 0)
    t = [free_swing_time(lambda s: HUB[2] + mu * (a + s) ** 2, lambda s: 0.0, lambda s: mu,
                         h, e, 0.0, xi) for xi in x]
    assert np.abs(np.array(t) - times).max() < 1e-10  # measured 2.2e-12, out to 16 lengths
    m, radius, arm = 0.3, 1.0, 0.4
    mu = m * MASS / (MASS + m)
    ref = Lagrange(HUB, MASS, [dict(kind="slosh", mass=m, pivot=[radius, 0, 0], length=arm,
                                    damping=0.0, start=[0, 1.0, 0])])
    y0 = ref.start([0, 0, 1.0], [1, 0, 0, 0], [[0, 1.0, 0]], [[0, 0, -0.3]])
    h, e = np.linalg.norm(ref.momentum_world(y0)[0]), ref.energy(y0)[0]
    n = ref.coordinates(ref.solve(y0, times), 0)
    psi = np.unwrap(np.arctan2(n[:, 1], n[:, 0]))
    stop = int(np.argmax(np.diff(psi) >= 0)) or len(psi)
    t = [free_swing_time(lambda p: HUB[2] + mu * (radius**2 + arm**2
                                                   + 2 * radius * arm * np.cos(p)),
                         lambda p: mu * arm * (radius * np.cos(p) + arm), lambda p: mu * arm**2,
                         h, e, psi[0], p, sign=-1.0) for p in psi[:stop]]
    assert stop > 20 and np.abs(np.array(t) - times[:stop]).max() < 1e-9  # measured 2.1e-11
