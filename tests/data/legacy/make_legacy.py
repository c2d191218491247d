"""Writes the files of tests/data/legacy/: results saved by dzhanibekov at main 3f80f7e
(the layout before parts were written generically, issue 29), so that tests check that files
written by earlier versions keep loading.

Run with that version's package, e.g.::

    git archive 3f80f7e python | tar -x -C /tmp/old
    cp python/dzhanibekov/_core.abi3.so /tmp/old/python/dzhanibekov/
    PYTHONPATH=/tmp/old/python python tests/data/legacy/make_legacy.py tests/data/legacy

The systems are the ones tests/python/io/test_legacy_files.py rebuilds and compares with.
"""

import sys
from pathlib import Path

import dzhanibekov as dz

BODY = dz.Body((2.0, 3.0, 1.0))
ORBITER = dz.System(BODY, parts=[dz.Wheel((0, 2, 0), 0.1), dz.Damper(0.05, 0.02),
                                 dz.Wheel((1, 0, 1), -0.3)],
                    torques=[dz.ConstantTorque((0.0, 0.0, 1e-3), frame="world"),
                             dz.GravityGradient(1.0), dz.ConstantTorque((1e-3, 0.0, 0.0))])
TABLED = dz.System(BODY, parts=[dz.Wheel((0, 2, 0), 0.1),
                                dz.Wheel((1, 0, 1), ([0.0, 0.5, 1.0], [0.0, 0.2, 0.1]))],
                   torques=[dz.TabulatedTorque([0.0, 0.5, 1.0], [(0, 0, 1e-3)] * 3),
                            dz.GravityGradient(1.0),
                            dz.TabulatedTorque([0.2, 0.4], [(1e-3, 0, 0), (0, 1e-3, 0)],
                                               frame="world", outside="hold")])
DAMPED = dz.System(dz.Body((1.0, 2.0, 3.0)), parts=[dz.Damper(0.1, 0.05, (0.1, 0.2, 0.3))])
ROWS = [dz.System(BODY, parts=[dz.Wheel((0, 1, 0), 0.2)],
                  torques=[dz.ConstantTorque((0.0, 1e-3, 0.0))]),
        dz.System(BODY, parts=[dz.Wheel((0, 1, 0), 0.2), dz.Wheel((0, 0, 1), 0.1)],
                  torques=[dz.ConstantTorque((0.0, 1e-3, 0.0)),
                           dz.ConstantTorque((0.0, 0.0, 1e-3), frame="world")])]


def main(out: Path) -> None:
    start = dz.lvlh_start(1.0)
    dz.save(dz.simulate(ORBITER, *start, t_end=1.0, frames=3, method="rk4", dt=0.01),
            out / "orbiter.nc")
    dz.save(dz.simulate(TABLED, *start, t_end=1.0, frames=3, method="rk4", dt=0.01),
            out / "tabled.nc")
    dz.save(dz.simulate(DAMPED, (0.3, 0.2, 1.0), t_end=1.0, frames=3, method="rk4", dt=0.01),
            out / "damped.nc")
    dz.save(dz.simulate(ROWS, (0.1, 1.0, 0.0), t_end=1.0, frames=3, method="rk4", dt=0.01),
            out / "rows.nc")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
