"""CCSDS Attitude Ephemeris Messages: a run's attitudes as the text file spacecraft attitude
tools take (CCSDS 504.0-B-2, KVN), and back.

**The attitude in an AEM.** The package's ``q`` is world-from-body, scalar first:
``x_world = M(q) x_body``. Read as a *coordinate transformation*, the same q takes a
vector's world coordinates to its body coordinates: ``x_body = M(q)ᵀ x_world``, and its
axis and angle are those of the rotation that carries the world axes onto the body axes.
That is the AEM's quaternion from ``REF_FRAME_A`` (the world: the inertial frame the run's
attitudes are given in, which only the caller knows — ``EME2000``, ``ICRF``, …) to
``REF_FRAME_B`` (the body, ``SC_BODY_1``), with the same four numbers: version 2.0 (the
default) writes them scalar last, ``Q1 Q2 Q3 QC`` = ``U V W Q``, as the standard fixes;
version 1.0 says ``ATTITUDE_DIR = A2B`` and ``QUATERNION_TYPE = FIRST`` and writes
``QC Q1 Q2 Q3`` = ``Q U V W``. Rates (``rates=True``) are the body's angular velocity in
body axes (``ANGVEL_FRAME``/``RATE_FRAME`` = ``REF_FRAME_B``), in degrees per second as the
standard asks.

**Segments.** A `Trajectory` is one segment; a `Batch` one segment per run (each with a
``COMMENT run K of M``). :func:`read_aem` reads every segment.

**What the reader accepts.** A regular file of at most :data:`MAX_AEM_BYTES`, ASCII, in
order: the header, then segments of ``META_START`` … ``META_STOP`` and ``DATA_START`` …
``DATA_STOP``; epochs that exist (``YYYY-MM-DDThh:mm:ss[.d…]`` or ``YYYY-DDDThh:mm:ss[.d…]``,
years 0001 to 9999, a leap second ``23:59:60`` allowed), strictly increasing within a
segment and inside its ``START_TIME``/``STOP_TIME``; finite numbers; quaternions of unit
norm to :data:`AEM_UNIT_TOLERANCE`. Anything else is a :class:`~dzhanibekov.io.ReadError`
naming the file and line. The file is read line by line: the memory held is that of the
rows kept.
"""

from __future__ import annotations

import array
import datetime as _dt
import re
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any, NamedTuple

import numpy as np

from ._args import check_size
from ._files import ReadError, as_path, describe, open_regular, replacing, size_of
from .results import Batch, Trajectory

__all__ = ["write_aem", "read_aem", "AttitudeEphemeris", "AemSegment", "AEM_VERSIONS",
           "AEM_UNIT_TOLERANCE", "MAX_AEM_BYTES"]

AEM_VERSIONS = ("1.0", "2.0")
"""The versions written and read: CCSDS 504.0-B-1 (1.0) and 504.0-B-2 (2.0)."""

AEM_UNIT_TOLERANCE = 1e-5
"""How far from 1 a quaternion's norm may be, in a file read or written: files written to
six significant digits pass; a quaternion further off is no attitude."""

MAX_AEM_BYTES = 1 << 32
"""The largest AEM file :func:`read_aem` reads (4 GiB, some 40 million data lines); the
memory the rows need is checked too, before the first is read."""

BYTES_PER_ROW = 8 * (2 + 4 + 3) + 80
"""Memory a kept data line takes: its time, line number, quaternion and rates (8 bytes
each) and its epoch as written (a str)."""

SHORTEST_ROW = 26
"""The shortest data line: ``2026-001T00:00:00 1 0 0 0`` and its newline."""

_EPOCH = re.compile(r"^(\d{4})-(?:(\d{2})-(\d{2})|(\d{3}))T(\d{2}):(\d{2}):(\d{2})(?:\.(\d*))?Z?$")
_NUMBER = re.compile(r"^[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?$")
_US_PER_DAY = 86_400_000_000


# -- epochs ----------------------------------------------------------------------------------


