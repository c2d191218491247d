"""The exact solution (method="exact") and the flip period against what the code cannot fake:
mpmath for the Jacobi functions and for ω(t) to 50 digits, scipy's DOP853 and an
extended-precision Taylor integrator for the whole state, the flip times RK4 measures, the
symmetric top's and the separatrix's own closed forms, and the invariants."""

import itertools
import warnings

import mpmath as mp
import numpy as np
import pytest
from reference import ExactOmegaMP, dop853, taylor_longdouble

import dzhanibekov as dz
from dzhanibekov import _core

EPS = np.finfo(float).eps


def scaled(y, ref, scale):
    return np.max(np.abs(y - ref)) / scale


def qmul(a, b):
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return np.array([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3, a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1, a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0])


def qexp(v):
    """The unit quaternion of the rotation vector `v` (angle |v| about v/|v|)."""
    angle = np.linalg.norm(v)
    if angle == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * np.asarray(v) / angle])


def regime(inertia, omega0):
    """+1 for L² > 2E I_mid (orbits about the major axis), −1 below, 0 on the separatrix."""
    inertia, omega0 = np.asarray(inertia, float), np.asarray(omega0, float)
    i_mid = np.sort(inertia)[1]
    return np.sign(np.sum(inertia * (inertia - i_mid) * omega0**2))


# --- the Jacobi functions, carrying m1 = 1 − m ---------------------------------------------


@pytest.mark.parametrize("m1", [0.5, 1e-3, 1e-6, 1e-9, 1e-11, 1e-13, 1e-15])
def test_jacobi_functions_match_mpmath_near_m_one_and_far_past_k(m1):
    m = 1.0 - m1
    k = _core.ellipk(m, m1)
    with mp.workdps(60):
        exact_m = 1 - mp.mpf(m1)  # the m whose complement is exactly the float m1
        assert abs(k - mp.ellipk(exact_m)) <= 4 * EPS * k
        u = k * np.array([0.0, 0.1, 0.5, 0.77, 0.999, 1.0, 1.001, 1.5, 2.0, 2.3, 3.0, 9.0, 10.0,
                          10.5, 11.0, -1.0, -6.2, 25.0])
        ref = np.array([[float(mp.ellipfun(f, mp.mpf(x), m=exact_m)) for f in ("sn", "cn", "dn")]
                        for x in u])
    got = np.stack(_core.ellipj(u, m, m1), axis=-1)
    # A float argument u is itself uncertain by |u| ε; the functions have slopes ≤ 1.
    tol = 4 * EPS * (1 + np.abs(u))
    assert np.all(np.abs(got - ref) <= tol[:, None]), np.abs(got - ref).max(axis=0)
    # dn to a relative accuracy, down to its minimum √m1 at odd multiples of K
    assert np.all(np.abs(got[:, 2] - ref[:, 2]) <= 1e-12 * ref[:, 2])


def test_jacobi_functions_at_the_circular_and_separatrix_ends():
    u = np.linspace(-7.0, 7.0, 29)
    sn, cn, dn = _core.ellipj(u, 0.0, 1.0)
    np.testing.assert_allclose(np.stack([sn, cn, dn]), [np.sin(u), np.cos(u), np.ones_like(u)],
                               rtol=0, atol=4 * EPS)
    sn, cn, dn = _core.ellipj(u, 1.0, 0.0)
    np.testing.assert_allclose(np.stack([sn, cn, dn]),
                               [np.tanh(u), 1 / np.cosh(u), 1 / np.cosh(u)], rtol=4 * EPS, atol=0)
    assert _core.ellipk(1.0, 0.0) == np.inf
    with pytest.raises(ValueError, match="`m` and `m1`"):
        _core.ellipk(1.5, -0.5)


# --- ω and q against independent references --------------------------------------------------


def physical_moments(rng):
    """Principal moments of some mass distribution: (b + c, a + c, a + b) for a, b, c > 0."""
    a, b, c = rng.uniform(0.2, 2.0, size=3)
    return np.array([b + c, a + c, a + b])


