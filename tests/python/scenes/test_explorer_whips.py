"""The scene ``explorer-1-whips`` (issue 31): Explorer 1 with its four whip antennas as hinged
rods goes from its minor-axis spin to a flat spin. Checked against its sources (the numbers
recomputed here from the NSSDCA data and steel's textbook constants), against the quasi-rigid
energy-sink estimate written here from the physics (not the package's `energy_sink` module),
and against the historical account — to which its damping was FITTED (no source gives it), so
that check says only that the fit holds, not that the model predicts it.

The estimate: the body nutates as the rigid symmetric top it nearly is (moments ``I_a`` about
the long axis, ``I_t`` across, the whips at rest counted), its rate across the axis
``ω_t = H sin θ / I_t`` turning in the body at ``λ = Ω (I_t − I_a) / I_t``, ``Ω = H cos θ / I_a``.
A whip (mass ``m``, length ``L``, hinged at radius ``r``, flapping out of the spin plane) then
obeys ``I_h β̈ + c β̇ + (k + Ω² μ) β = −μ (λ + Ω) ω_t cos λt`` to first order, ``I_h = m L²/3``,
``μ = m L (r/2 + L/3)`` (the rotating frame's moments about the hinge: Euler's, the centrifugal
one, whose first-order part also stiffens the hinge; the Coriolis one is second order). The
four whips dissipate ``P = 2 c λ² F² / ((k + Ω² μ − I_h λ²)² + c² λ²)``, ``F = μ (λ + Ω) ω_t``,
and at constant ``H`` the energy ``T = ½ H² (sin²θ / I_t + cos²θ / I_a)`` falls at ``P``:
``θ' = P / (H² sin θ cos θ (1/I_a − 1/I_t))``, integrated here by scipy at any θ."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import dzhanibekov as dz

SCENE = dz.SCENES["explorer-1-whips"]
# NASA NSSDCA Master Catalog 1958-001A: 13.97 kg, 80.75 in × 6.00 in, 750 rpm
TOTAL, LONG, DIAMETER, RPM = 13.97, 2.03, 0.152, 750.0
# the whips (assumed): steel rods 0.56 m × 1.5 mm; E = 200 GPa, ρ = 7850 kg/m³ (steel)
WHIP, WIRE, E, RHO = 0.56, 1.5e-3, 200e9, 7850.0
ONE_ORBIT = 114.8 * 60  # s (NSSDCA); "after about one orbit" (Bollay, ECL 1006, 1967)


def whips() -> list[dz.Hinge]:
    return [p for p in SCENE.system.parts if isinstance(p, dz.Hinge)]


def moments() -> tuple[float, float, float, float, float]:
    """``I_a``, ``I_t`` of the composite at rest, the hub radius ``r`` and a whip's ``m``,
    ``L``, written from the geometry: a uniform cylinder and four radial rods."""
    w = whips()[0]
    m, length, r = w.mass, 2 * w.length, DIAMETER / 2
    hub = TOTAL - 4 * m
    rod = m * (r * r + r * length + length**2 / 3)  # about the spin axis, from r to r + L
    ia = hub * r * r / 2 + 4 * rod
    it = hub * (3 * r * r + LONG**2) / 12 + 2 * rod  # two rods lie along each transverse axis
    return ia, it, r, m, length


def estimate_times(shares: tuple[float, ...]) -> list[float]:
    """The quasi-rigid estimate's times at which ``sin θ`` reaches each share (module doc)."""
    ia, it, r, m, length = moments()
    w = whips()[0]
    k, c = w.stiffness, w.damping
    ih, mu = m * length**2 / 3, m * length * (r / 2 + length / 3)
    omega0 = np.array(SCENE.omega0)
    h = np.hypot(it * np.hypot(omega0[0], omega0[1]), ia * omega0[2])
    theta0 = np.arctan2(it * np.hypot(omega0[0], omega0[1]), ia * omega0[2])

    def rate(_t: float, y: np.ndarray) -> list[float]:
        th = y[0]
        spin = h * np.cos(th) / ia
        lam = spin * (it - ia) / it
        force = mu * (lam + spin) * h * np.sin(th) / it
        power = 2 * c * lam**2 * force**2 / ((k + spin**2 * mu - ih * lam**2) ** 2
                                              + (c * lam) ** 2)
        return [power / (h * h * np.sin(th) * np.cos(th) * (1 / ia - 1 / it))]

    events = [lambda _t, y, s=s: np.sin(y[0]) - s for s in shares]
    sol = solve_ivp(rate, (0.0, 1e6), [theta0], events=events, rtol=1e-10, atol=1e-12)
    return [float(e[0]) for e in sol.t_events]


