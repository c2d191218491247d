"""Independent references for the energy sinks: Lagrange's equations derived symbolically.

Nothing here calls the package's core. The whole system is written in generalised coordinates
the core does not use — the hub's position in space (three), its attitude by ZYX Euler angles
(three), a spring's displacement, a hinge's angle, a pendulum's two angles about its start —
and its kinetic energy is summed body by body in space, each mass's position differentiated
in time by sympy. The hub's translation is a coordinate, so the mass centre's motion comes out
of the equations rather than being put in (the core removes it by the total linear momentum).
Lagrange's equations ``d/dt ∂L/∂q̇ − ∂L/∂q = −∂R/∂q̇`` with the springs' potential and the
Rayleigh dissipation are then integrated by scipy's DOP853 at tight tolerance.

A part is a dict:

- ``{"kind": "spring", "mass", "anchor", "direction", "stiffness", "damping"}``: a point mass
  at ``anchor + x·direction``;
- ``{"kind": "hinge", "mass", "moments", "hinge", "axis", "arm", "length", "stiffness",
  "damping"}``: a rigid panel, its centre at ``hinge + length·A(β)·arm`` (``A(β)`` the turn by
  β about ``axis``, by Rodrigues' formula) and its tensor ``A(β) I₀ A(β)ᵀ``, ``I₀`` its moments
  about the arm, the axis and their normal;
- ``{"kind": "slosh", "mass", "pivot", "length", "damping"}``: a point mass at
  ``pivot + length·n``, ``n = B (cos a cos b, sin a cos b, sin b)`` with ``B`` a fixed turn
  taking x to the start's direction (the angles' poles stay far from the motions tested), the
  dissipation ``½ c |ṅ|²``.

The Euler angles are singular at a pitch of ±90°: the runs here keep the hub's attitude away
from it (a check raises otherwise).
"""

from __future__ import annotations

import functools

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation


def _rodrigues(axis, angle):
    """The turn by `angle` about the unit `axis` (sympy matrix)."""
    e = sp.Matrix(axis)
    k = sp.Matrix([[0, -e[2], e[1]], [e[2], 0, -e[0]], [-e[1], e[0], 0]])
    return sp.eye(3) + sp.sin(angle) * k + (1 - sp.cos(angle)) * k * k


def _turn_to(v):
    """A rotation matrix (numpy) taking the x axis to the unit vector along `v`."""
    v = np.asarray(v, float) / np.linalg.norm(v)
    return Rotation.align_vectors([v], [[1.0, 0.0, 0.0]])[0].as_matrix()


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