@pytest.mark.parametrize("perm", list(itertools.permutations(range(3))))
def test_exact_matches_dop853_in_both_regimes_for_every_axis_ordering(rng, perm):
    sorted_moments = np.sort(physical_moments(rng))
    inertia = sorted_moments[list(perm)]
    minor, major = perm.index(0), perm.index(2)
    for axis, expected in ((major, 1), (minor, -1)):
        omega0 = 0.4 * rng.normal(size=3)
        omega0[axis] = rng.choice([-1.0, 1.0]) * rng.uniform(0.8, 1.2)
        assert regime(inertia, omega0) == expected
        q0 = rng.normal(size=4)
        traj = dz.simulate(dz.Body(inertia), omega0, q0, t_end=20.0, frames=41, method="exact")
        omega, q = dop853(inertia, omega0, q0, traj.t)
        assert scaled(traj.omega, omega, np.abs(omega0).max()) <= 1e-11
        assert scaled(traj.q, q, 1.0) <= 1e-11
        assert traj.n_steps == traj.nfev == 0 and traj.dt == 0.0


@pytest.mark.parametrize("name", ["example", "fig3a", "fig3b", "fig3c"])
def test_exact_omega_matches_mpmath_to_1e_12_up_to_t_1000_on_the_papers_cases(name):
    s = dz.SCENES[name]
    traj = dz.simulate(s.body, s.omega0, t_end=1000.0, frames=201, method="exact")
    ref = ExactOmegaMP(s.inertia, s.omega0)(traj.t)
    assert scaled(traj.omega, ref, np.abs(s.omega0).max()) <= 1e-12


@pytest.mark.parametrize("name, t_end", [("fig3a", 1000.0), ("fig3b", 1000.0), ("fig3c", 1000.0),
                                         ("example", 90.0)])
@pytest.mark.skipif(np.finfo(np.longdouble).eps > 1e-18, reason="longdouble is float64 here")
def test_exact_state_matches_extended_precision_taylor_to_1e_12(name, t_end):
    # The Taylor reference runs in longdouble (ε ≈ 1e-19). On the paper's example
    # (u0 = v0 = 5e-6) each pass near the unstable axis amplifies its round-off, so its own
    # error reaches 1e-13 by t = 95 and 1e-7 by t = 1000; there ω is checked against
    # mpmath to t = 1000 above, and q by eq. 1 between frames and by the invariants below.
    s = dz.SCENES[name]
    traj = dz.simulate(s.body, s.omega0, s.q0, t_end=t_end, frames=201, method="exact")
    omega, q = taylor_longdouble(s.inertia, s.omega0, s.q0, traj.t,
                                 h=0.25 if name == "fig3a" else 0.5)
    assert scaled(traj.omega, omega, np.abs(s.omega0).max()) <= 1e-12
    assert scaled(traj.q, q, 1.0) <= 1e-12


def test_papers_example_satisfies_eq_1_between_frames_to_t_1000():
    # Restarted at each frame, DOP853 must land on the next frame: ω and q obey eq. 1
    # everywhere, including the attitude about L that only the exact method keeps there.
    s = dz.SCENES["example"]
    traj = dz.simulate(s.body, s.omega0, t_end=1000.0, frames=101, method="exact")
    for i in range(0, 100, 7):
        omega, q = dop853(s.inertia, traj.omega[i], traj.q[i], traj.t[i:i + 2])
        assert np.abs(omega[-1] - traj.omega[i + 1]).max() <= 1e-12
        assert np.abs(q[-1] - traj.q[i + 1]).max() <= 1e-12


@pytest.mark.parametrize("name", ["example", "fig3a", "fig3b", "fig3c", "random"])
def test_invariants_hold_to_round_off_at_t_1e6(name, rng):
    if name == "random":
        inertia, omega0, q0 = physical_moments(rng), rng.normal(size=3), rng.normal(size=4)
    else:
        s = dz.SCENES[name]
        inertia, omega0, q0 = s.inertia, s.omega0, s.q0
    traj = dz.simulate(dz.Body(inertia), omega0, q0, t_end=1e6, frames=201, method="exact")
    inv = traj.invariants()
    e0, l0 = inv["energy"][0], np.linalg.norm(inv["momentum_body"][0])
    assert np.abs(inv["energy"] / e0 - 1).max() <= 16 * EPS
    assert np.abs(np.linalg.norm(inv["momentum_body"], axis=1) / l0 - 1).max() <= 16 * EPS
    assert np.abs(inv["momentum_world"] - inv["momentum_world"][0]).max() <= 16 * EPS * l0
    assert np.abs(inv["q_norm"] - 1).max() <= 4 * EPS
    assert max(traj.drift) <= 16 * EPS