class _Epochs:
    """Parses CCSDS epochs into integer microseconds since 0001-01-01 (exact: differences
    up to 285 years convert to float64 seconds without rounding), the day's ordinal cached."""

    def __init__(self) -> None:
        self._days: dict[str, int] = {}

    def micros(self, text: str) -> int:
        """Microseconds since 0001-01-01T00:00:00 of `text`; ValueError saying what is wrong."""
        ordinal = self._days.get(text[:10])
        if (ordinal is not None and len(text) >= 19 and text[10] == "T" and text[13] == ":"
                and text[16] == ":"):  # the common form, its date seen before: no regex
            hour, minute, second, fraction = text[11:13], text[14:16], text[17:19], text[19:]
            if fraction[-1:] == "Z":
                fraction = fraction[:-1]
            if (hour.isdigit() and minute.isdigit() and second.isdigit()
                    and (not fraction or fraction[0] == "." and (len(fraction) == 1
                                                                 or fraction[1:].isdigit()))):
                h, m, s = int(hour), int(minute), int(second)
                if h < 24 and m < 60 and s < 60:  # else (a leap second) as below
                    return (ordinal * _US_PER_DAY + ((h * 60 + m) * 60 + s) * 1_000_000
                            + int(fraction[1:7].ljust(6, "0") or 0))
        return self._micros(text)

    def _micros(self, text: str) -> int:
        match = _EPOCH.match(text)
        if match is None:
            raise ValueError(f"{text!r} is not an epoch like 2026-01-01T00:00:00.000 or "
                             "2026-001T00:00:00 (years 0001 to 9999)")
        year, month, day, doy, hour, minute, second, fraction = match.groups()
        key = text[: match.end(4) if doy is not None else match.end(3)]
        ordinal = self._days.get(key)
        if ordinal is None:
            ordinal = self._ordinal(text, int(year), month, day, doy)
            self._days[key] = ordinal
        h, m, s = int(hour), int(minute), int(second)
        if h > 23 or m > 59 or s > 60 or (s == 60 and (h, m) != (23, 59)):
            raise ValueError(f"{text!r} is not a time of day (hh < 24, mm < 60, ss < 60; "
                             "a leap second only at 23:59:60)")
        micro = int((fraction or "").ljust(6, "0")[:6])  # to the µs, as written
        return ordinal * _US_PER_DAY + ((h * 60 + m) * 60 + s) * 1_000_000 + micro

    @staticmethod
    def _ordinal(text: str, year: int, month: str | None, day: str | None,
                 doy: str | None) -> int:
        if year < 1:
            raise ValueError(f"{text!r} has year 0000; years run from 0001 to 9999")
        try:
            if doy is None:
                assert month is not None and day is not None
                return _dt.date(year, int(month), int(day)).toordinal()
            days = 366 if _dt.date(year, 12, 31).timetuple().tm_yday == 366 else 365
            if not 1 <= int(doy) <= days:
                raise ValueError(f"day of year {doy} is not in 001 to {days:03d}")
            return _dt.date(year, 1, 1).toordinal() + int(doy) - 1
        except ValueError as exc:
            raise ValueError(f"{text!r} is not a date: {exc}") from None


def _parse_epoch(text: str, what: str) -> _dt.datetime:
    """A CCSDS epoch as a datetime (to the µs); a leap second is the next day's 00:00:00."""
    try:
        micros = _Epochs().micros(text.strip())
    except ValueError as exc:
        raise ValueError(f"`{what}` must be a time like 2026-01-01T00:00:00.000: {exc}") \
            from None
    return _dt.datetime.min + _dt.timedelta(microseconds=micros - _US_PER_DAY)


def _epoch(value: Any) -> _dt.datetime:
    if isinstance(value, _dt.datetime):
        if value.tzinfo is not None:
            return value.astimezone(_dt.timezone.utc).replace(tzinfo=None)
        return value
    if isinstance(value, str):
        return _parse_epoch(value, "epoch")
    raise TypeError(f"`epoch` must be a datetime or an ISO 8601 string, got "
                    f"{type(value).__name__}")


def _format_epoch(t: _dt.datetime) -> str:
    return t.strftime("%Y-%m-%dT%H:%M:%S.%f")


def _keyword(name: str, value: Any) -> str:
    if not isinstance(value, str):
        raise TypeError(f"`{name}` must be a str, got {type(value).__name__}")
    text = value.strip()
    if not text or "\n" in value or not text.isprintable() or not text.isascii():
        raise ValueError(f"`{name}` must be one printable line of ASCII text, got {value!r}")
    return text


# -- writing ---------------------------------------------------------------------------------


