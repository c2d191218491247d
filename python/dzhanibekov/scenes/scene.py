"""Scenes: what to simulate and what to draw, as small TOML files.

A scene names the body, the initial state, the time span and frames, the method, and what
is drawn or asked. The paper's figures ship as scenes (``dzhanibekov/scenes/*.toml``); write
your own from one of them (``dzhanibekov scenes --show fig3a > my.toml``). A file::

    title = "Fig. 3a: u0 = v0 = 0.01, w0 = 1"

    [body]
    inertia = [52.0833, 27.0833, 41.6666]  # principal moments (Ix, Iy, Iz); or box = [a, b, c]
    box = [20.0, 10.0, 15.0]               # the box drawn, edges along x, y, z
    signal_point = [0.0, 0.0, 13.0]        # body frame

    [start]
    omega = [0.01, 0.01, 1.0]              # body angular velocity (u0, v0, w0)
    q = [1.0, 0.0, 0.0, 0.0]               # attitude, scalar first

    [run]
    t_end = 100.0
    frames = 201
    dt = 1e-3
    method = "rk4"                         # one of dzhanibekov.METHODS

    [ask]
    flips = true                           # flip times and the stability verdict

    [draw]
    path = true                            # the signal point's path
    figures = ["path", "omega", "invariants", "polhode"]

Loading checks every key: an unknown key, a value of the wrong type or out of range is a
:class:`SceneError` naming the file, the key and what is allowed.
"""

from __future__ import annotations

import dataclasses
import os
import re
import sys
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from .._args import as_array, as_float, as_int
from ..body import Body
from ..damper import Damper
from ..deployment import Deployment
from ..geometry import CONVENTIONS
from ..methods import DEFAULT_METHOD, METHODS
from ..simulate import simulate
from ..summary import Summary, summarize
from ..results import Trajectory

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = [
    "CONVENTIONS",
    "FIGURES",
    "PAPER_SCENES",
    "SCENES",
    "STORY_SCENES",
    "Draw",
    "EllipsoidStyle",
    "Scene",
    "SceneError",
    "load_scene",
]

FIGURES = ("phases", "path", "omega", "invariants", "polhode", "shares", "energy")
"""Figures a scene may ask for: the phases panel (Fig. 2), the signal point's path in 3-D
(Fig. 3), ω(t) with the flips marked, the invariants' drift, the polhode, the share of
``|L|`` on each body axis, and the total kinetic energy (with ``|L_world|``)."""

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
_MAX_CELLS = 256
"""Most cells of the ellipsoid mesh along either direction, for a drawing."""
_DEFAULT_PHASES = 6


class SceneError(ValueError):
    """A scene that cannot be loaded; the message names the file, the key and what is allowed.

    Attributes
    ----------
    source : str
        The file (or ``<scene NAME>`` for a scene built in Python).
    key : str or None
        The dotted key at fault, e.g. ``run.frames``; None for a file that is not TOML.
    """

    def __init__(self, source: str, key: str | None, message: str) -> None:
        where = f"{source}: " if key is None else f"{source}: `{key}` "
        super().__init__(where + message)
        self.source, self.key, self.detail = source, key, message

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (self.source, self.key, self.detail), self.__dict__)


@dataclass(frozen=True)
class EllipsoidStyle:
    """How the inertia ellipsoid is drawn.

    Attributes
    ----------
    convention : {"gyration", "poinsot"}
        ``gyration``: semi-axes ``√(I/m)``, radii of gyration (the paper's); ``poinsot``: the
        classical ellipsoid ``x · I x = const``, semi-axes ∝ ``1/√I`` (see
        :mod:`dzhanibekov.ellipsoid`).
    mesh : (int, int)
        ``(eN, eM)``: cells around the body z axis (a full turn) and from pole to pole (a
        half turn).
    """

    convention: str = "gyration"
    mesh: tuple[int, int] = (24, 12)


@dataclass(frozen=True)
class Draw:
    """What a scene draws. The 3-D objects (box … momentum) appear in the phases panel and the
    animation; `figures` lists the figures made (see :data:`FIGURES`)."""

    box: bool = False
    ellipsoid: bool = False
    signal_point: bool = False
    path: bool = False
    body_axes: bool = False
    momentum: bool = False
    figures: tuple[str, ...] = ()
    animation: bool = False
    phases: tuple[float, ...] = ()
    """Instants of the phases panel; empty: evenly spread over the run."""

    @property
    def objects(self) -> tuple[str, ...]:
        """The 3-D objects drawn, by name."""
        names = ("box", "ellipsoid", "signal_point", "path", "body_axes", "momentum")
        return tuple(n for n in names if getattr(self, n))