def test_restarting_from_a_late_state_continues_the_same_motion(rng):
    # The flow property x(t1 + t2; x0) = x(t2; x(t1; x0)) with t1 = 1e6: the late state,
    # refitted from scratch, must continue the same motion.
    inertia, omega0, q0 = physical_moments(rng), rng.normal(size=3), rng.normal(size=4)
    body = dz.Body(inertia)
    far = dz.simulate(body, omega0, q0, t_end=1e6 + 50.0, frames=2, method="exact")
    mid = dz.simulate(body, omega0, q0, t_end=1e6, frames=2, method="exact")
    rest = dz.simulate(body, mid.omega[-1], mid.q[-1], t_end=50.0, frames=2, method="exact")
    # t = 1e6 itself is known to 1e6 ε ≈ 2e-10, and so is the phase
    assert scaled(rest.omega[-1], far.omega[-1], np.abs(omega0).max()) <= 1e-8
    assert scaled(rest.q[-1], far.q[-1], 1.0) <= 1e-8


# --- the special motions ---------------------------------------------------------------------


def test_separatrix_is_a_single_tanh_sech_flip():
    # I = (1, 2, 2.25), ω1 = 0.75 ω3: L² − 2E I2 = 2.25·0.25·ω3² − 1·1·ω1² = 0 exactly.
    # ω2(0) = −2 makes y the dominant axis (|L_y| > |L|/√2) before the flip, as a flip needs.
    inertia, omega0 = (1.0, 2.0, 2.25), np.array([0.75, -2.0, 1.0])
    assert regime(inertia, omega0) == 0
    body = dz.Body(inertia)
    assert dz.flip_period(body, omega0) == np.inf
    traj = dz.simulate(body, omega0, t_end=60.0, frames=601, method="exact")
    assert len(traj.flip_times) == 1
    # The closed form on the separatrix, from the invariants (sorted axes 1, 2, 3 = x, y, z):
    i1, i2, i3 = inertia
    two_e = np.dot(inertia, omega0**2)
    l2 = np.dot(np.square(inertia) * omega0, omega0)
    a1 = np.sqrt((two_e * i3 - l2) / (i1 * (i3 - i1)))
    a2 = np.sqrt((two_e * i3 - l2) / (i2 * (i3 - i2)))
    a3 = np.sqrt((l2 - two_e * i1) / (i3 * (i3 - i1)))
    lam = np.sqrt((i3 - i2) * (l2 - two_e * i1) / (i1 * i2 * i3))
    # ω2 rises from −2 through 0 (ω1 ω3 > 0): ω2 = A2 tanh(λ (t − t*)), ω1,3 ∝ sech
    t_flip = np.arctanh(omega0[1] / a2) / -lam
    x = lam * (traj.t - t_flip)
    closed = np.stack([a1 / np.cosh(x), a2 * np.tanh(x), a3 / np.cosh(x)], axis=-1)
    assert scaled(traj.omega, closed, 1.0) <= 1e-14
    assert traj.flip_times[0] == pytest.approx(t_flip, abs=1e-12)
    # and the attitude obeys eq. 1 (DOP853 stays near the saddle long enough over [0, 6])
    omega, q = dop853(inertia, omega0, (1, 0, 0, 0), traj.t[:61])
    assert scaled(traj.q[:61], q, 1.0) <= 1e-11