def write_aem(
    traj: Trajectory | Batch,
    path: str | Path,
    object_name: str | Sequence[str],
    object_id: str | Sequence[str],
    epoch: _dt.datetime | str,
    *,
    ref_frame_a: str | None = None,
    time_unit: float = 1.0,
    ref_frame_b: str = "SC_BODY_1",
    center_name: str | None = None,
    time_system: str = "UTC",
    originator: str = "DZHANIBEKOV",
    rates: bool = False,
    version: str = "2.0",
    comment: str | None = None,
) -> Path:
    """Writes the attitudes of a run (or of every run of a batch) as a CCSDS Attitude
    Ephemeris Message (KVN text), all or nothing.

    One data line per frame: its epoch and quaternion (and with `rates`, the body rates).
    The quaternion is the package's ``q`` unchanged in value: the transformation from
    `ref_frame_a` (the world) to `ref_frame_b` (the body) — see the module's docs. A batch
    is written as one segment per run.

    Parameters
    ----------
    traj : Trajectory or Batch
    path : str or Path
        The file to write (``.aem`` by convention); replaced only once complete.
    object_name, object_id : str, or a sequence of str (one per run of a batch)
        The spacecraft's name and its international designator (``YYYY-NNNP{PP}``).
    epoch : datetime or str
        The time of the first frame (``t = 0``), in `time_system`; a string like
        ``"2026-01-01T00:00:00"``. Epochs are written to the microsecond.
    ref_frame_a : str
        The inertial frame the run's world axes are — ``"EME2000"``, ``"ICRF"``, … —
        written as ``REF_FRAME_A``. Required: the package's world frame is whatever
        inertial frame `q0` was given in, which only the caller knows.
    time_unit : float
        Seconds per time unit of the run (the package's units are the user's own).
    ref_frame_b : str
        The body frame's CCSDS name.
    center_name : str, optional
        Written as ``CENTER_NAME`` when given.
    time_system : str
        ``TIME_SYSTEM``, e.g. UTC, TAI, TT, GPS.
    originator : str
    rates : bool
        Also write the body rates: ``QUATERNION/ANGVEL`` (version 2.0) or
        ``QUATERNION/RATE`` (version 1.0), in degrees per second, in body axes.
    version : {"2.0", "1.0"}
        ``CCSDS_AEM_VERS``: 2.0 (CCSDS 504.0-B-2) fixes the order ``Q1 Q2 Q3 QC`` and the
        direction A to B; 1.0 (504.0-B-1) states them (``QUATERNION_TYPE = FIRST``,
        ``ATTITUDE_DIR = A2B``).
    comment : str, optional
        A ``COMMENT`` line in the metadata.

    Returns
    -------
    Path

    Raises
    ------
    TypeError
        `traj` is neither a Trajectory nor a Batch, or `epoch` not a time.
    ValueError
        A keyword value that is empty or not one line of ASCII, a bad `version` or
        `time_unit`, frames closer than the microsecond epochs resolve or later than year
        9999, or quaternions further from unit norm than :data:`AEM_UNIT_TOLERANCE`.
    OSError
        The file cannot be written (its folder is missing, the disk is full): the previous
        file is as it was.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), frames=3)
    >>> dz.io.write_aem(traj, "box.aem", "BOX", "2026-001A", "2026-01-01T00:00:00",
    ...                 ref_frame_a="EME2000")                     # doctest: +SKIP
    PosixPath('box.aem')
    """
    if not isinstance(traj, (Trajectory, Batch)):
        raise TypeError(f"`traj` must be a Trajectory or a Batch, got {type(traj).__name__}")
    runs = 1 if isinstance(traj, Trajectory) else len(traj)
    if version not in AEM_VERSIONS:
        raise ValueError(f"`version` must be one of {AEM_VERSIONS}, got {version!r}")
    if (isinstance(time_unit, bool) or not isinstance(time_unit, (int, float))
            or not np.isfinite(time_unit) or time_unit <= 0):
        raise ValueError(f"`time_unit` must be a positive number of seconds, got {time_unit!r}")
    if not isinstance(rates, (bool, np.bool_)):
        raise TypeError(f"`rates` must be True or False, got {type(rates).__name__}")
    names = _per_run("object_name", object_name, runs)
    ids = _per_run("object_id", object_id, runs)
    if ref_frame_a is None:
        raise TypeError("write_aem() needs `ref_frame_a`: the inertial frame the run's world "
                        "axes are ('EME2000', 'ICRF', …), written as REF_FRAME_A; the "
                        "package's world frame is whatever frame q0 was given in, which only "
                        "you know")
    frame_a = _keyword("ref_frame_a", ref_frame_a)
    frame_b = _keyword("ref_frame_b", ref_frame_b)
    center = None if center_name is None else _keyword("center_name", center_name)
    system = _keyword("time_system", time_system)
    note = None if comment is None else _keyword("comment", comment)
    start = _epoch(epoch)
    epochs = _epochs_of(np.asarray(traj.t, dtype=np.float64), start, float(time_unit))
    q_all = traj.q.reshape(runs, len(traj.t), 4)
    omega_all = traj.omega.reshape(runs, len(traj.t), 3)
    norm = np.sqrt(np.einsum("...i,...i->...", q_all, q_all))
    off = float(np.abs(norm - 1.0).max(initial=0.0))
    if not off <= AEM_UNIT_TOLERANCE:
        raise ValueError(f"`traj.q` departs from unit norm by {off:.3g}, more than the "
                         f"{AEM_UNIT_TOLERANCE:g} an AEM's quaternions may (readers take them "
                         "as rotations): normalise it, or run with a smaller dt")
    header = [f"CCSDS_AEM_VERS = {version}",
              f"CREATION_DATE = {_format_epoch(_dt.datetime.now(_dt.timezone.utc))}",
              f"ORIGINATOR = {_keyword('originator', originator)}", ""]
    with replacing(path) as tmp:
        with open(tmp, "w", encoding="ascii", newline="\n") as f:
            f.write("\n".join(header) + "\n")
            for run in range(runs):
                meta = _metadata(version, names[run], ids[run], center, frame_a, frame_b,
                                 system, epochs, bool(rates), note,
                                 f"run {run + 1} of {runs}" if runs > 1 else None)
                f.write("\n".join(meta) + "\n\n")
                _write_data(f, epochs, q_all[run], omega_all[run], version, bool(rates),
                            float(time_unit))
    return as_path(path)