@dataclass(frozen=True)
class Scene:
    """A run and what to draw or ask of it. Construct it directly or load a TOML file with
    :func:`load_scene`; both are checked the same way (:class:`SceneError`).

    """

    name: str
    title: str
    inertia: tuple[float, float, float]
    omega0: tuple[float, float, float]
    t_end: float
    frames: int
    q0: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    dt: float = 1e-3
    method: str = DEFAULT_METHOD
    box: tuple[float, float, float] | None = None
    """Edges of the box drawn (along x, y, z); None: the uniform box with these moments."""
    signal_point: tuple[float, float, float] = (0.0, 0.0, 13.0)
    flips: bool = True
    """Ask for the flip times (and the stability verdict)."""
    draw: Draw = Draw()
    ellipsoid: EllipsoidStyle = EllipsoidStyle()
    about: str = ""
    deployment: Deployment | None = None
    """A prescribed change of inertia (``[deployment]`` with ``times`` and ``inertia``, a
    list of principal moments or 3 × 3 tensors); `inertia` is then the body at ``t = 0``
    (the drawn box keeps its size)."""
    damper: Damper | None = None
    """A spherical viscous damper (``[damper]`` with ``inertia`` and ``damping``)."""
    sigma0: tuple[float, float, float] | None = None
    """The damper's initial rate (``damper.sigma``); None: co-rotating."""
    source: str = field(default="", compare=False, repr=False)
    """Where the scene came from, for messages."""

    def __post_init__(self) -> None:
        _validate(self)

    # -- running ------------------------------------------------------------------------

    @property
    def body(self) -> Body:
        """The body whose moments the scene names."""
        return Body(self.inertia)

    def run(self, **overrides: Any) -> Trajectory:
        """Simulates the scene, keeping every frame; keywords override :func:`simulate`'s."""
        kwargs: dict[str, Any] = dict(
            q0=self.q0, t_end=self.t_end, frames=self.frames, dt=self.dt, method=self.method
        )
        if self.damper is not None:
            kwargs.update(damper=self.damper, sigma0=self.sigma0)
        kwargs.update(overrides)
        if self.deployment is not None or self.damper is not None:
            kwargs.pop("flips", None)  # flips are located for the constant body only
        body = self.deployment if self.deployment is not None else self.body
        traj = simulate(body, self.omega0, **kwargs)
        assert isinstance(traj, Trajectory), "a scene is one run"
        return traj

    def summarize(self, **overrides: Any) -> Summary:
        """Simulates the scene keeping no frames (:func:`summarize`): flip times only."""
        kwargs: dict[str, Any] = dict(
            q0=self.q0, t_end=self.t_end, frames=self.frames, dt=self.dt, method=self.method
        )
        kwargs.update(overrides)
        return summarize(self.body, self.omega0, **kwargs)

    def replace(self, **changes: Any) -> Scene:
        """A copy with some fields changed (checked again)."""
        return dataclasses.replace(self, **changes)

    # -- drawing helpers ----------------------------------------------------------------

    @property
    def drawn_box(self) -> tuple[float, float, float]:
        """The edges of the box drawn: `box`, or the uniform box with the scene's moments
        (``a² = 6 (Iy + Iz − Ix) / m`` with ``m = 1``, etc.)."""
        if self.box is not None:
            return self.box
        derived = _uniform_box(self.inertia)
        if derived is None:
            raise SceneError(self.source or f"<scene {self.name}>", "body.box",
                             "is needed: no uniform box has these moments")
        return derived

    @property
    def phase_times(self) -> tuple[float, ...]:
        """The instants of the phases panel."""
        if self.draw.phases:
            return self.draw.phases
        return tuple(float(t) for t in np.linspace(0.0, self.t_end, _DEFAULT_PHASES))

    # -- TOML ---------------------------------------------------------------------------

    def to_dict(self) -> dict[str, Any]:
        """The scene as the nested tables of its TOML file (defaults included)."""
        body: dict[str, Any] = {"inertia": list(self.inertia)}
        if self.box is not None:
            body["box"] = list(self.box)
        body["signal_point"] = list(self.signal_point)
        out: dict[str, Any] = {"title": self.title}
        if self.about:
            out["about"] = self.about
        d = self.draw
        out |= {
            "body": body,
            "start": {"omega": list(self.omega0), "q": list(self.q0)},
            "run": {"t_end": self.t_end, "frames": self.frames, "dt": self.dt,
                    "method": self.method},
            "ask": {"flips": self.flips},
            "draw": {n: getattr(d, n) for n in
                     ("box", "ellipsoid", "signal_point", "path", "body_axes", "momentum",
                      "animation")}
            | {"figures": list(d.figures), "phases": list(d.phases)},
            "ellipsoid": {"convention": self.ellipsoid.convention,
                          "mesh": list(self.ellipsoid.mesh)},
        }
        if self.deployment is not None:
            out["deployment"] = {"times": self.deployment.times.tolist(),
                                 "inertia": self.deployment.tensors.tolist()}
        if self.damper is not None:
            out["damper"] = {"inertia": self.damper.inertia, "damping": self.damper.damping}
            if self.sigma0 is not None:
                out["damper"]["sigma"] = list(self.sigma0)
        return out

    def to_toml(self) -> str:
        """The scene as TOML text that :meth:`from_toml` reads back to an equal scene."""
        return tomli_w.dumps(self.to_dict())

    def save(self, path: str | Path) -> Path:
        """Writes the scene to `path` (its stem should be the scene's name)."""
        path = Path(path)
        path.write_text(self.to_toml(), encoding="utf-8")
        return path

    @classmethod
    def from_toml(cls, text: str, name: str, source: str = "") -> Scene:
        """Reads a scene from TOML text; `name` is the scene's name (a file's stem)."""
        source = source or f"<scene {name}>"
        if not isinstance(text, str):
            raise TypeError(f"`text` must be a str of TOML, got {type(text).__name__}")
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise SceneError(source, None, f"is not valid TOML: {exc}") from None
        return cls.from_dict(data, name, source)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], name: str, source: str = "") -> Scene:
        """Builds a scene from the nested tables of a TOML file (see the module's docs)."""
        source = source or f"<scene {name}>"
        if not isinstance(data, Mapping):
            raise TypeError(f"`data` must be a mapping of a scene file's tables, got "
                            f"{type(data).__name__}")
        return _from_tables(cls, data, name, source)


