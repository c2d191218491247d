"""Results into files other tools read, and back.

- :func:`save` / :func:`load`: a `Trajectory`, `Batch`, `Sweep`, `DeploymentSweep` or
  `MonteCarlo` study as a netCDF-4 file (xarray with the h5netcdf engine; the ``io`` extra;
  :mod:`dzhanibekov.netcdf`). Arrays round-trip bit for bit, and the file carries what is
  needed to rebuild the object: each run's system (the body's tensor, a deployment's knots,
  the parts with their parameters, the wheels and the external torques), every part's state, so that what a loaded run derives
  (energy, angular momentum in space) is the saved run's, bit for bit.
- :func:`write_aem` / :func:`read_aem`: the attitudes of a trajectory (or of every run of a
  batch) as a CCSDS Attitude Ephemeris Message (CCSDS 504.0-B-2, KVN), the text file
  spacecraft attitude tools take (:mod:`dzhanibekov.aem`, where the attitude's direction
  and order are explained).

Every writer is all or nothing: the file is written beside its destination and renamed over
it once complete, so a failure (a full disk, Ctrl-C) leaves the previous file as it was.
Every reader refuses at once what is not a regular file (a FIFO, ``/dev/zero``), names the
format of a file of another kind, and checks what it reads as strictly as a run checks what
it computes; its errors are :class:`ReadError` (a ValueError) naming the file.
"""

from __future__ import annotations

from ._files import ReadError
from .aem import (
    AEM_UNIT_TOLERANCE,
    AEM_VERSIONS,
    MAX_AEM_BYTES,
    AemSegment,
    AttitudeEphemeris,
    read_aem,
    write_aem,
)
from .netcdf import load, save

__all__ = ["save", "load", "write_aem", "read_aem", "AttitudeEphemeris", "AemSegment",
           "ReadError", "AEM_VERSIONS", "AEM_UNIT_TOLERANCE", "MAX_AEM_BYTES"]