def _per_run(name: str, value: Any, runs: int) -> list[str]:
    if isinstance(value, str):
        return [_keyword(name, value)] * runs
    if isinstance(value, Sequence) and not isinstance(value, (bytes, bytearray)):
        if len(value) != runs:
            raise ValueError(f"`{name}` must be one str, or one per run ({runs}), got "
                             f"{len(value)}")
        return [_keyword(f"{name}[{k}]", v) for k, v in enumerate(value)]
    raise TypeError(f"`{name}` must be a str (or one per run of a batch), got "
                    f"{type(value).__name__}")


def _epochs_of(t: np.ndarray, start: _dt.datetime, time_unit: float) -> list[str]:
    """The frames' epochs as written, refused if later than year 9999 or not increasing at
    the microsecond."""
    last = float(t[-1]) * time_unit
    room = (_dt.datetime.max - start).total_seconds()
    if not last <= room:
        raise ValueError(
            f"the last frame's epoch, `epoch` + t_end × `time_unit` = {start.isoformat()} + "
            f"{last:.6g} s, is past 9999-12-31T23:59:59.999999, the last epoch an AEM holds; "
            "give an earlier `epoch` or a smaller `time_unit`")
    micros = np.round(t * (time_unit * 1e6))
    if len(micros) > 1 and not (np.diff(micros) > 0).all():
        spacing = float(np.diff(t).min()) * time_unit
        raise ValueError(
            f"frames {spacing:.3g} s apart (the closest, with `time_unit` = {time_unit:g}) "
            "get the same epoch at the microsecond an AEM's epochs are written to; give a "
            "larger `time_unit` or fewer frames")
    return [_format_epoch(start + _dt.timedelta(microseconds=int(m))) for m in micros]


def _metadata(version: str, name: str, ident: str, center: str | None, frame_a: str,
              frame_b: str, system: str, epochs: list[str], rates: bool,
              comment: str | None, run: str | None) -> list[str]:
    meta = ["META_START"]
    meta += [f"COMMENT {c}" for c in (comment, run) if c is not None]
    meta += [f"OBJECT_NAME = {name}", f"OBJECT_ID = {ident}"]
    if center is not None:
        meta.append(f"CENTER_NAME = {center}")
    meta += [f"REF_FRAME_A = {frame_a}", f"REF_FRAME_B = {frame_b}"]
    if version == "1.0":
        meta.append("ATTITUDE_DIR = A2B")
    meta += [f"TIME_SYSTEM = {system}", f"START_TIME = {epochs[0]}",
             f"STOP_TIME = {epochs[-1]}"]
    if version == "1.0":
        meta.append(f"ATTITUDE_TYPE = {'QUATERNION/RATE' if rates else 'QUATERNION'}")
        meta.append("QUATERNION_TYPE = FIRST")
        if rates:
            meta.append("RATE_FRAME = REF_FRAME_B")
    else:
        meta.append(f"ATTITUDE_TYPE = {'QUATERNION/ANGVEL' if rates else 'QUATERNION'}")
        if rates:
            meta.append(f"ANGVEL_FRAME = {frame_b}")
    meta.append("META_STOP")
    return meta