class Lagrange:
    """The system of a hub (tensor `inertia` about its mass centre, `mass`) and `parts`.

    The kinetic energy is ``T = ½ uᵀ M(q) u`` with ``M = Σ_b m_b J_bᵀ J_b + Σ_b W_bᵀ I_b W_b``
    over the bodies' positions in space (``J_b = ∂x_b/∂q``) and the rigid bodies' angular
    velocities in their own axes (``W_b = ∂Ω_b/∂u``), so that Lagrange's equations read
    ``M u̇ = ½ [uᵀ ∂M/∂q_k u]_k − (Σ_k ∂M/∂q_k u_k) u − ∂V/∂q − ∂R/∂u``; `M` and each
    ``∂M/∂q_k`` are sympy's, evaluated by lambdify.
    """

    def __init__(self, inertia, mass, parts):
        self.parts = [dict(p) for p in parts]
        self.hub_inertia = np.asarray(inertia, float)
        if self.hub_inertia.shape == (3,):
            self.hub_inertia = np.diag(self.hub_inertia)
        self.hub_mass = float(mass)
        widths = [2 if p["kind"] == "slosh" else 1 for p in self.parts]
        n = 6 + sum(widths)
        self.n = n
        qs = sp.symbols(f"q0:{n}")
        us = sp.symbols(f"u0:{n}")
        psi, theta, phi = qs[3:6]
        rz = sp.Matrix([[sp.cos(psi), -sp.sin(psi), 0], [sp.sin(psi), sp.cos(psi), 0], [0, 0, 1]])
        ry = sp.Matrix([[sp.cos(theta), 0, sp.sin(theta)], [0, 1, 0],
                        [-sp.sin(theta), 0, sp.cos(theta)]])
        rx = sp.Matrix([[1, 0, 0], [0, sp.cos(phi), -sp.sin(phi)], [0, sp.sin(phi), sp.cos(phi)]])
        rot = rz * ry * rx  # world from body
        origin = sp.Matrix(qs[:3])
        # the body rates of the ZYX angles: ω_b = (Rᵀ Ṙ)^∨, Ṙ by the chain rule
        rdot = sum((rot.diff(qs[k]) * us[k] for k in range(3, 6)), sp.zeros(3, 3))
        skew = rot.T * rdot
        omega_b = sp.Matrix([skew[2, 1], skew[0, 2], skew[1, 0]])
        uvec = sp.Matrix(us)
        w_hub = omega_b.jacobian(uvec)
        j_origin = origin.jacobian(sp.Matrix(qs))
        mass_matrix = (self.hub_mass * j_origin.T * j_origin
                       + w_hub.T * sp.Matrix(self.hub_inertia) * w_hub)
        potential = sp.Integer(0)
        rayleigh = sp.Integer(0)
        self.bodies = []  # (mass, world position)
        self.spins = []   # (tensor in body axes, spin in body axes) of rigid parts, or None
        self.columns = []
        at = 6
        for k, part in enumerate(self.parts):
            cols = list(range(at, at + widths[k]))
            self.columns.append(cols)
            at += widths[k]
            spin = None
            if part["kind"] == "spring":
                x = qs[cols[0]]
                r = sp.Matrix(part["anchor"]) + x * sp.Matrix(_unit(part["direction"]))
                potential += sp.Rational(1, 2) * part["stiffness"] * x**2
                rayleigh += sp.Rational(1, 2) * part["damping"] * us[cols[0]] ** 2
            elif part["kind"] == "hinge":
                beta = qs[cols[0]]
                e = _unit(part["axis"])
                arm = np.asarray(part["arm"], float)
                arm = _unit(arm - e * (e @ arm))
                normal = np.cross(e, arm)
                turn = _rodrigues(e, beta)
                r = sp.Matrix(part["hinge"]) + part["length"] * turn * sp.Matrix(arm)
                js, je, jg = part["moments"]
                i0 = js * np.outer(arm, arm) + je * np.outer(e, e) + jg * np.outer(normal, normal)
                tensor = turn * sp.Matrix(i0) * turn.T
                spin = (tensor, omega_b + us[cols[0]] * sp.Matrix(e))
                potential += sp.Rational(1, 2) * part["stiffness"] * beta**2
                rayleigh += sp.Rational(1, 2) * part["damping"] * us[cols[0]] ** 2
            elif part["kind"] == "slosh":
                a, b = qs[cols[0]], qs[cols[1]]
                base = _turn_to(part.get("start", [1.0, 0.0, 0.0]))
                part["_base"] = base
                n_dir = sp.Matrix(base) * sp.Matrix([sp.cos(a) * sp.cos(b),
                                                     sp.sin(a) * sp.cos(b), sp.sin(b)])
                r = sp.Matrix(part["pivot"]) + part["length"] * n_dir
                ndot = n_dir.jacobian(sp.Matrix(qs)) * uvec
                rayleigh += sp.Rational(1, 2) * part["damping"] * ndot.dot(ndot)
            else:
                raise ValueError(part["kind"])
            world = origin + rot * r
            jac = world.jacobian(sp.Matrix(qs))
            mass_matrix += float(part["mass"]) * jac.T * jac
            if spin is not None:
                w = spin[1].jacobian(uvec)
                mass_matrix += w.T * spin[0] * w
            self.bodies.append((float(part["mass"]), world, jac))
            self.spins.append(spin)
        moving = sorted(set().union(*(e.free_symbols for e in mass_matrix)) & set(qs),
                        key=qs.index)
        self.moving = [qs.index(s) for s in moving]
        args = (qs, us)

        def fn(expr):
            return sp.lambdify(args, expr, cse=True, modules="numpy")

        self._mass = fn(mass_matrix)
        self._dmass = fn([mass_matrix.diff(s) for s in moving])
        self._dpot = fn(sp.Matrix([potential]).jacobian(sp.Matrix(qs)))
        self._pot = fn(potential)
        self._drayleigh = fn(sp.Matrix([rayleigh]).jacobian(uvec))
        self._power = fn(2 * rayleigh)
        self._omega = fn(omega_b)
        self._rot = fn(rot)
        self._world = fn([sp.Matrix.hstack(w, j * uvec) for _, w, j in self.bodies])
        self._origin = fn(sp.Matrix.hstack(origin, j_origin * uvec))
        self._spin = fn([rot * s[1] if s is not None else sp.zeros(3, 1) for s in self.spins])
        self._tensor = fn([rot * s[0] * rot.T if s is not None else sp.zeros(3, 3)
                           for s in self.spins])

    # -- numbers -----------------------------------------------------------------------

    def rhs(self, _t, y):
        q, u = y[: self.n], y[self.n:]
        m = np.asarray(self._mass(q, u), float)
        f = -np.asarray(self._dpot(q, u), float).ravel()
        f -= np.asarray(self._drayleigh(q, u), float).ravel()
        for k, dm in zip(self.moving, self._dmass(q, u)):
            dm = np.asarray(dm, float)
            f[k] += 0.5 * u @ dm @ u
            f -= dm @ u * u[k]
        return np.concatenate([u, np.linalg.solve(m, f)])

    def start(self, omega0, q0, configs, rates):
        """The state `(q, u)` of body rates `omega0` (body axes), attitude `q0` (scalar first,
        world from body), each part's configuration (``x``, ``β``, or the rod's unit
        direction, which must be the part's ``start``) and its rates (``ẋ``, ``β̇``, or the rod's
        angular velocity relative to the body ``ν``, body axes), with the hub placed so that
        the system's linear momentum is zero and its mass centre at the origin."""
        angles = Rotation.from_quat(q0, scalar_first=True).as_euler("ZYX")
        q = np.zeros(self.n)
        q[3:6] = angles
        u = np.zeros(self.n)
        at = 6
        for part, config, rate in zip(self.parts, configs, rates):
            if part["kind"] in ("spring", "hinge"):
                q[at], u[at] = float(np.ravel(config)[0]), float(np.ravel(rate)[0])
                at += 1
            else:
                base = part["_base"]
                direction = _unit(config)
                if not np.allclose(base[:, 0], direction, atol=1e-12):
                    raise ValueError("a slosh part's start must be its configuration")
                ndot = np.cross(np.asarray(rate, float), direction)  # ṅ = ν × n
                # n = B (cos a cos b, sin a cos b, sin b): at a = b = 0, ṅ = B (0, ȧ, ḃ)
                local = base.T @ ndot
                q[at:at + 2] = 0.0
                u[at:at + 2] = local[1:3]
                at += 2
        # the Euler rates of ω_b, solved from the map at these angles (it is linear in them)
        basis = np.array([np.asarray(self._omega(q, _e(self.n, 3 + j)), float).ravel()
                          for j in range(3)]).T
        fixed = u.copy()
        fixed[3:6] = 0.0
        u[3:6] = np.linalg.solve(basis, np.asarray(omega0, float)
                                 - np.asarray(self._omega(q, fixed), float).ravel())
        # the hub's position and velocity that put the mass centre at rest at the origin
        total = self.hub_mass + sum(p["mass"] for p in self.parts)
        first, moving = np.zeros(3), np.zeros(3)
        for (m, _, _), wv in zip(self.bodies, self._world(q, u)):
            wv = np.asarray(wv, float)
            first += m * wv[:, 0]
            moving += m * wv[:, 1]
        q[:3] = -first / total
        u[:3] = -moving / total
        return np.concatenate([q, u])

    def solve(self, y0, times, rtol=1e-12, atol=1e-13):
        sol = solve_ivp(self.rhs, (times[0], times[-1]), y0, method="DOP853", t_eval=times,
                        rtol=rtol, atol=atol)
        assert sol.success, sol.message
        pitch = np.abs(sol.y[4])
        assert pitch.max() < 1.4, "the Euler angles neared their singularity: rearrange the run"
        return sol.y.T

    # -- what a run shows --------------------------------------------------------------

    def omega(self, y):
        """The hub's body rates at each state, shape (n, 3)."""
        return np.array([np.asarray(self._omega(s[: self.n], s[self.n:]), float).ravel()
                         for s in np.atleast_2d(y)])

    def quaternion(self, y):
        """The hub's attitude, world from body, scalar first, shape (n, 4)."""
        mats = [np.asarray(self._rot(s[: self.n], s[self.n:]), float) for s in np.atleast_2d(y)]
        return Rotation.from_matrix(np.array(mats)).as_quat(scalar_first=True)

    def energy(self, y):
        """``T + V`` at each state."""
        out = []
        for s in np.atleast_2d(y):
            q, u = s[: self.n], s[self.n:]
            out.append(0.5 * u @ np.asarray(self._mass(q, u), float) @ u + float(self._pot(q, u)))
        return np.array(out)

    def dissipation(self, y):
        """The dissipated power ``2R`` at each state."""
        return np.array([float(self._power(s[: self.n], s[self.n:])) for s in np.atleast_2d(y)])

    def coordinates(self, y, k):
        """Part `k`'s configuration at each state: ``x``, ``β`` (shape (n,)) or the rod's unit
        direction in body axes (shape (n, 3))."""
        y = np.atleast_2d(y)
        cols = self._columns(k)
        if self.parts[k]["kind"] != "slosh":
            return y[:, cols[0]]
        a, b = y[:, cols[0]], y[:, cols[1]]
        local = np.stack([np.cos(a) * np.cos(b), np.sin(a) * np.cos(b), np.sin(b)], -1)
        return local @ self.parts[k]["_base"].T

    def rates(self, y, k):
        """Part `k`'s rates: ``ẋ``, ``β̇``, or ``ṅ`` (body axes, shape (n, 3))."""
        y = np.atleast_2d(y)
        cols = self._columns(k)
        if self.parts[k]["kind"] != "slosh":
            return y[:, self.n + cols[0]]
        a, b = y[:, cols[0]], y[:, cols[1]]
        da, db = y[:, self.n + cols[0]], y[:, self.n + cols[1]]
        local = np.stack([-np.sin(a) * np.cos(b) * da - np.cos(a) * np.sin(b) * db,
                          np.cos(a) * np.cos(b) * da - np.sin(a) * np.sin(b) * db,
                          np.cos(b) * db], -1)
        return local @ self.parts[k]["_base"].T

    def momentum_world(self, y):
        """The total angular momentum about the system's mass centre, in space, shape (n, 3)."""
        out = []
        total = self.hub_mass + sum(p["mass"] for p in self.parts)
        for s in np.atleast_2d(y):
            q, u = s[: self.n], s[self.n:]
            o = np.asarray(self._origin(q, u), float)
            worlds = [np.asarray(w, float) for w in self._world(q, u)]
            centre = (self.hub_mass * o[:, 0]
                      + sum(m * w[:, 0] for (m, _, _), w in zip(self.bodies, worlds))) / total
            rot = np.asarray(self._rot(q, u), float)
            w_hub = rot @ np.asarray(self._omega(q, u), float).ravel()
            h = (np.cross(o[:, 0] - centre, self.hub_mass * o[:, 1])
                 + rot @ self.hub_inertia @ rot.T @ w_hub)
            for (m, _, _), w in zip(self.bodies, worlds):
                h += np.cross(w[:, 0] - centre, m * w[:, 1])
            for tensor, spin in zip(self._tensor(q, u), self._spin(q, u)):
                h += np.asarray(tensor, float) @ np.asarray(spin, float).ravel()
            out.append(h)
        return np.array(out)

    def _columns(self, k):
        return self.columns[k]