def test_symmetric_top_follows_its_closed_form(rng):
    i, i3 = 1.3, 2.1
    for axis in range(3):
        inertia = np.full(3, i)
        inertia[axis] = i3
        omega0, q0 = rng.normal(size=3), rng.normal(size=4)
        q0 /= np.linalg.norm(q0)
        traj = dz.simulate(dz.Body(inertia), omega0, q0, t_end=1e4, frames=101, method="exact")
        big_omega = (i3 - i) * omega0[axis] / i
        e = np.eye(3)[axis]
        l_world = qmul(qmul(q0, np.concatenate([[0.0], inertia * omega0])), q0 * [1, -1, -1, -1])
        for t, w, q in zip(traj.t, traj.omega, traj.q):
            turn = qexp(big_omega * t * e)
            w_ref = qmul(qmul(turn, np.concatenate([[0.0], omega0])), turn * [1, -1, -1, -1])[1:]
            q_ref = qmul(qmul(qexp(l_world[1:] * t / i), q0), turn * [1, -1, -1, -1])
            np.testing.assert_allclose(w, w_ref, rtol=0, atol=1e-12)
            np.testing.assert_allclose(q, q_ref, rtol=0, atol=1e-11)
        assert len(traj.flip_times) == 0
        assert dz.flip_period(dz.Body(inertia), omega0) == np.inf


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_spin_exactly_about_a_principal_axis_is_steady(axis):
    omega0 = np.zeros(3)
    omega0[axis] = -0.7
    q0 = np.array([0.5, 0.5, -0.5, 0.5])
    traj = dz.simulate(dz.Body(dz.PAPER_INERTIA), omega0, q0, t_end=50.0, frames=11,
                       method="exact")
    assert np.all(traj.omega == omega0)
    _, q = dop853(dz.PAPER_INERTIA, omega0, q0, traj.t)
    assert scaled(traj.q, q, 1.0) <= 1e-11
    assert len(traj.flip_times) == 0
    assert dz.flip_period(dz.Body(dz.PAPER_INERTIA), omega0) == np.inf


# --- flips -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "inertia, omega0",
    [
        (dz.PAPER_INERTIA, (0.01, 0.01, 1.0)),  # fig3a: near the intermediate axis
        (dz.PAPER_INERTIA, (0.01, 0.01, 0.03)),  # fig3c: about the major axis, flipping
        ((1.0, 2.0, 3.0), (0.05, 1.0, 0.3)),  # about the minor axis, flipping
        ((3.0, 1.0, 2.0), (-0.3, 0.5, -0.9)),
        ((2.0, 3.0, 1.0), (0.7, -0.2, 0.4)),
    ],
)
def test_flip_period_and_times_match_the_flips_rk4_measures(inertia, omega0):
    body = dz.Body(inertia)
    period = dz.flip_period(body, omega0)
    assert np.isfinite(period)
    t_end = 5.3 * period
    rk4 = dz.simulate(body, omega0, t_end=t_end, frames=11, dt=1e-3)
    exact = dz.simulate(body, omega0, t_end=t_end, frames=11, method="exact")
    assert len(rk4.flip_times) >= 4
    np.testing.assert_allclose(np.diff(rk4.flip_times), period, rtol=1e-8)
    # same definition, same flips: each found by RK4's detector is one of the exact ones
    assert len(exact.flip_times) == len(rk4.flip_times)
    np.testing.assert_allclose(exact.flip_times, rk4.flip_times, rtol=0, atol=1e-8 * period)


def test_stable_wobbles_and_short_runs_have_no_flips():
    body = dz.Body(dz.PAPER_INERTIA)
    wobble = (0.01, 0.1, 0.03)  # fig3b: about the minor axis, never near the intermediate
    assert dz.flip_period(body, wobble) == np.inf
    for method in ("rk4", "exact"):
        assert len(dz.simulate(body, wobble, t_end=300.0, method=method).flip_times) == 0
    # fig3a's first flip is at t ≈ 22.9: none before, exactly one by t = 40
    assert len(dz.simulate(body, (0.01, 0.01, 1.0), t_end=20.0, method="exact").flip_times) == 0
    assert len(dz.simulate(body, (0.01, 0.01, 1.0), t_end=40.0, method="exact").flip_times) == 1


