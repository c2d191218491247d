"""Independent references for the tests: scipy's DOP853 on eq. 1 and the free top's exact ω(t).

Nothing here calls the package's core: it is what the core is checked against.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import ellipj, ellipk, ellipkinc


def euler_quaternion_rhs(inertia, law="body"):
    """Eq. 1 as f(t, y), y = (u, v, w, Q, U, V, W).

    law="body" is q' = ½ q ⊗ (0, ω), the correct one; "printed" is the paper's as printed
    (the dV row with the wrong sign); "space" is q' = ½ (0, ω) ⊗ q.
    """
    ix, iy, iz = inertia

    def f(_t, y):
        u, v, w, q0, q1, q2, q3 = y
        dw = [(iy - iz) / ix * v * w, (iz - ix) / iy * u * w, (ix - iy) / iz * u * v]
        if law == "body":
            dq = [-(q1 * u + q2 * v + q3 * w), q0 * u + q2 * w - q3 * v,
                  q0 * v + q3 * u - q1 * w, q0 * w + q1 * v - q2 * u]
        elif law == "printed":
            dq = [-(q1 * u + q2 * v + q3 * w), q0 * u + q2 * w - q3 * v,
                  q3 * u + q0 * v + q1 * w, q0 * w + q1 * v - q2 * u]
        elif law == "space":
            dq = [-(q1 * u + q2 * v + q3 * w), q0 * u - q2 * w + q3 * v,
                  q0 * v - q3 * u + q1 * w, q0 * w - q1 * v + q2 * u]
        else:
            raise ValueError(law)
        return np.array(dw + [0.5 * d for d in dq])

    return f


def dop853(inertia, omega0, q0, t, law="body", rtol=1e-13, atol=1e-15):
    """Eq. 1 by DOP853 at tight tolerance, sampled at times `t`; returns (omega, q)."""
    y0 = np.concatenate([omega0, np.asarray(q0, float) / np.linalg.norm(q0)])
    sol = solve_ivp(euler_quaternion_rhs(inertia, law), (t[0], t[-1]), y0, method="DOP853",
                    t_eval=t, rtol=rtol, atol=atol)
    assert sol.success, sol.message
    return sol.y[:3].T, sol.y[3:].T


def quaternion_matrix(q):
    """The paper's M(q) for unit q, literally as printed, shape (..., 3, 3)."""
    Q, U, V, W = np.moveaxis(np.asarray(q, float), -1, 0)
    return np.stack([
        np.stack([1 - 2 * V**2 - 2 * W**2, 2 * U * V - 2 * W * Q, 2 * U * W + 2 * V * Q], -1),
        np.stack([2 * U * V + 2 * W * Q, 1 - 2 * U**2 - 2 * W**2, 2 * V * W - 2 * U * Q], -1),
        np.stack([2 * U * W - 2 * V * Q, 2 * V * W + 2 * U * Q, 1 - 2 * U**2 - 2 * V**2], -1),
    ], -2)