def _e(n, k):
    out = np.zeros(n)
    out[k] = 1.0
    return out


@functools.lru_cache(maxsize=None)
def _cached(key):
    inertia, mass, parts = key
    return Lagrange(np.array(inertia), mass, [dict(p) for p in parts])


def lagrange(inertia, mass, parts):
    """A `Lagrange` system, derived once per set of arguments in a test session."""
    frozen = tuple(tuple((k, tuple(np.ravel(v)) if isinstance(v, (list, tuple, np.ndarray))
                          else v) for k, v in sorted(p.items())) for p in parts)
    key = (tuple(np.ravel(np.asarray(inertia, float))), float(mass), frozen)
    system = _cached(key)
    return system


# -- closed forms --------------------------------------------------------------------------


def amended_frequency(spin_inertia, coupling, rate_inertia, d_spin, dd_spin, stiffness, h):
    """The frequency of a one-coordinate part's small oscillation about a relative equilibrium
    of a free body spinning about a fixed principal axis, from Routh's amended potential
    (Routh 1877; Goldstein, *Classical Mechanics*, §8.3 on cyclic coordinates; Hughes 1986,
    §8.1 on the energy–momentum method).

    With the spin angle cyclic, ``T = ½ I(θ) Ω² + b(θ) Ω θ̇ + ½ j(θ) θ̇²`` and the momentum
    ``h = I Ω + b θ̇`` fixed, the Routhian energy is ``h²/(2 I(θ)) + ½ (j − b²/I) θ̇² + V(θ)``
    (the term linear in θ̇ is a total derivative for one coordinate). About an equilibrium θ₀
    the frequency is ``√(U''/μ)``, ``U = h²/(2I) + V``, ``μ = j − b²/I``:
    ``U'' = h² (2 I'² / I³ − I'' / I²) / 2 + V''``.

    `spin_inertia` I(θ₀), `coupling` b(θ₀), `rate_inertia` j(θ₀), `d_spin`, `dd_spin` I' and
    I'' at θ₀, `stiffness` V''(θ₀).
    """
    i, b, j = spin_inertia, coupling, rate_inertia
    curvature = h**2 * (2 * d_spin**2 / i**3 - dd_spin / i**2) / 2 + stiffness
    return np.sqrt(curvature / (j - b**2 / i))