@pytest.mark.parametrize("eps", [1e-2, 1e-4, 1e-6, 5e-6, 1e-8, 1e-10])
def test_flip_period_matches_mpmath_and_the_near_axis_asymptote(eps):
    body = dz.Body(dz.PAPER_INERTIA)
    omega0 = (eps, eps, 1.0)  # z is the intermediate axis: m → 1 as eps → 0
    period = dz.flip_period(body, omega0)
    ref = ExactOmegaMP(dz.PAPER_INERTIA, omega0)
    assert period == pytest.approx(ref.flip_period, rel=1e-13)
    with mp.workdps(50):
        m1 = 1 - ref.m
        lam = ref.lam
        asymptote = float(2 / lam * mp.log(4 / mp.sqrt(m1)))
        # K(m) = ln(4/√m1) + O(m1 ln m1) as m1 → 0 (A&S 17.3.26)
        bound = float(m1 * abs(mp.log(m1)))
    assert abs(period - asymptote) <= 2 * bound * float(2 / lam) + 1e-13 * period


def test_exact_ignores_dt_counts_its_frames_toward_max_steps_and_checks_its_input():
    body = dz.Body(dz.PAPER_INERTIA)
    # no steps: t_end = 1e9 costs nothing; its frames are its work (issue 16)
    traj = dz.simulate(body, (0.01, 0.01, 1.0), t_end=1e9, frames=5, max_steps=5, dt=1e-9,
                       method="exact")
    assert traj.t[-1] == 1e9 and np.all(np.isfinite(traj.q))
    with pytest.raises(ValueError, match="needs 5 frames"):
        dz.simulate(body, (0.01, 0.01, 1.0), t_end=1e9, frames=5, max_steps=1, method="exact")
    with pytest.raises(ValueError, match="omega0"):
        dz.simulate(body, (np.nan, 0.0, 1.0), method="exact")
    with pytest.raises(ValueError, match="flip"):
        dz.simulate(body, (0.01, 0.01, 1.0), t_end=1e12, frames=2, method="exact")
    assert len(dz.simulate(body, (0.01, 0.01, 1.0), t_end=1e12, frames=2, method="exact",
                           flips=False).t) == 2
    with pytest.raises(ValueError, match="omega0"):
        dz.flip_period(body, (np.inf, 0.0, 1.0))
    with pytest.raises(TypeError, match="omega0"):
        dz.flip_period(body, "fast")
    assert "exact" in dz.METHODS


@pytest.mark.parametrize(
    "inertia, omega0",
    [
        ((1e-6, 1.0, 1.0 + 1e-9), (0.3, 0.4, 1.0)),  # a thin rod, about its long axis (minor)
        ((1e-6, 1.0, 1.0 + 1e-9), (1e-3, 0.4, 1.0)),  # the rod tumbling (about the major axis)
        ((1.0, 1.0 + 1e-6, 2.0 + 1e-6), (0.5, -0.4, 1.0)),  # a thin disc
        ((1.0, 1.0 + 1e-12, 2.0), (1.0, 0.4, 1e-3)),  # Ix = Iy (1 + 1e-12)
        (dz.PAPER_INERTIA, (1e-15, 1e-15, 1.0)),  # perturbations of 1e-15: 1 − m ≈ 1e-31
        (dz.PAPER_INERTIA, (3e5, -1e6, 2e5)),  # spin rates of 1e6
        (dz.PAPER_INERTIA, (1e-200, 2e-200, -1e-201)),  # and of 1e-200
    ],
)
@pytest.mark.skipif(np.finfo(np.longdouble).eps > 1e-18, reason="longdouble is float64 here")
def test_exact_at_the_extremes_matches_extended_precision_taylor(inertia, omega0):
    scale = np.abs(omega0).max()
    q0 = (0.8, 0.1, -0.3, 0.5)
    with warnings.catch_warnings():  # nearly symmetric on purpose (within dz.NEAR_SYMMETRY)
        warnings.simplefilter("ignore", dz.InertiaWarning)
        body = dz.Body(inertia)
    traj = dz.simulate(body, omega0, q0, t_end=20.0 / scale, frames=21, method="exact")
    assert max(traj.drift) <= 16 * EPS
    # the reference in units where the largest rate is 1: (ω, t) → (ω/s, s t) is exact
    omega, q = taylor_longdouble(inertia, np.asarray(omega0) / scale, q0, traj.t * scale, h=0.05)
    assert scaled(traj.omega / scale, omega, 1.0) <= 1e-13
    assert scaled(traj.q, q, 1.0) <= 1e-13