def _write_data(f: IO[str], epochs: list[str], q: np.ndarray, omega: np.ndarray,
                version: str, rates: bool, time_unit: float) -> None:
    q = q if version == "1.0" else q[:, [1, 2, 3, 0]]
    values = np.concatenate([q] + ([np.degrees(omega) / time_unit] if rates else []), axis=1)
    f.write("DATA_START\n")
    chunk = 4096
    for k in range(0, len(epochs), chunk):
        rows = values[k: k + chunk].tolist()
        f.write("".join(" ".join([e] + [repr(x) for x in row]) + "\n"
                        for e, row in zip(epochs[k: k + chunk], rows)))
    f.write("DATA_STOP\n\n")


# -- reading ---------------------------------------------------------------------------------


class AemSegment(NamedTuple):
    """One segment of an AEM: its metadata and data, in the package's convention."""

    metadata: dict[str, str]
    """The segment's metadata keywords (``OBJECT_NAME``, ``REF_FRAME_A`` …)."""
    epochs: list[str]
    """The data lines' epochs as written."""
    t: np.ndarray
    """Seconds since the first epoch of the file (the first segment's first), shape (N,)."""
    q: np.ndarray
    """Unit quaternions (N, 4), scalar first, world-from-body (``REF_FRAME_A``-from-
    ``REF_FRAME_B``), whatever order and direction the file used; as written (not
    renormalised)."""
    omega: np.ndarray | None
    """Angular velocity (N, 3) in body axes (``REF_FRAME_B``), rad/s; None without rates."""


class AttitudeEphemeris(NamedTuple):
    """What :func:`read_aem` read: the header and every segment. For a file of one segment
    (as :func:`write_aem` writes a `Trajectory`), `metadata`, `epochs`, `t`, `q` and `omega`
    are that segment's."""

    header: dict[str, str]
    """The header's keywords (``CCSDS_AEM_VERS``, ``CREATION_DATE``, ``ORIGINATOR`` …)."""
    segments: tuple[AemSegment, ...]
    """Every segment, in the file's order (a `Batch`: one per run)."""

    def _only(self) -> AemSegment:
        if len(self.segments) != 1:
            raise ValueError(f"this AEM has {len(self.segments)} segments: take each from "
                             "`.segments`")
        return self.segments[0]

    @property
    def metadata(self) -> dict[str, str]:
        """The one segment's metadata (ValueError for a file of several segments)."""
        return self._only().metadata

    @property
    def epochs(self) -> list[str]:
        """The one segment's epochs as written."""
        return self._only().epochs

    @property
    def t(self) -> np.ndarray:
        """The one segment's times, seconds since its first epoch, shape (N,)."""
        return self._only().t

    @property
    def q(self) -> np.ndarray:
        """The one segment's quaternions (N, 4), scalar first, world-from-body."""
        return self._only().q

    @property
    def omega(self) -> np.ndarray | None:
        """The one segment's body rates (N, 3) in rad/s, or None."""
        return self._only().omega


_RATE_TYPES = ("QUATERNION/ANGVEL", "QUATERNION/RATE")
_HEADER_REQUIRED = ("CCSDS_AEM_VERS", "CREATION_DATE", "ORIGINATOR")
_META_REQUIRED = ("OBJECT_NAME", "OBJECT_ID", "REF_FRAME_A", "REF_FRAME_B", "TIME_SYSTEM",
                  "START_TIME", "STOP_TIME", "ATTITUDE_TYPE")


class _Segment:
    """A segment being read: its rows in growing typed arrays (memory ∝ rows)."""

    def __init__(self, metadata: dict[str, str], line: int) -> None:
        self.metadata = metadata
        self.line = line
        self.epochs: list[str] = []
        self.micros = array.array("q")
        self.values = array.array("d")
        self.lines = array.array("q")
        """The file's line number of each data line (for messages)."""