def across(traj: dz.Trajectory) -> np.ndarray:
    """The share of ``|H|`` across the long axis z, ``sin θ``, at every frame."""
    h = traj.momentum_body
    return np.hypot(h[:, 0], h[:, 1]) / np.linalg.norm(h, axis=1)


def test_the_scene_holds_its_sources_numbers():
    body = SCENE.system.body
    (w0, w1, w2, w3) = whips()
    assert body.mass + 4 * w0.mass == pytest.approx(TOTAL, rel=1e-12)
    np.testing.assert_allclose(body.inertia[2], (TOTAL - 4 * w0.mass) * (DIAMETER / 2) ** 2 / 2,
                               rtol=1e-12)
    assert SCENE.omega0[2] == pytest.approx(RPM * 2 * np.pi / 60, rel=1e-15)
    # a steel whip: its mass, and its first cantilever mode f = (1.8751²/2π) √(EI/(ρA L⁴))
    area, second = np.pi * WIRE**2 / 4, np.pi * WIRE**4 / 64
    assert w0.mass == pytest.approx(RHO * area * WHIP, rel=0.01)
    f = 1.8751**2 / (2 * np.pi) * np.sqrt(E * second / (RHO * area * WHIP**4))
    end = w0.mass * WHIP**2 / 3
    for w in (w0, w1, w2, w3):
        assert 2 * w.length == pytest.approx(WHIP) and np.hypot(*w.hinge[:2]) == DIAMETER / 2
        assert w.stiffness == pytest.approx((2 * np.pi * f) ** 2 * end, rel=0.01)
        # the fitted damping: 8.5 % of critical
        assert w.damping / (2 * np.sqrt(w.stiffness * end)) == pytest.approx(0.085, rel=1e-9)
        # each hinge normal to the spin axis and to its rod: the flap out of the spin plane
        assert np.dot(w.axis, (0, 0, 1)) == 0 and np.dot(w.axis, w.arm) == 0
    theta0 = np.degrees(np.arctan2(moments()[1] * SCENE.omega0[0],
                                   moments()[0] * SCENE.omega0[2]))
    assert theta0 == pytest.approx(3.9, abs=0.05)


def test_the_nutation_grows_at_the_estimate_s_rate():
    """The first 900 s (sin θ from 0.068 to 0.125, 0.7 s of CPU): ln tan θ grows linearly at
    the estimate's small-angle rate, to 1.2 % (measured): the estimate leaves out the whips'
    own pull on the hub's nutation, which they nearly resonate with."""
    traj = SCENE.run(t_end=900.0, frames=181)
    s = across(traj)
    keep = traj.t >= 150.0
    slope = np.polyfit(traj.t[keep], np.log(np.tan(np.arcsin(s[keep]))), 1)[0]
    t1, t2 = estimate_times((0.08, 0.12))
    expected = np.log(np.tan(np.arcsin(0.12)) / np.tan(np.arcsin(0.08))) / (t2 - t1)
    assert slope == pytest.approx(expected, rel=0.03)


@pytest.mark.slow
def test_the_spin_goes_flat_within_an_orbit():
    """The whole scene (3 s of CPU): 99 % of |H| across the long axis at 6905 s, 0.7–1.2 %
    after the estimate at each share (measured), within an orbit, at the account's spin rate."""
    traj = SCENE.run()
    s = across(traj)
    shares = (0.5, 0.9, 0.99)
    times = [float(traj.t[np.flatnonzero(s >= share)[0]]) for share in shares]
    for run, est in zip(times, estimate_times(shares)):
        assert est < run < 1.03 * est
    # the historical account, to which the damping was fitted: about 90° by one orbit
    assert 0.95 * ONE_ORBIT < times[-1] < 1.05 * ONE_ORBIT
    # not fitted: "the spin rate decreased to about 2 cycles per second" by then
    at = np.flatnonzero(traj.t == times[-1])[0]
    assert 1.5 < np.linalg.norm(traj.omega[at]) / (2 * np.pi) < 2.5
    # flat: at constant |H|, the energy has fallen nearly to the flat spin's, H² / (2 I_t)
    h = np.linalg.norm(traj.momentum_body, axis=1)
    flat = h[-1] ** 2 / (2 * moments()[1])
    assert (traj.energy[-1] - flat) / (traj.energy[0] - flat) < 0.03
    assert np.ptp(h) / h[0] < 1e-3 and traj.drift.momentum_world < 1e-3