# -- reading the tables -----------------------------------------------------------------

_TABLES: dict[str, tuple[str, ...]] = {
    "body": ("inertia", "box", "mass", "signal_point"),
    "start": ("omega", "q"),
    "run": ("t_end", "frames", "dt", "method"),
    "ask": ("flips",),
    "draw": ("box", "ellipsoid", "signal_point", "path", "body_axes", "momentum", "figures",
             "animation", "phases"),
    "ellipsoid": ("convention", "mesh"),
    "deployment": ("times", "inertia"),
    "damper": ("inertia", "damping", "sigma"),
}
_TOP = ("title", "about")


def _from_tables(cls: type[Scene], data: Mapping[str, Any], name: str, source: str) -> Scene:
    def fail(key: str, message: str) -> SceneError:
        return SceneError(source, key, message)

    allowed_top = _TOP + tuple(f"[{t}]" for t in _TABLES)
    for key, value in data.items():
        if key in _TABLES:
            if not isinstance(value, dict):
                raise fail(key, f"must be a table [{key}], got {type(value).__name__}")
            for sub in value:
                if sub not in _TABLES[key]:
                    raise fail(f"{key}.{sub}", "is not a known key; allowed in "
                               f"[{key}]: {', '.join(_TABLES[key])}")
        elif key not in _TOP:
            raise fail(key, f"is not a known key; allowed: {', '.join(allowed_top)}")
    tables = {t: data.get(t, {}) for t in _TABLES}

    def need(table: str, key: str) -> Any:
        if key not in tables[table]:
            raise fail(f"{table}.{key}", "is missing")
        return tables[table][key]

    body = tables["body"]
    if "inertia" in body:
        if "mass" in body:
            raise fail("body.mass", "is only used with `body.box` to compute the moments; "
                       "remove it or `body.inertia`")
        inertia = body["inertia"]
    elif "box" in body:
        edges = _triple(source, "body.box", body["box"], positive=True)
        mass = _number(source, "body.mass", body.get("mass", 1.0), positive=True)
        inertia = Body.box(edges[0], edges[1], edges[2], mass=mass).inertia
    else:
        raise fail("body.inertia", "is missing; give the principal moments (Ix, Iy, Iz) "
                   "or `body.box` (edges along x, y, z)")
    draw, style = tables["draw"], tables["ellipsoid"]
    kwargs: dict[str, Any] = {
        "name": name,
        "title": data.get("title", _Missing("title")),
        "inertia": inertia,
        "omega0": need("start", "omega"),
        "t_end": need("run", "t_end"),
        "frames": need("run", "frames"),
        "source": source,
        "about": data.get("about", ""),
    }
    optional = {
        ("start", "q"): "q0",
        ("run", "dt"): "dt",
        ("run", "method"): "method",
        ("body", "box"): "box",
        ("body", "signal_point"): "signal_point",
        ("ask", "flips"): "flips",
    }
    for (table, key), attr in optional.items():
        if key in tables[table]:
            kwargs[attr] = tables[table][key]
    kwargs["draw"] = _Raw(draw)
    kwargs["ellipsoid"] = _Raw(style)
    if "deployment" in data:
        kwargs["deployment"] = _Raw(tables["deployment"])
    if "damper" in data:
        kwargs["damper"] = _Raw(tables["damper"])
        if "sigma" in tables["damper"]:
            kwargs["sigma0"] = tables["damper"]["sigma"]
    return cls(**kwargs)