def read_aem(path: str | Path) -> AttitudeEphemeris:
    """Reads a CCSDS Attitude Ephemeris Message (KVN) of quaternions: every segment.

    Versions 1.0 and 2.0; ``QUATERNION`` and ``QUATERNION/ANGVEL`` (2.0) or
    ``QUATERNION/RATE`` (1.0). The quaternions are returned in the package's convention
    (scalar first, world-from-body), turned from the file's order and direction. The file is
    read line by line, after its size is checked (:data:`MAX_AEM_BYTES`, and the memory its
    rows could need).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    AttitudeEphemeris

    Raises
    ------
    ReadError
        (a ValueError) Not a regular file (a FIFO, a device, a folder), missing, too large,
        not an ASCII AEM (another format is named), an attitude type other than
        quaternions, a missing keyword or section, a data line of the wrong length, a
        number that is not finite, an epoch that does not exist or runs backwards, or a
        quaternion not of unit norm: the message names the file and the line.

    Examples
    --------
    >>> import dzhanibekov as dz
    >>> aem = dz.io.read_aem("box.aem")                              # doctest: +SKIP
    >>> aem.q.shape, aem.metadata["REF_FRAME_A"]                     # doctest: +SKIP
    ((3, 4), 'EME2000')
    """
    p = as_path(path)
    what = "a CCSDS AEM (KVN text)"
    with open_regular(p, what) as f:
        size = size_of(f)
        if size > MAX_AEM_BYTES:
            raise ReadError(f"{p} holds {size} bytes, more than the {MAX_AEM_BYTES} "
                            f"(MAX_AEM_BYTES) read_aem reads", path=str(p))
        check_size(size // SHORTEST_ROW * BYTES_PER_ROW, f"reading {p}'s data lines",
                   "split the file, or read it in pieces")
        head = f.read(64)
        if not head.lstrip(b"\xef\xbb\xbf \t\r\n").startswith((b"CCSDS_AEM_VERS", b"COMMENT")):
            raise ReadError(f"{p} is {describe(head)}, not {what}: it must begin with "
                            "CCSDS_AEM_VERS", path=str(p))
        f.seek(0)
        try:
            return _read(f, p)
        except ValueError as exc:
            if isinstance(exc, ReadError):
                raise
            raise ReadError(f"{p}: {exc}", path=str(p)) from None


def _read(f: IO[bytes], p: Path) -> AttitudeEphemeris:
    header: dict[str, str] = {}
    segments: list[_Segment] = []
    state = "header"  # header, meta, between (after META_STOP), data, done (after DATA_STOP)
    meta: dict[str, str] = {}
    current: _Segment | None = None
    layout: tuple[int, bool] = (4, False)  # fields after the epoch, rates
    width = 5  # fields of a data line
    epochs = _Epochs()
    number = 0

    def fail(message: str) -> ReadError:
        return ReadError(f"{p}:{number}: {message}", path=str(p))

    for number, raw in enumerate(f, 1):
        try:
            line = raw.decode("ascii").strip()
        except UnicodeDecodeError as exc:
            raise fail(f"is not ASCII text (byte {raw[exc.start]:#04x}); a KVN AEM is "
                       "ASCII") from None
        if not line or line.startswith("COMMENT"):
            continue
        if state == "data" and line != "DATA_STOP":  # the hot path: one data line
            assert current is not None
            fields = line.split()
            if len(fields) != width:
                raise fail(f"a data line of {current.metadata['ATTITUDE_TYPE']} has {width} "
                           f"fields (the epoch and {width - 1} numbers), got {len(fields)}")
            try:
                if "_" in line:  # float() reads 1_0 as 10; a KVN number has no underscore
                    raise ValueError
                current.values.extend(map(float, fields[1:]))
            except ValueError:
                del current.values[len(current.epochs) * (width - 1):]
                bad = next((x for x in fields[1:] if not _NUMBER.match(x)), fields[1])
                raise fail(f"{bad[:40]!r} is not a number") from None
            current.epochs.append(fields[0])  # parsed all at once when the segment ends
            current.lines.append(number)
            continue
        if line == "META_START":
            if state not in ("header", "done"):
                raise fail(f"META_START inside a segment ({_expected(state)})")
            if state == "header":
                _check_header(header, fail)
            state, meta = "meta", {}
        elif line == "META_STOP":
            if state != "meta":
                raise fail(f"META_STOP without META_START ({_expected(state)})")
            layout = _check_metadata(meta, header["CCSDS_AEM_VERS"], fail)
            width = layout[0] + 1
            state = "between"
        elif line == "DATA_START":
            if state != "between":
                raise fail(f"DATA_START out of place ({_expected(state)})")
            current = _Segment(meta, number)
            segments.append(current)
            state = "data"
        elif line == "DATA_STOP":
            if state != "data":
                raise fail(f"DATA_STOP out of place ({_expected(state)})")
            assert current is not None
            _close(current, epochs, p)
            state = "done"
        elif state in ("header", "meta"):
            key, eq, value = line.partition("=")
            key, value = key.strip(), value.strip()
            if not eq or not key or not value:
                raise fail(f"expected KEYWORD = value, got {line[:80]!r}")
            table = header if state == "header" else meta
            if key in table:
                raise fail(f"{key} given twice")
            table[key] = value
        else:
            raise fail(f"unexpected line {line[:80]!r} ({_expected(state)})")
    if state != "done":
        raise ReadError(f"{p} ends {_expected(state)}: the file is truncated or not a "
                        "whole AEM", path=str(p))
    return _ephemeris(header, segments)