class ExactOmega:
    """ω(t) of the free asymmetric top in Jacobi elliptic functions (Landau & Lifshitz §37).

    With the moments sorted I1 < I2 < I3 (a right-handed relabelling of the body axes), on
    orbits about the axis of I3 (L² > 2E I2):
        ω1 = s1 A1 cn(λt - u0), ω2 = s2 A2 sn(λt - u0), ω3 = s3 A3 dn(λt - u0),
    and about the axis of I1 the roles of 1 and 3 swap. The signs and the phase u0 are
    fitted to ω(0). The intermediate rate ω2 ∝ sn changes sign every 2K(m)/λ: the flip
    period. Valid away from the separatrix, where scipy's ellipj (which takes m alone) is
    accurate.
    """

    def __init__(self, inertia, omega0):
        inertia = np.asarray(inertia, float)
        omega0 = np.asarray(omega0, float)
        order = np.argsort(inertia)
        # Odd relabellings are left-handed: flip the last axis to keep Euler's equations.
        cyclic = tuple(order) in {(0, 1, 2), (1, 2, 0), (2, 0, 1)}
        self.order, self.hand = order, 1.0 if cyclic else -1.0
        i1, i2, i3 = inertia[order]
        w = omega0[order] * np.array([1.0, 1.0, self.hand])
        two_e = np.dot(inertia[order], w**2)
        l2 = np.dot((inertia[order] * w) ** 2, np.ones(3))
        self.about_major = l2 > two_e * i2
        if not self.about_major:  # swap the roles of axes 1 and 3 (a reflection: flip axis 2)
            i1, i3 = i3, i1
            w = np.array([w[2], -w[1], w[0]])
        a1 = np.sqrt((two_e * i3 - l2) / (i1 * (i3 - i1)))
        a2 = np.sqrt((two_e * i3 - l2) / (i2 * (i3 - i2)))
        a3 = np.sqrt((l2 - two_e * i1) / (i3 * (i3 - i1)))
        self.lam = np.sqrt((i3 - i2) * (l2 - two_e * i1) / (i1 * i2 * i3))
        self.m = (i2 - i1) * (two_e * i3 - l2) / ((i3 - i2) * (l2 - two_e * i1))
        # Euler's first equation with cn' = -sn dn fixes s1 = ∓ s2 s3 by the sign of I2 - I3;
        # take s2 = +1 and s3 = sign ω3 (dn > 0).
        s3 = np.sign(w[2])
        s1 = s3 if self.about_major else -s3
        self.signs = np.array([s1, 1.0, s3])
        self.amps = np.array([a1, a2, a3])
        # The starting argument: the one whose sn and cn give ω2(0) and ω1(0).
        self.u_start = ellipkinc(np.arctan2(w[1] / a2, w[0] / (s1 * a1)), self.m)

    @property
    def flip_period(self) -> float:
        """2K(m)/λ: the time between sign changes of the intermediate rate."""
        return 2.0 * ellipk(self.m) / self.lam

    def __call__(self, t):
        sn, cn, dn, _ = ellipj(self.lam * np.asarray(t, float) + self.u_start, self.m)
        w = self.signs * self.amps * np.stack([cn, sn, dn], axis=-1)
        if not self.about_major:
            w = np.stack([w[..., 2], -w[..., 1], w[..., 0]], axis=-1)
        w = w * np.array([1.0, 1.0, self.hand])
        out = np.empty_like(w)
        out[..., self.order] = w
        return out


