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