def free_swing_time(spin_inertia, coupling, rate_inertia, h, energy, theta0, theta1, sign=1.0):
    """The time a free part (no spring, no damping) takes from θ₀ to θ₁ on a body spinning
    about a fixed principal axis, by quadrature of the two integrals: with ``h`` and the
    energy ``E`` kept, ``½ μ(θ) θ̇² = E − h² / (2 I(θ))``, ``μ = j − b²/I`` (see
    `amended_frequency`), so ``t = ∫ √(μ / (2 (E − h²/(2I)))) dθ`` (scipy's quad). The
    body's rate at θ is ``Ω = (h − b θ̇) / I``. `spin_inertia`, `coupling`, `rate_inertia` are
    functions of θ; `sign` the direction of travel."""
    from scipy.integrate import quad

    def dt(theta):
        i = spin_inertia(theta)
        mu = rate_inertia(theta) - coupling(theta) ** 2 / i
        return np.sqrt(mu / (2.0 * (energy - h**2 / (2.0 * i))))

    value, _ = quad(dt, theta0, theta1, epsabs=0.0, epsrel=1e-13, limit=200)
    return sign * value


def free_swing_rate(spin_inertia, coupling, rate_inertia, h, energy, theta, sign=1.0):
    """``(θ̇, Ω)`` of the free part at θ (see `free_swing_time`)."""
    i = spin_inertia(theta)
    mu = rate_inertia(theta) - coupling(theta) ** 2 / i
    rate = sign * np.sqrt(2.0 * (energy - h**2 / (2.0 * i)) / mu)
    return rate, (h - coupling(theta) * rate) / i