class _Missing:
    """A required key that the file lacks (reported by the validator, with its name)."""

    def __init__(self, key: str) -> None:
        self.key = key


class _Raw:
    """An unchecked sub-table, turned into its dataclass by the validator."""

    def __init__(self, table: Mapping[str, Any]) -> None:
        self.table = table


# -- checking -----------------------------------------------------------------------------


def _number(source: str, key: str, value: Any, *, positive: bool = False) -> float:
    try:
        return as_float(key, value, positive=positive)
    except (TypeError, ValueError) as exc:
        raise SceneError(source, key, str(exc).removeprefix(f"`{key}` ")) from None


def _integer(source: str, key: str, value: Any, minimum: int, maximum: int | None = None) -> int:
    try:
        n = as_int(key, value, minimum=minimum)
    except (TypeError, ValueError) as exc:
        raise SceneError(source, key, str(exc).removeprefix(f"`{key}` ")) from None
    if maximum is not None and n > maximum:
        raise SceneError(source, key, f"must be at most {maximum}, got {n}")
    return n


def _flag(source: str, key: str, value: Any) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise SceneError(source, key, f"must be true or false, got {value!r}")
    return bool(value)


def _vector(source: str, key: str, value: Any, n: int) -> tuple[float, ...]:
    try:
        sized = not isinstance(value, (str, bytes)) and len(value) == n
    except TypeError:  # no length, or a 0-d array's
        sized = False
    if not sized:
        raise SceneError(source, key, f"must be a list of {n} numbers, got {value!r}")
    if any(isinstance(x, (bool, np.bool_)) for x in value):
        raise SceneError(source, key, f"must be a list of {n} numbers, got {value!r}")
    try:
        arr = as_array(key, value, f"({n},)", last=n, ndim=(1,))
    except (TypeError, ValueError):
        raise SceneError(source, key, f"must be a list of {n} finite numbers, got {value!r}") \
            from None
    return tuple(float(x) for x in arr)


def _triple(source: str, key: str, value: Any, *, positive: bool = False) -> tuple[float, ...]:
    v = _vector(source, key, value, 3)
    if positive and not all(x > 0 for x in v):
        raise SceneError(source, key, f"must hold three positive numbers, got {list(v)}")
    return v


def _text(source: str, key: str, value: Any, *, required: bool) -> str:
    if isinstance(value, _Missing):
        raise SceneError(source, key, "is missing; give the scene a title")
    if not isinstance(value, str) or (required and not value.strip()):
        raise SceneError(source, key, f"must be a{' non-empty' if required else ''} string, "
                         f"got {value!r}")
    return value


def _strings(source: str, key: str, value: Any, allowed: tuple[str, ...]) -> tuple[str, ...]:
    if isinstance(value, str) or not isinstance(value, (list, tuple)):
        raise SceneError(source, key, f"must be a list of names from {list(allowed)}, "
                         f"got {value!r}")
    for v in value:
        if v not in allowed:
            raise SceneError(source, key, f"must name only {list(allowed)}, got {v!r}")
    if len(set(value)) != len(value):
        raise SceneError(source, key, f"names a figure twice: {list(value)}")
    return tuple(value)


def _set(scene: Scene, attr: str, value: Any) -> None:
    object.__setattr__(scene, attr, value)


