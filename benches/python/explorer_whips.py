"""Explorer 1 with its four whip antennas as hinged appendages: the energy-sink estimate of
its minor-axis spin going flat, and the simulated time (issue 31's first scene, run long):

    python benches/python/explorer_whips.py                 # 9000 s, RK4 dt = 5e-4 (a minute)
    python benches/python/explorer_whips.py --zeta 0.015    # the damping first assumed

The shipped scene ``explorer-1-whips`` is this system run by dop853; this script runs it by RK4
at a fixed step, to time the four hinges' step and to look at other dampings.

The body (NASA NSSDCA Master Catalog 1958-001A; JPL): a cylinder 2.03 m long and 0.152 m
across, 13.97 kg in all, spun about its long (minor) axis at 750 rpm. The sources give no
antenna properties: each whip is taken as a steel rod 0.56 m (22 in) long and 1.5 mm across
(7.8 g), rigid, hinged at the body's surface at its mid-section, its torsional spring giving
the rod's first cantilever bending mode (3.38 Hz: ``k = (2π f)² m L² / 3``), with 8.5 % of
critical damping by default: no source gives it, so it is fitted, as in the scene, to the
account that the spin axis had turned about 90° after about one orbit (Bollay, Stanford ECL
1006, 1967); each hinge axis normal to the spin axis and to its rod (the flap out of the
spin plane, which the nutation drives). The start: a nutation of about 4° (ω₀ = (0.05, 0,
78.54) rad/s). Prints the estimate's time constant ``τ`` and its small-angle time to each
share of ``|H|`` across the long axis (``sin θ = share``, ``tan θ = tan θ₀ e^{t/τ}``), and the
times the run reaches them.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import dzhanibekov as dz
from dzhanibekov import energy_sink

MASS, LENGTH, RADIUS, HEIGHT = 13.97, 2.03, 0.076, 0.56
WHIP, ZETA, MODE = 0.0078, 0.085, 3.38


def explorer(zeta: float = ZETA) -> tuple[object, object, list[object]]:
    """The hub and the four hinged whips, with `zeta` of critical damping."""
    end = WHIP * HEIGHT**2 / 3             # about the hinge
    own = WHIP * HEIGHT**2 / 12            # about its centre
    k = (2 * np.pi * MODE) ** 2 * end
    c = 2 * zeta * np.sqrt(k * end)
    hub = dz.Body.cylinder(RADIUS, LENGTH, mass=MASS - 4 * WHIP)
    arms = [((1, 0, 0), (0, 1, 0)), ((-1, 0, 0), (0, 1, 0)),
            ((0, 1, 0), (1, 0, 0)), ((0, -1, 0), (1, 0, 0))]
    whips = [dz.Hinge(WHIP, (0.0, own, own), tuple(RADIUS * np.array(a, float)), axis, a,
                      HEIGHT / 2, k, c) for a, axis in arms]
    return hub, dz.System(hub, parts=whips), whips


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=9000.0)
    parser.add_argument("--dt", type=float, default=5e-4)
    parser.add_argument("--zeta", type=float, default=ZETA, help="the share of critical damping")
    args = parser.parse_args()
    hub, system, whips = explorer(args.zeta)
    omega0 = (0.05, 0.0, 750 * 2 * np.pi / 60)
    est = energy_sink.estimate(np.diag(hub.inertia), MASS - 4 * WHIP,
                               [("hinge", w) for w in whips], omega0)
    shares = (0.5, 0.9, 0.99)
    print(f"estimate: tau = {est.time_constant:.0f} s, theta0 = {np.degrees(est.theta0):.2f} deg,"
          f" spin {est.spin:.2f} rad/s, nutation in the body {est.nutation:.2f} rad/s")
    for s in shares:
        t = est.time_constant * np.log(np.tan(np.arcsin(s)) / np.tan(est.theta0))
        print(f"  estimate: share {s} of |H| across the long axis at t = {t:.0f} s")
    cpu, wall = time.process_time(), time.perf_counter()
    traj = dz.simulate(system, omega0, t_end=args.t_end, frames=4001, dt=args.dt, flips=False)
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    print(f"run: {traj.n_steps} RK4 steps, {cpu:.1f} s CPU ({wall:.1f} s wall), "
          f"{cpu / traj.n_steps * 1e9:.0f} ns a step; drift {traj.drift}")
    h = np.asarray(traj.momentum_body)
    across = np.hypot(h[:, 0], h[:, 1]) / np.linalg.norm(h, axis=1)
    for s in shares:
        reached = np.flatnonzero(across >= s)
        at = f"t = {traj.t[reached[0]]:.0f} s" if reached.size else "not in the run"
        print(f"  run: share {s} at {at}")
    print(f"  run: share {across[-1]:.3f} at the end, t = {traj.t[-1]:.0f} s")


if __name__ == "__main__":
    main()
