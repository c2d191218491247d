"""Measured accuracy of method="exact" against independent references (not a test: prints).

    python benches/python/exact_accuracy.py

- ω against the mpmath solution (50 digits) to T = 1000 on the paper's cases;
- ω and q against the longdouble Taylor integrator (tests/python/reference.py) to T = 1000
  (T = 90 on the ill-conditioned example, where that reference's own error grows);
- the invariants' largest drift over 201 frames to T = 10⁶;
- sn, cn, dn against mpmath at 1 − m = 1e-15 for arguments up to 25 K.
"""

import pathlib
import sys

import mpmath as mp
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tests" / "python"))
from reference import ExactOmegaMP, taylor_longdouble  # noqa: E402

import dzhanibekov as dz  # noqa: E402
from dzhanibekov import _core  # noqa: E402


def main() -> None:
    print("case     | ω vs mpmath, T=1000 | ω, q vs longdouble Taylor      | drift to T=1e6")
    for name in ("example", "fig3a", "fig3b", "fig3c"):
        s = dz.SCENES[name]
        scale = np.abs(s.omega0).max()
        traj = dz.simulate(s.body, s.omega0, s.q0, t_end=1000.0, frames=201, method="exact")
        e_mp = np.abs(traj.omega - ExactOmegaMP(s.inertia, s.omega0)(traj.t)).max() / scale
        t_end = 90.0 if name == "example" else 1000.0
        traj = dz.simulate(s.body, s.omega0, s.q0, t_end=t_end, frames=201, method="exact")
        w, q = taylor_longdouble(s.inertia, s.omega0, s.q0, traj.t,
                                 h=0.25 if name == "fig3a" else 0.5)
        e_w, e_q = np.abs(traj.omega - w).max() / scale, np.abs(traj.q - q).max()
        long = dz.simulate(s.body, s.omega0, s.q0, t_end=1e6, frames=201, method="exact")
        print(f"{name:8} | {e_mp:19.1e} | {e_w:8.1e} {e_q:8.1e} (T={t_end:g}) | "
              f"{max(long.drift):.1e}")
    m1 = 1e-15
    k = _core.ellipk(1 - m1, m1)
    u = k * np.array([0.1, 0.5, 0.999, 1.0, 1.5, 2.3, 9.0, 10.5, 25.0])
    got = np.stack(_core.ellipj(u, 1 - m1, m1), axis=-1)
    with mp.workdps(60):
        m = 1 - mp.mpf(m1)
        ref = np.array([[float(mp.ellipfun(f, mp.mpf(x), m=m)) for f in ("sn", "cn", "dn")]
                        for x in u])
    err = np.abs(got - ref)
    print(f"1 - m = 1e-15, u up to 25K: max |error| sn {err[:, 0].max():.1e}, "
          f"cn {err[:, 1].max():.1e}, dn {err[:, 2].max():.1e}; "
          f"dn relative {np.max(err[:, 2] / ref[:, 2]):.1e}")


if __name__ == "__main__":
    main()