def _validate(s: Scene) -> None:
    """Checks and normalises every field of `s` in place (it is frozen: via object)."""
    src = s.source or f"<scene {s.name}>"
    if not isinstance(s.name, str) or not _NAME.match(s.name):
        raise SceneError(src, "name", "must be letters, digits, '_', '-' or '.' (it names the "
                         f"output files), got {s.name!r}")
    _set(s, "title", _text(src, "title", s.title, required=True))
    _set(s, "about", _text(src, "about", s.about, required=False))
    inertia = _triple(src, "body.inertia", s.inertia, positive=True)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            Body(inertia)
    except (TypeError, ValueError) as exc:
        raise SceneError(src, "body.inertia", str(exc).replace("`inertia` ", "")) from None
    _set(s, "inertia", inertia)
    _set(s, "omega0", _vector(src, "start.omega", s.omega0, 3))
    q0 = _vector(src, "start.q", s.q0, 4)
    if not any(q0):
        raise SceneError(src, "start.q", "must be a non-zero quaternion (Q, U, V, W)")
    _set(s, "q0", q0)
    _set(s, "t_end", _number(src, "run.t_end", s.t_end, positive=True))
    _set(s, "frames", _integer(src, "run.frames", s.frames, 2))
    _set(s, "dt", _number(src, "run.dt", s.dt, positive=True))
    if s.method not in METHODS:
        raise SceneError(src, "run.method", f"must be one of {list(METHODS)}, got {s.method!r}")
    if s.box is not None:
        _set(s, "box", _triple(src, "body.box", s.box, positive=True))
    _set(s, "signal_point", _triple(src, "body.signal_point", s.signal_point))
    _set(s, "flips", _flag(src, "ask.flips", s.flips))

    draw = s.draw.table if isinstance(s.draw, _Raw) else dataclasses.asdict(s.draw)
    if not isinstance(draw, Mapping):
        raise SceneError(src, "draw", f"must be a table, got {draw!r}")
    flags = {n: _flag(src, f"draw.{n}", draw.get(n, False))
             for n in ("box", "ellipsoid", "signal_point", "path", "body_axes", "momentum",
                       "animation")}
    figures = _strings(src, "draw.figures", draw.get("figures", ()), FIGURES)
    phases = draw.get("phases", ())
    if isinstance(phases, str) or not isinstance(phases, (list, tuple)):
        raise SceneError(src, "draw.phases", f"must be a list of times, got {phases!r}")
    times = tuple(_number(src, "draw.phases", t) for t in phases)
    if any(not 0.0 <= t <= s.t_end for t in times):
        raise SceneError(src, "draw.phases", f"must be times in [0, run.t_end = {s.t_end:g}], "
                         f"got {list(times)}")
    _set(s, "draw", Draw(**flags, figures=figures, phases=times))

    style = s.ellipsoid.table if isinstance(s.ellipsoid, _Raw) else \
        dataclasses.asdict(s.ellipsoid)
    if not isinstance(style, Mapping):
        raise SceneError(src, "ellipsoid", f"must be a table, got {style!r}")
    convention = style.get("convention", "gyration")
    if convention not in CONVENTIONS:
        raise SceneError(src, "ellipsoid.convention",
                         f"must be one of {list(CONVENTIONS)}, got {convention!r}")
    mesh = style.get("mesh", (24, 12))
    if isinstance(mesh, str) or not isinstance(mesh, (list, tuple)) or len(mesh) != 2:
        raise SceneError(src, "ellipsoid.mesh", f"must be [eN, eM], two integers, got {mesh!r}")
    e_n = _integer(src, "ellipsoid.mesh[0]", mesh[0], 3, _MAX_CELLS)  # eN, around
    e_m = _integer(src, "ellipsoid.mesh[1]", mesh[1], 2, _MAX_CELLS)  # eM, pole to pole
    _set(s, "ellipsoid", EllipsoidStyle(convention, (e_n, e_m)))

    _validate_models(s, src)

    if flags["box"] and s.box is None and _uniform_box(inertia) is None:
        raise SceneError(src, "body.box", "is needed to draw the box: no uniform box has the "
                         "moments of `body.inertia`")