def _expected(state: str) -> str:
    return {"header": "before the first META_START",
            "meta": "inside META_START … META_STOP, no META_STOP",
            "between": "after META_STOP, with no DATA_START",
            "data": "inside DATA_START … DATA_STOP, no DATA_STOP",
            "done": "after DATA_STOP"}[state]


def _check_header(header: dict[str, str], fail: Any) -> None:
    missing = [k for k in _HEADER_REQUIRED if k not in header]
    if missing:
        raise fail(f"the header lacks {', '.join(missing)}")
    if header["CCSDS_AEM_VERS"] not in AEM_VERSIONS:
        raise fail(f"CCSDS_AEM_VERS {header['CCSDS_AEM_VERS']!r} is not read; versions "
                   f"{' and '.join(AEM_VERSIONS)} are")


def _check_metadata(meta: dict[str, str], version: str, fail: Any) -> tuple[int, bool]:
    missing = [k for k in _META_REQUIRED if k not in meta]
    if version == "1.0":
        missing += [k for k in ("ATTITUDE_DIR",) if k not in meta]
    if missing:
        raise fail(f"the segment's metadata lacks {', '.join(missing)}")
    kind = meta["ATTITUDE_TYPE"].upper()
    rates = kind in _RATE_TYPES
    if kind != "QUATERNION" and not rates:
        raise fail(f"ATTITUDE_TYPE {kind!r} is not read; read_aem reads QUATERNION, "
                   "QUATERNION/ANGVEL and QUATERNION/RATE")
    if version == "1.0":
        if meta.get("QUATERNION_TYPE", "").upper() not in ("FIRST", "LAST"):
            raise fail("QUATERNION_TYPE must be FIRST or LAST in a version 1.0 AEM, got "
                       f"{meta.get('QUATERNION_TYPE')!r}")
        if meta["ATTITUDE_DIR"].upper() not in ("A2B", "B2A"):
            raise fail(f"ATTITUDE_DIR must be A2B or B2A, got {meta['ATTITUDE_DIR']!r}")
    for key in ("START_TIME", "STOP_TIME"):
        try:
            _Epochs().micros(meta[key])
        except ValueError as exc:
            raise fail(f"{key}: {exc}") from None
    return 4 + (3 if rates else 0), rates


_UNIX_DAY = _dt.date(1970, 1, 1).toordinal()
_LAYOUT = {4: "-", 7: "-", 10: "T", 13: ":", 16: ":", 19: "."}
"""The fixed characters of the common epoch form ``YYYY-MM-DDThh:mm:ss.ffffff``."""


def _epochs_micros(segment: _Segment, epochs: _Epochs, p: Path) -> np.ndarray:
    """The segment's epochs in microseconds since 0001-01-01 (as `_Epochs.micros`)."""
    texts = segment.epochs
    out = np.empty(len(texts), dtype=np.int64)
    for start in range(0, len(texts), _EPOCH_CHUNK):
        chunk = texts[start: start + _EPOCH_CHUNK]
        micros = _common_micros(chunk)
        if micros is None:  # one by one, naming the first epoch that is none
            micros = np.empty(len(chunk), dtype=np.int64)
            for k, text in enumerate(chunk):
                try:
                    micros[k] = epochs.micros(text)
                except ValueError as exc:
                    line = segment.lines[start + k]
                    raise ReadError(f"{p}:{line}: {exc}", path=str(p)) from None
        out[start: start + len(chunk)] = micros
    return out


_EPOCH_CHUNK = 1 << 13
"""Epochs parsed at once (the transient arrays stay a few MB whatever the file)."""


