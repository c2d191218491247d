"""The round-off a fixed step adds, per method: the `roundoff` (R) of the registry's step rule.

    python benches/python/step_roundoff.py                 # every fixed-step method, ~2 min
    python benches/python/step_roundoff.py rk4 rkmk4       # some

A run of n steps gathers round-off of about ``R · n · ε`` (ε = 2⁻⁵²) in the error measure of
``dt=None`` (ω in units of Ω, q absolute, the largest over the frames against
``method="exact"``). On three well-conditioned orbits (the HLW body (1, 1.7, 2.3) from
(0.4, −0.9, 0.6); (1, 2, 3) from (0.3, 1, 0.2); and the paper's body from (0.01, 0.01, 1),
whose flips pass near the separatrix and amplify every error) over T = 2000, at steps
``hΩ`` = 0.002 and 0.001 where the truncation error of the fourth- and sixth-order methods
is far below the round-off, it prints ``error / (n ε)``. The registry's ``roundoff`` is the
largest over the two well-conditioned orbits; the second- and third-order methods are still
truncation-bound there (no step reaches their round-off in practice) and take RK4's.
"""

from __future__ import annotations

import sys
import warnings

import numpy as np

import dzhanibekov as dz

CASES = [((1.0, 1.7, 2.3), (0.4, -0.9, 0.6)), ((1.0, 2.0, 3.0), (0.3, 1.0, 0.2)),
         ((52.0833, 27.0833, 41.6666), (0.01, 0.01, 1.0))]
STEP_RATES = (0.002, 0.001)
T_END = 2000.0


def main() -> None:
    methods = sys.argv[1:] or [m for m, info in dz.METHODS.items()
                               if not info.adaptive and m != "exact" and "free" in info.models]
    warnings.simplefilter("ignore", dz.StepSizeWarning)
    for method in methods:
        for inertia, omega0 in CASES:
            i, w = np.array(inertia), np.array(omega0)
            rate = float(np.sqrt(i @ w**2 / i.min()))
            exact = dz.simulate(inertia, omega0, t_end=T_END, frames=11, method="exact")
            cells = []
            for x in STEP_RATES:
                traj = dz.simulate(inertia, omega0, t_end=T_END, frames=11, method=method,
                                   dt=x / rate, flips=False)
                dq = np.minimum(np.abs(traj.q - exact.q), np.abs(traj.q + exact.q)).max()
                err = max(np.abs(traj.omega - exact.omega).max() / rate, dq)
                r = err / (traj.n_steps * np.finfo(float).eps)
                cells.append(f"hΩ = {x:g}: {err:.1e}, R = {r:.3f}")
            print(f"{method:17s} {inertia}  " + " | ".join(cells), flush=True)


if __name__ == "__main__":
    main()