class ExactOmegaMP:
    """`ExactOmega` in mpmath arithmetic: the same Landau–Lifshitz solution, with the
    invariants, parameter, phase and Jacobi functions all computed to `dps` digits from the
    (exactly representable) float inputs, so it stays exact near the separatrix too."""

    def __init__(self, inertia, omega0, dps=50):
        import mpmath as mp

        self.mp, self.dps = mp, dps
        with mp.workdps(dps):
            inertia = [mp.mpf(float(i)) for i in inertia]
            omega0 = [mp.mpf(float(w)) for w in omega0]
            order = list(np.argsort([float(i) for i in inertia]))
            cyclic = tuple(order) in {(0, 1, 2), (1, 2, 0), (2, 0, 1)}
            self.order, self.hand = order, 1 if cyclic else -1
            i1, i2, i3 = (inertia[k] for k in order)
            w = [omega0[k] for k in order]
            w[2] *= self.hand
            two_e = i1 * w[0] ** 2 + i2 * w[1] ** 2 + i3 * w[2] ** 2
            l2 = (i1 * w[0]) ** 2 + (i2 * w[1]) ** 2 + (i3 * w[2]) ** 2
            self.about_major = l2 > two_e * i2
            if not self.about_major:
                i1, i3 = i3, i1
                w = [w[2], -w[1], w[0]]
            a1 = mp.sqrt((two_e * i3 - l2) / (i1 * (i3 - i1)))
            a2 = mp.sqrt((two_e * i3 - l2) / (i2 * (i3 - i2)))
            a3 = mp.sqrt((l2 - two_e * i1) / (i3 * (i3 - i1)))
            self.lam = mp.sqrt((i3 - i2) * (l2 - two_e * i1) / (i1 * i2 * i3))
            self.m = (i2 - i1) * (two_e * i3 - l2) / ((i3 - i2) * (l2 - two_e * i1))
            s3 = mp.sign(w[2])
            s1 = s3 if self.about_major else -s3
            self.signs, self.amps = (s1, 1, s3), (a1, a2, a3)
            phi = mp.atan2(w[1] / a2, w[0] / (s1 * a1))
            self.u_start = mp.ellipf(phi, self.m)

    @property
    def flip_period(self) -> float:
        with self.mp.workdps(self.dps):
            return float(2 * self.mp.ellipk(self.m) / self.lam)

    def __call__(self, t):
        mp = self.mp
        out = np.empty((len(t), 3))
        with mp.workdps(self.dps):
            for row, ti in enumerate(np.asarray(t, float)):
                u = self.lam * mp.mpf(float(ti)) + self.u_start
                sn, cn, dn = (mp.ellipfun(f, u, m=self.m) for f in ("sn", "cn", "dn"))
                w = [s * a * f for s, a, f in zip(self.signs, self.amps, (cn, sn, dn))]
                if not self.about_major:
                    w = [w[2], -w[1], w[0]]
                w[2] *= self.hand
                for k, wk in zip(self.order, w):
                    out[row, k] = float(wk)
        return out


def taylor_longdouble(inertia, omega0, q0, t, order=24, h=0.25):
    """Eq. 1 by a Taylor-series method in extended precision (numpy longdouble), sampled at
    times `t` (from t[0] = 0); returns (omega, q) rounded to float64.

    Eq. 1 is quadratic, so its Taylor coefficients follow from Cauchy products:
    (k+1) x_{k+1} = Σ_i f(x_i, x_{k−i}). With steps of `h` well inside the radius of
    convergence the truncation error is far below the longdouble round-off (~1e-19 on
    x86-64), about a thousand times smaller than float64's.
    """
    ld = np.longdouble
    ix, iy, iz = (ld(float(i)) for i in inertia)
    coef = np.array([(iy - iz) / ix, (iz - ix) / iy, (ix - iy) / iz], dtype=ld)
    x = np.concatenate([np.asarray(omega0, float), np.asarray(q0, float)]).astype(ld)
    x[3:] /= np.sqrt(np.sum(x[3:] ** 2))
    out = np.empty((len(t), 7))
    out[0] = x.astype(float)
    now = ld(0)
    for row in range(1, len(t)):
        target = ld(float(t[row]))
        n = max(1, int(np.ceil(float((target - now) / ld(h)))))
        step = (target - now) / n
        for _ in range(n):
            c = np.zeros((order + 1, 7), dtype=ld)
            c[0] = x
            for k in range(order):
                w, q = c[: k + 1, :3], c[: k + 1, 3:]
                rev = w[::-1]
                pair = [rev[:, 1] @ w[:, 2], rev[:, 0] @ w[:, 2], rev[:, 0] @ w[:, 1]]
                m = q.T @ rev  # m[a, b] = Σ_i q_a(i) ω_b(k − i)
                dq = [-(m[1, 0] + m[2, 1] + m[3, 2]), m[0, 0] + m[2, 2] - m[3, 1],
                      m[0, 1] + m[3, 0] - m[1, 2], m[0, 2] + m[1, 1] - m[2, 0]]
                c[k + 1, :3] = coef * np.array(pair, dtype=ld) / (k + 1)
                c[k + 1, 3:] = np.array(dq, dtype=ld) / (2 * (k + 1))
            x = c[order]
            for k in range(order - 1, -1, -1):  # Horner
                x = x * step + c[k]
        now = target
        out[row] = x.astype(float)
    return out[:, :3], out[:, 3:]