def _validate_models(s: Scene, src: str) -> None:
    """Checks and builds a scene's deployment and damper."""
    if isinstance(s.deployment, _Raw):
        table = s.deployment.table
        for key in ("times", "inertia"):
            if key not in table:
                raise SceneError(src, f"deployment.{key}", "is missing")
        try:
            _set(s, "deployment", Deployment(table["times"], table["inertia"]))
        except (TypeError, ValueError) as exc:
            raise SceneError(src, "deployment", str(exc)) from None
    elif s.deployment is not None and not isinstance(s.deployment, Deployment):
        raise SceneError(src, "deployment", f"must be a Deployment, got {s.deployment!r}")
    if isinstance(s.damper, _Raw):
        table = s.damper.table
        for key in ("inertia", "damping"):
            if key not in table:
                raise SceneError(src, f"damper.{key}", "is missing")
        try:
            _set(s, "damper", Damper(table["inertia"], table["damping"]))
        except (TypeError, ValueError) as exc:
            raise SceneError(src, "damper", str(exc)) from None
    elif s.damper is not None and not isinstance(s.damper, Damper):
        raise SceneError(src, "damper", f"must be a Damper, got {s.damper!r}")
    if s.sigma0 is not None:
        if s.damper is None:
            raise SceneError(src, "damper.sigma", "needs a [damper]")
        _set(s, "sigma0", _vector(src, "damper.sigma", s.sigma0, 3))
    if s.deployment is not None and s.damper is not None:
        raise SceneError(src, "damper", "cannot be combined with a [deployment]")
    if (s.deployment is not None or s.damper is not None) and s.flips:
        raise SceneError(src, "ask.flips", "must be false with a deployment or a damper "
                         "(flips are located for the constant body only)")


def _uniform_box(inertia: tuple[float, ...]) -> tuple[float, float, float] | None:
    """Edges of the uniform unit-mass box with these principal moments, if there is one."""
    ix, iy, iz = inertia
    squares = (6 * (iy + iz - ix), 6 * (ix + iz - iy), 6 * (ix + iy - iz))
    if min(squares) <= 0:
        return None
    a, b, c = (float(np.sqrt(x)) for x in squares)
    return a, b, c


# -- files --------------------------------------------------------------------------------


def load_scene(path: str | Path) -> Scene:
    """Loads a scene from a TOML file, or a shipped scene by name (see :data:`SCENES`).

    Parameters
    ----------
    path : str or Path
        A ``.toml`` file (the scene is named after its stem), or the name of a shipped scene.

    Returns
    -------
    Scene

    Raises
    ------
    SceneError
        The file is missing, not UTF-8 TOML, or has a key that is unknown, missing, of the
        wrong type or out of range; the message names the file, the key and what is allowed.
    TypeError
        `path` is neither a str nor a path.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"`path` must be a scene file (str or Path) or the name of a shipped "
                        f"scene, got {type(path).__name__}")
    shipped = ", ".join(SCENES)
    if isinstance(path, str) and not path.strip():
        raise SceneError(repr(path), None, f"is not a scene: `path` is empty; give a scene file "
                         f"or one of the shipped scenes: {shipped}")
    p = Path(path)
    try:
        if not p.exists() and isinstance(path, str) and path in SCENES:
            return SCENES[path]
        text = p.read_text(encoding="utf-8")
    except (OSError, ValueError) as exc:  # ValueError: a NUL in the path, or not UTF-8
        why = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        if isinstance(exc, UnicodeDecodeError):
            why = f"not UTF-8 text: {exc.reason} at byte {exc.start}"
        raise SceneError(str(p), None, f"cannot be read ({why}); give a scene file or one of "
                         f"the shipped scenes: {shipped}") from None
    return Scene.from_toml(text, p.stem, str(p))


def _shipped() -> dict[str, Scene]:
    folder = resources.files("dzhanibekov") / "scenes"
    scenes = {}
    for item in sorted(folder.iterdir(), key=lambda f: f.name):
        if item.name.endswith(".toml"):
            name = item.name[: -len(".toml")]
            scenes[name] = Scene.from_toml(item.read_text(encoding="utf-8"), name,
                                           f"dzhanibekov/scenes/{item.name}")
    return scenes


SCENES: Mapping[str, Scene] = _shipped()
"""The shipped scenes by name: the paper's (see :data:`PAPER_SCENES`) and two stable
counter-examples, ``stable-largest`` and ``stable-smallest``."""

PAPER_SCENES = ("example", "fig3a", "fig3b", "fig3c")
"""The scenes of the paper's figures: ``example`` (Fig. 2) and ``fig3a``–``fig3c``."""

STORY_SCENES = ("deployment", "explorer-1")
"""Bodies that change: a stowed major-axis spin deployed to an intermediate one, which
tumbles; and Explorer 1's minor-axis spin going flat through a damper."""
