"""The quasi-rigid energy-sink estimate of nutation growth or decay, for any energy sink.

A spinner carries small parts that flex or slosh. Treated as a small perturbation of the
torque-free motion of the composite body (the parts frozen at their relative equilibrium
under the spin), each part is a damped oscillator driven by the body's nutation; the power
it dissipates, averaged over a cycle, drains the kinetic energy at constant angular momentum,
and the nutation angle follows (Kaplan, *Modern Spacecraft Dynamics and Control*, 1976, §5;
Hughes, *Spacecraft Attitude Dynamics*, 1986, §8.2; Thomson & Reiter 1960).

**The rigid motion.** The composite, its moment ``I_a`` about the spin axis ``a`` (the
principal axis nearest the angular momentum ``H``) and ``I_t`` the mean of the other two,
nutates at angle θ: ``ω = Ω a + ω_t (e₁ cos λt + e₂ sin λt)`` in body axes, ``Ω = H cos θ / I_a``,
``ω_t = H sin θ / I_t``, ``λ = Ω (I_a − I_t) / I_t``.

**A part's forced motion.** Each part's equation is written by Newton–Euler in the body's
frame with the body's origin held (a small part does not move the mass centre): a point mass
``m (r̈ + 2 ω × ṙ + ω̇ × r + ω × (ω × r))`` against its spring, damper and constraint; a hinged
panel's moment about its hinge axis ``e · [ρ × m a + I Ω̇ + Ω × I Ω] = −k β − c β̇``; a
pendulum's bob projected on the rod's two free directions. Linearised about the relative
equilibrium under ``Ω a`` (found by Newton's method) by complex-step derivatives (exact to
round-off), ``𝕄 ẍ + 𝔻 ẋ + 𝕂 x = −𝔹 δω − 𝔹' δω̇``; its response to
``δω = Re[ω_t (e₁ − i e₂) e^{iλt}]`` is ``x̂ = −(𝕂 − λ² 𝕄 + iλ 𝔻)⁻¹ (𝔹 + iλ 𝔹') (e₁ − i e₂) ω_t``
and its mean dissipated power ``½ λ² x̂ᴴ 𝔻ₛ x̂`` (``𝔻ₛ`` the symmetric, dissipative part of ``𝔻``;
the rest is gyroscopic).

**The nutation.** With ``P = p̄ ω_t²`` the parts' mean power, ``dT/dt = −P`` and
``T = ½ H² (sin²θ / I_t + cos²θ / I_a)`` give, at small θ, ``θ' = θ / τ`` with

``1/τ = p̄ I_a / (I_t (I_t − I_a))``:

growth for a spin about the minor axis (``I_a < I_t``: the spin goes flat, Explorer 1),
decay about the major axis. The estimate is the leading order in the parts' size: its
relative error falls in proportion to them (the parts' mass, moments, stiffness and damping
scaled together).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

_STEP = 1e-30
"""The complex step: ``f'(x) = Im f(x + ih) / h`` has no cancellation, so any tiny ``h``."""


def _jacobian(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray) -> np.ndarray:
    """``∂f/∂x`` by complex steps, shape (len(f(x)), len(x))."""
    x = np.asarray(x, dtype=complex)
    cols = []
    for k in range(x.size):
        dx = np.zeros(x.size, dtype=complex)
        dx[k] = 1j * _STEP
        cols.append(np.imag(f(x + dx)) / _STEP)
    return np.array(cols).T.reshape(-1, x.size)