# --- near the separatrix far from the intermediate axis (issue 11) --------------------------


def near_separatrix_start(perm, side, m1, sign):
    """Rates on the body (1, 2, 3) with its axes permuted by `perm`, ω2 = 0.2 and ω3 = 0.5,
    and ω1 picked so that 1 − m ≈ `m1` on the major (`side` = +1) or minor (−1) side of the
    separatrix: there L² − 2E I2 = 3·ω3² − ω1² is a difference of two terms near 0.75."""
    # 1 − m = (I3 − I1)(L² − 2E I2) / ((I3 − I2)(L² − 2E I1)) on the major side, with
    # L² − 2E I1 ≈ 2·0.04 + 6·0.25 on this orbit; the minor side swaps I1 and I3.
    gap = m1 * (1.58 / 2 if side > 0 else 0.08 * 2 + 0.75 * 2) / 2
    w1 = float(mp.sqrt(mp.mpf(0.75) - side * mp.mpf(gap)))
    # body axis i is axis perm[i] of the body (1, 2, 3)
    inertia = np.array([1.0, 2.0, 3.0])[list(perm)]
    omega0 = sign * np.array([w1, 0.2, 0.5])[list(perm)]
    return inertia, omega0


SEPARATRIX_CASES = [(perm, side, m1, sign)
                    for perm in [(0, 1, 2), (2, 0, 1), (1, 0, 2)]
                    for side in (1, -1)
                    for m1 in (1e-3, 1e-9, 1e-13, 1e-15)
                    for sign in (1.0, -1.0)]


def test_issue_11s_start_has_the_flip_period_of_mpmath():
    # I3 (I3 − I2) ω3² = 0.75 and I1 (I2 − I1) ω1² = 0.75 + 1.6e-16: was 71.86016
    omega0 = (0.8660254037844394, 0.2, 0.5)
    ref = ExactOmegaMP((1.0, 2.0, 3.0), omega0, dps=60)
    assert dz.flip_period(dz.Body((1.0, 2.0, 3.0)), omega0) == pytest.approx(ref.flip_period,
                                                                            rel=1e-13)
    assert ref.flip_period == pytest.approx(71.80057, abs=1e-5)


@pytest.mark.parametrize("perm, side, m1, sign", SEPARATRIX_CASES)
def test_flip_period_near_the_separatrix_matches_mpmath_on_every_side(perm, side, m1, sign):
    inertia, omega0 = near_separatrix_start(perm, side, m1, sign)
    ref = ExactOmegaMP(inertia, omega0, dps=60)
    with mp.workdps(60):
        assert m1 / 3 < 1 - ref.m < 3 * m1 and ref.about_major == (side > 0)
    assert dz.flip_period(dz.Body(inertia), omega0) == pytest.approx(ref.flip_period, rel=1e-13)


@pytest.mark.parametrize("perm, side, m1, sign",
                         [c for c in SEPARATRIX_CASES if c[2] <= 1e-13 and c[3] > 0])
def test_exact_omega_near_the_separatrix_matches_mpmath_at_t_1000(perm, side, m1, sign):
    inertia, omega0 = near_separatrix_start(perm, side, m1, sign)
    t = np.linspace(0.0, 1000.0, 21)
    traj = dz.simulate(inertia, omega0, t_end=1000.0, frames=21, method="exact", flips=False)
    ref = ExactOmegaMP(inertia, omega0, dps=60)(t)
    # a phase error δu moves ω by up to |ω'|·δu; |ω'| ≤ 1 here and u ≈ 1000 λ ≈ 900 has
    # ulps of 1e-13: 1e-11 leaves room for the phase's round-off, not for a wrong parameter
    assert scaled(traj.omega, ref, 1.0) <= 1e-11