def _common_micros(texts: list[str]) -> np.ndarray | None:
    """`texts` parsed by NumPy when every one has the common form ``YYYY-MM-DDThh:mm:ss[.f]``
    of one length (NumPy's own date checks, plus the form's separators and years from 0001
    checked here); None otherwise (or for a date NumPy refuses: checked one by one)."""
    width = len(texts[0])
    if not (19 <= width <= 26 and width != 20 and all(len(x) == width for x in texts)):
        return None
    chars = np.array(texts, dtype=f"U{width}").view("U1").reshape(len(texts), width)
    digits = [k for k in range(width) if k not in _LAYOUT]
    if not all((chars[:, k] == c).all() for k, c in _LAYOUT.items() if k < width):
        return None
    if not np.char.isdigit(chars[:, digits]).all():
        return None
    if (chars[:, :4] == "0").all(axis=1).any():
        return None  # year 0000: refused one by one
    try:
        stamps = np.array(texts, dtype="datetime64[us]")
    except ValueError:  # a date or time that does not exist: say which, one by one
        return None
    micros: np.ndarray = stamps.astype(np.int64) + _UNIX_DAY * _US_PER_DAY
    return micros


def _close(segment: _Segment, epochs: _Epochs, p: Path) -> None:
    """Checks a segment's rows all at once: epochs that exist and increase, finite numbers,
    unit quaternions, epochs inside START_TIME … STOP_TIME; an error names the data line."""

    def fail(k: int, message: str) -> ReadError:
        return ReadError(f"{p}:{segment.lines[k]}: {message}", path=str(p))

    if not segment.epochs:
        raise ReadError(f"{p}:{segment.line}: a segment without data lines", path=str(p))
    micros = _epochs_micros(segment, epochs, p)
    segment.micros = array.array("q", micros.tobytes())
    values = np.frombuffer(segment.values, dtype=np.float64).reshape(len(micros), -1)
    finite = np.isfinite(values).all(axis=1)
    if not finite.all():
        k = int(np.argmin(finite))
        raise fail(k, f"{float(values[k][~np.isfinite(values[k])][0])!r} is not a finite number")
    later = np.diff(micros) > 0
    if not later.all():
        k = int(np.argmin(later)) + 1
        raise fail(k, f"epoch {segment.epochs[k]} is not after the line before's "
                      f"{segment.epochs[k - 1]}: a segment's epochs must increase")
    q = values[:, :4]
    norm = np.sqrt(np.einsum("ij,ij->i", q, q))
    unit = np.abs(norm - 1.0) <= AEM_UNIT_TOLERANCE
    if not unit.all():
        k = int(np.argmin(unit))
        raise fail(k, f"the quaternion of the data line at {segment.epochs[k]} has norm "
                      f"{norm[k]:.9g}, not 1 (to {AEM_UNIT_TOLERANCE:g}): no attitude")
    start = epochs.micros(segment.metadata["START_TIME"])
    stop = epochs.micros(segment.metadata["STOP_TIME"])
    if micros[0] < start or micros[-1] > stop:
        raise fail(len(micros) - 1 if micros[-1] > stop else 0,
                   f"the segment's epochs, {segment.epochs[0]} to {segment.epochs[-1]}, are "
                   f"not inside its START_TIME {segment.metadata['START_TIME']} to "
                   f"STOP_TIME {segment.metadata['STOP_TIME']}")


def _ephemeris(header: dict[str, str], segments: list[_Segment]) -> AttitudeEphemeris:
    version = header["CCSDS_AEM_VERS"]
    origin = segments[0].micros[0]
    out = []
    for s in segments:
        meta = s.metadata
        values = np.frombuffer(s.values, dtype=np.float64).reshape(len(s.micros), -1)
        first = version == "1.0" and meta.get("QUATERNION_TYPE", "").upper() == "FIRST"
        q = values[:, :4] if first else values[:, [3, 0, 1, 2]]
        if version == "1.0" and meta.get("ATTITUDE_DIR", "A2B").upper() == "B2A":
            q = q * np.array([1.0, -1.0, -1.0, -1.0])  # the inverse transformation
        omega = None
        if values.shape[1] == 7:
            omega = np.radians(values[:, 4:7])
            frame = meta.get("ANGVEL_FRAME", meta.get("RATE_FRAME", "REF_FRAME_B"))
            if frame in ("REF_FRAME_A", meta.get("REF_FRAME_A")):  # world axes: into body
                omega = np.einsum("nji,nj->ni", _matrices(q), omega)
        micros = np.frombuffer(s.micros, dtype=np.int64)
        t = (micros - origin) / 1e6
        out.append(AemSegment(meta, s.epochs, t, np.ascontiguousarray(q), omega))
    return AttitudeEphemeris(header, tuple(out))


def _matrices(q: np.ndarray) -> np.ndarray:
    """``M(q)`` for unit scalar-first quaternions, shape (N, 3, 3)."""
    w, x, y, z = (q / np.linalg.norm(q, axis=1, keepdims=True)).T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], axis=1)