def _cross(a: Any, b: Any) -> np.ndarray:
    """``a × b`` without conjugation (complex steps pass through)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def _inertial(r: Any, rdot: Any, rddot: Any, w: Any, wd: Any) -> np.ndarray:
    """A point's acceleration in space, in body axes, from its motion relative to the body
    (the body's origin held): ``r̈ + 2 ω × ṙ + ω̇ × r + ω × (ω × r)``."""
    return np.asarray(rddot + 2 * _cross(w, rdot) + _cross(wd, r) + _cross(w, _cross(w, r)))


def spring_residual(p: Any, q: Any, qd: Any, qdd: Any, w: Any, wd: Any,
                    base: Any = None) -> np.ndarray:
    """The spring–mass damper's equation along its line: ``d · m a + k x + c ẋ``."""
    d = np.asarray(p.direction, float)
    r = np.asarray(p.anchor, float) + q[0] * d
    a = _inertial(r, qd[0] * d, qdd[0] * d, w, wd)
    return np.array([p.mass * (d @ a) + p.stiffness * q[0] + p.damping * qd[0]])


def hinge_residual(p: Any, q: Any, qd: Any, qdd: Any, w: Any, wd: Any,
                   base: Any = None) -> np.ndarray:
    """The hinged panel's moment about its hinge axis:
    ``e · [ρ × m a + I Ω̇ + Ω × I Ω] + k β + c β̇``."""
    e = np.asarray(p.axis, float)
    arm0 = np.asarray(p.arm, float)
    s = arm0 * np.cos(q[0]) + np.cross(e, arm0) * np.sin(q[0])
    g = _cross(e, s)
    rho = p.length * s
    r = np.asarray(p.hinge, float) + rho
    a = _inertial(r, qd[0] * p.length * g, qdd[0] * p.length * g - qd[0] ** 2 * rho, w, wd)
    js, je, jg = p.moments
    tensor = js * np.outer(s, s) + je * np.outer(e, e) + jg * np.outer(g, g)
    spin = w + qd[0] * e
    spin_rate = wd + qdd[0] * e + _cross(w, qd[0] * e)
    moment = _cross(rho, p.mass * a) + tensor @ spin_rate + _cross(spin, tensor @ spin)
    return np.array([e @ moment + p.stiffness * q[0] + p.damping * qd[0]])


def _rod(base: Any, q: Any) -> tuple[np.ndarray, np.ndarray]:
    """The rod's direction at local coordinates `q` about `base` ``(n₀, t₁, t₂)`` and its
    derivatives ``∂n/∂q`` (columns)."""
    n0, t1, t2 = base
    v = n0 + q[0] * t1 + q[1] * t2
    size = np.sqrt(v @ v)
    n = v / size
    dn = np.array([(t - n * (n @ t)) / size for t in (t1, t2)]).T
    return n, dn


def slosh_residual(p: Any, q: Any, qd: Any, qdd: Any, w: Any, wd: Any,
                   base: Any = None) -> np.ndarray:
    """The pendulum's bob projected on the rod's free directions, with the pivot's damping:
    ``(∂r/∂q)ᵀ m a + c (∂n/∂q)ᵀ ṅ`` (terms of second order in ``q̇`` left out: they vanish from
    the linearisation)."""
    n, dn = _rod(base, q)
    r = np.asarray(p.pivot, float) + p.length * n
    rdot = p.length * (dn @ qd)
    a = _inertial(r, rdot, p.length * (dn @ qdd), w, wd)
    return np.asarray(p.length * (dn.T @ (p.mass * a)) + p.damping * (dn.T @ (dn @ qd)))


RESIDUALS: dict[str, tuple[Callable[..., np.ndarray], int]] = {
    "spring_mass": (spring_residual, 1),
    "hinge": (hinge_residual, 1),
    "slosh": (slosh_residual, 2),
}
"""Each sink's equation and its number of coordinates, by kind."""


def _point_tensor(m: float, r: np.ndarray) -> np.ndarray:
    return np.asarray(m * (r @ r * np.eye(3) - np.outer(r, r)))


def _carried(p: Any, kind: str, q: np.ndarray, base: Any) -> tuple[float, np.ndarray, np.ndarray]:
    """A part's mass, centre and own tensor at coordinates `q`."""
    if kind == "spring_mass":
        return p.mass, np.asarray(p.anchor, float) + q[0] * np.asarray(p.direction, float), \
            np.zeros((3, 3))
    if kind == "hinge":
        e = np.asarray(p.axis, float)
        arm0 = np.asarray(p.arm, float)
        s = arm0 * np.cos(q[0]) + np.cross(e, arm0) * np.sin(q[0])
        g = np.cross(e, s)
        js, je, jg = p.moments
        return p.mass, np.asarray(p.hinge, float) + p.length * s, \
            js * np.outer(s, s) + je * np.outer(e, e) + jg * np.outer(g, g)
    n, _ = _rod(base, q)
    return p.mass, np.asarray(p.pivot, float) + p.length * n, np.zeros((3, 3))


def _composite(hub: np.ndarray, hub_mass: float, masses: Sequence[tuple[float, np.ndarray,
               np.ndarray]]) -> np.ndarray:
    """The tensor of the hub and the parts about their common mass centre."""
    total = hub_mass + sum(m for m, _, _ in masses)
    centre = sum((m * r for m, r, _ in masses), np.zeros(3)) / total
    out = hub + _point_tensor(hub_mass, -centre)
    for m, r, i in masses:
        out = out + _point_tensor(m, r - centre) + i
    return np.asarray(out)


def _base(p: Any, kind: str, axis: np.ndarray) -> Any:
    """A slosh pendulum's starting direction under spin about `axis`: outward from the axis
    at its pivot (where the centrifugal field points), with a basis of the rod's free
    directions."""
    if kind != "slosh":
        return None
    pivot = np.asarray(p.pivot, float)
    out = pivot - axis * (axis @ pivot)
    size = np.linalg.norm(out)
    if not size > 1e-9 * max(p.length, np.linalg.norm(pivot)):
        raise ValueError("a slosh pendulum pivoted on the spin axis has no single relative "
                         "equilibrium (its rod may point anywhere in the plane normal to the "
                         "spin): the estimate needs the pivot off the axis")
    n0 = out / size
    t1 = np.cross(n0, axis)
    t1 /= np.linalg.norm(t1)
    return (n0, t1, np.cross(n0, t1))


def _equilibrium(p: Any, kind: str, base: Any, w: np.ndarray) -> np.ndarray:
    """The part's coordinates at rest relative to a body spinning at `w` (Newton's method)."""
    residual, width = RESIDUALS[kind]
    zero = np.zeros(width)
    q = np.zeros(width)
    for _ in range(50):
        r = np.real(residual(p, q, zero, zero, w, np.zeros(3), base))
        k = _jacobian(lambda x: residual(p, x, zero, zero, w, np.zeros(3), base), q)
        step = np.linalg.solve(k, r)
        q = q - step
        if np.max(np.abs(step)) < 1e-15 * (1 + np.max(np.abs(q))):
            break
    return q


def frequencies(kind: str, part: Any, spin: Any) -> np.ndarray:
    """The undamped frequencies of a part's small oscillation about its relative equilibrium
    on a body turning steadily at `spin` (a vector, body axes) — the body held to that turn,
    as a heavy body is — sorted: ``√eig(𝕄⁻¹ 𝕂)`` of the linearised equation (gyroscopic
    coupling left out; for the three sinks here it vanishes at these equilibria)."""
    spin = np.asarray(spin, float)
    residual, width = RESIDUALS[kind]
    axis = spin / np.linalg.norm(spin)
    base = _base(part, kind, axis)
    q = _equilibrium(part, kind, base, spin)
    zero, z3 = np.zeros(width), np.zeros(3)
    mass = _jacobian(lambda x: residual(part, q, zero, x, spin, z3, base), zero)
    stiff = _jacobian(lambda x: residual(part, x, zero, zero, spin, z3, base), q)
    return np.sort(np.sqrt(np.linalg.eigvals(np.linalg.solve(mass, stiff)).real))


class SinkEstimate:
    """What the estimate found: the composite's moments, the spin, the nutation rate in body
    axes, each part's mean power per unit ``ω_t²``, and the time constant."""

    __slots__ = ("axial", "transverse", "spin", "nutation", "powers", "time_constant",
                 "theta0")

    def __init__(self, axial: float, transverse: float, spin: float, nutation: float,
                 powers: list[float], time_constant: float, theta0: float) -> None:
        self.axial, self.transverse, self.spin = axial, transverse, spin
        self.nutation, self.powers = nutation, powers
        self.time_constant, self.theta0 = time_constant, theta0


def estimate(hub: Any, hub_mass: float, parts: Sequence[tuple[str, Any]],
             omega0: Any) -> SinkEstimate:
    """The energy-sink estimate (see the module doc) for a hub of tensor `hub` (body axes,
    about its mass centre) and mass `hub_mass` carrying `parts` (``(kind, part)`` pairs) and
    starting at body rates `omega0`."""
    hub = np.asarray(hub, float)
    omega0 = np.asarray(omega0, float)
    moments, axes = np.linalg.eigh(hub)
    near = int(np.argmax(np.abs(axes.T @ (hub @ omega0))))
    axis = axes[:, near]
    coords = [np.zeros(RESIDUALS[k][1]) for k, _ in parts]
    bases = [_base(p, k, axis) for k, p in parts]
    for _ in range(8):
        masses = [_carried(p, k, q, b) for (k, p), q, b in zip(parts, coords, bases)]
        tensor = _composite(hub, hub_mass, masses)
        h = tensor @ omega0
        moments, axes = np.linalg.eigh(tensor)
        near = int(np.argmax(np.abs(axes.T @ h)))
        axis = axes[:, near] * np.sign(axes[:, near] @ h)
        spin = np.linalg.norm(h) / moments[near]
        bases = [_base(p, k, axis) for k, p in parts]
        coords = [_equilibrium(p, k, b, spin * axis) for (k, p), b in zip(parts, bases)]
    axial = moments[near]
    others = [i for i in range(3) if i != near]
    transverse = float(np.mean(moments[others]))
    e1 = axes[:, others[0]]
    e2 = np.cross(axis, e1)
    hn = np.linalg.norm(h)
    theta0 = float(np.arccos(np.clip(abs(axis @ h) / hn, -1.0, 1.0)))
    nutation = spin * (axial - transverse) / transverse
    w = spin * axis
    forcing = e1 - 1j * e2
    powers = []
    for (kind, p), q, b in zip(parts, coords, bases):
        residual, width = RESIDUALS[kind]
        zero, z3 = np.zeros(width), np.zeros(3)
        mass = _jacobian(lambda x: residual(p, q, zero, x, w, z3, b), zero)
        damp = _jacobian(lambda x: residual(p, q, x, zero, w, z3, b), zero)
        stiff = _jacobian(lambda x: residual(p, x, zero, zero, w, z3, b), q)
        by_rate = _jacobian(lambda x: residual(p, q, zero, zero, x, z3, b), w)
        by_accel = _jacobian(lambda x: residual(p, q, zero, zero, w, x, b), z3)
        lam = nutation
        dynamic = stiff - lam**2 * mass + 1j * lam * damp
        x_hat = -np.linalg.solve(dynamic, (by_rate + 1j * lam * by_accel) @ forcing)
        dissipative = 0.5 * (damp + damp.T)
        powers.append(float(0.5 * lam**2 * np.real(np.conj(x_hat) @ dissipative @ x_hat)))
    rate = sum(powers) * axial / (transverse * (transverse - axial))
    tau = 1.0 / rate if rate != 0 else np.inf
    return SinkEstimate(float(axial), transverse, float(spin), float(nutation), powers,
                        float(tau), theta0)
