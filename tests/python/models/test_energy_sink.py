"""The quasi-rigid energy-sink estimate (dzhanibekov.energy_sink) against what it must
reproduce, derived by hand: the classic axial spring–mass nutation damper's dissipated power,
and each sink's small-oscillation frequencies on a heavy spinning body (the centrifugal
pendulum, the flapping rod with hinge offset). Its agreement with the full motion in the
small-damper limit is checked against the sympy reference (slow)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from dzhanibekov import energy_sink

HUB = np.diag([1.0, 1.0, 0.5])  # a minor-axis spinner about z


def spring(**kw):
    base = dict(mass=0.01, anchor=[0.4, 0.0, 0.0], direction=[0.0, 0.0, 1.0],
                stiffness=0.0144, damping=0.0048)
    return SimpleNamespace(**{**base, **kw})


def test_the_axial_damper_dissipates_the_forced_oscillators_power():
    # A mass at (b, 0, 0) sliding along z on a body nutating at λ in its own axes:
    # m ẍ + c ẋ + k x = m b ω_t (λ − Ω) cos λt (its axial acceleration to first order in ω_t),
    # so p̄ = P / ω_t² = ½ c λ² m² b² (λ − Ω)² / ((k − m λ²)² + c² λ²)
    part = spring()
    est = energy_sink.estimate(HUB, 10.0, [("spring_mass", part)], [0.002, 0.0, 2.0])
    lam, spin = est.nutation, est.spin
    m, b, k, c = part.mass, 0.4, part.stiffness, part.damping
    closed = 0.5 * c * lam**2 * m**2 * b**2 * (lam - spin) ** 2 / ((k - m * lam**2) ** 2
                                                                    + (c * lam) ** 2)
    assert est.powers[0] == pytest.approx(closed, rel=1e-12)
    # the body: λ = Ω (I_a − I_t) / I_t of the composite, and a spin about the minor axis grows
    assert lam == pytest.approx(spin * (est.axial - est.transverse) / est.transverse, rel=1e-14)
    assert est.time_constant > 0
    # about the major axis the same damper makes the nutation decay
    flat = energy_sink.estimate(np.diag([0.5, 0.5, 1.0]), 10.0, [("spring_mass", part)],
                                [0.002, 0.0, 2.0])
    assert flat.time_constant < 0


def test_a_radial_spring_softens_by_the_centrifugal_field():
    # along a radius the spring feels k − m Ω²: ω² = k/m − Ω²
    part = spring(direction=[1.0, 0.0, 0.0], stiffness=0.09)
    (w,) = energy_sink.frequencies("spring_mass", part, [0.0, 0.0, 2.0])
    assert w == pytest.approx(np.sqrt(0.09 / 0.01 - 4.0), rel=1e-12)


def test_a_pendulum_swings_at_the_centrifugal_pendulums_frequencies():
    # pivot at R from the spin axis, rod l: in the spin plane Ω √(R/l) (Den Hartog's
    # centrifugal pendulum), across it Ω √(1 + R/l)
    tank = SimpleNamespace(mass=0.02, pivot=[0.3, 0.0, 0.0], length=0.15, damping=0.0)
    w = energy_sink.frequencies("slosh", tank, [0.0, 0.0, 2.0])
    assert w == pytest.approx([2.0 * np.sqrt(0.3 / 0.15), 2.0 * np.sqrt(1 + 0.3 / 0.15)],
                              rel=1e-12)


def test_a_flapping_rod_has_johnsons_frequency_with_hinge_offset():
    # a uniform rod of length L hinged at radius R flapping out of the spin plane:
    # ω² = k / (m L²/3) + Ω² (1 + 3R / (2L)) (Johnson, Helicopter Theory, the flap frequency)
    m, length, radius, k = 0.01, 0.6, 0.3, 0.002
    rod = SimpleNamespace(mass=m, moments=[0.0, m * length**2 / 12, m * length**2 / 12],
                          hinge=[radius, 0.0, 0.0], axis=[0.0, 1.0, 0.0], arm=[1.0, 0.0, 0.0],
                          length=length / 2, stiffness=k, damping=0.0)
    (w,) = energy_sink.frequencies("hinge", rod, [0.0, 0.0, 2.0])
    expected = np.sqrt(k / (m * length**2 / 3) + 4.0 * (1 + 1.5 * radius / length))
    assert w == pytest.approx(expected, rel=1e-12)
    # with its axis along the spin (lead-lag) a point mass swings at Ω √(R/ℓ) + its spring
    point = SimpleNamespace(mass=m, moments=[0.0, 0.0, 0.0], hinge=[radius, 0.0, 0.0],
                            axis=[0.0, 0.0, 1.0], arm=[1.0, 0.0, 0.0], length=0.2,
                            stiffness=k, damping=0.0)
    (w,) = energy_sink.frequencies("hinge", point, [0.0, 0.0, 2.0])
    assert w == pytest.approx(np.sqrt(k / (m * 0.04) + 4.0 * radius / 0.2), rel=1e-12)


def test_a_pendulum_pivoted_on_the_spin_axis_is_refused():
    tank = SimpleNamespace(mass=0.02, pivot=[0.0, 0.0, 0.3], length=0.15, damping=0.01)
    with pytest.raises(ValueError, match="pivoted on the spin axis"):
        energy_sink.estimate(HUB, 10.0, [("slosh", tank)], [0.002, 0.0, 2.0])


def _nutation_time_constant(reference, y, times):
    """The growth time of the angle between the angular momentum and the body's z axis, by a
    straight line through its logarithm while it is below 0.1 rad."""
    h = reference.momentum_world(y[:1])[0]
    axes = np.array([np.asarray(reference._rot(s[: reference.n], s[reference.n:]), float)
                     for s in y])[:, :, 2]
    theta = np.arccos(axes @ h / np.linalg.norm(h))
    keep = theta < 0.1
    return 1.0 / np.polyfit(times[keep], np.log(theta[keep]), 1)[0]


@pytest.mark.slow
def test_the_estimate_is_the_small_damper_limit_of_the_full_motion():
    # the full motion by Lagrange's equations (sympy, DOP853): the estimate's error falls
    # with the damper (measured −0.45 % at s = 1, −0.12 % at s = ½)
    from sinks_reference import Lagrange

    errors = []
    for s in (1.0, 0.5):
        part = spring(mass=0.01 * s, stiffness=0.0144 * s, damping=0.0048 * s)
        w0 = [0.02, 0.0, 2.0]
        est = energy_sink.estimate(HUB, 10.0, [("spring_mass", part)], w0)
        reference = Lagrange(HUB, 10.0, [dict(kind="spring", **vars(part))])
        times = np.linspace(0.0, 1.6 * est.time_constant, 3001)
        y = reference.solve(reference.start(w0, [1, 0, 0, 0], [[0.0]], [[0.0]]), times,
                            rtol=1e-10, atol=1e-12)
        errors.append(abs(est.time_constant / _nutation_time_constant(reference, y, times) - 1))
    assert errors[0] < 0.01 and errors[1] < 0.6 * errors[0], errors
