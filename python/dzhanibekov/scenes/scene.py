"""Scenes: what to simulate and what to draw, as small TOML files.

A scene names the body, the initial state, the time span and frames, the method, and what
is drawn or asked. The paper's figures ship as scenes (``dzhanibekov/scenes/*.toml``); write
your own from one of them (``dzhanibekov scenes --show fig3a > my.toml``). A file::

    title = "Fig. 3a: u0 = v0 = 0.01, w0 = 1"

    [body]
    inertia = [52.0833, 27.0833, 41.6666]  # principal moments (Ix, Iy, Iz); or box = [a, b, c]
    box = [20.0, 10.0, 15.0]               # the box drawn, edges along x, y, z
    signal_point = [0.0, 0.0, 13.0]        # body frame; left out: scaled to the body

    [start]
    omega = [0.01, 0.01, 1.0]              # body angular velocity (u0, v0, w0)
    q = [1.0, 0.0, 0.0, 0.0]               # attitude, scalar first

    [run]
    t_end = 100.0
    frames = 201
    dt = 1e-3                              # or "none" (the default): the step for `rtol`
    method = "rk4"                         # one of dzhanibekov.METHODS
    # rtol = 1e-9                          # accuracy of dt = "none", or an adaptive method's
    # atol = 1e-12                         # adaptive methods only

    [ask]
    flips = true                           # flip times and the stability verdict

    [draw]
    path = true                            # the signal point's path
    figures = ["path", "omega", "invariants", "polhode"]

Instead of `inertia`, the body may be any of (with ``mass`` or, for meshes, ``density``)::

    tensor = [[2.0, -0.1, 0.0], [-0.1, 3.0, 0.0], [0.0, 0.0, 4.0]]  # Body.from_tensor
    cylinder = [radius, height]        sphere = radius        ellipsoid = [a, b, c]
    mesh = "part.stl"                  # a mesh file, relative to the scene file (trimesh)
    preset = "wing-nut"                # Body.wing_nut()
    parts = [{ box = [1, 1, 1], mass = 2.0, position = [0, 0, 0], q = [1, 0, 0, 0] }, …]

Loading checks every key: an unknown key, a value of the wrong type or out of range is a
:class:`SceneError` naming the file, the key and what is allowed.
"""

from __future__ import annotations

import dataclasses
import os
import re
import stat
import sys
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from .._args import as_array, as_float, as_int, run_options
from .._files import ReadError, open_regular, write_text
from ..body import Body
from .bodies import BODY_KEYS, build_body, default_signal_point
from ..damper import Damper
from ..deployment import Deployment
from ..shapes import Shape, box_shape
from ..geometry import CONVENTIONS, ellipsoid_semi_axes
from ..methods import DEFAULT_METHOD, METHODS
from ..simulate import simulate
from ..summary import Summary, summarize
from ..results import Trajectory
from ..system import System

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = [
    "CONVENTIONS",
    "FIGURES",
    "MAX_ANIMATION_FRAMES",
    "MAX_DRAWN_SIZE",
    "MAX_PHASES",
    "MAX_SCENE_BYTES",
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

MAX_SCENE_BYTES = 1 << 20
"""The largest scene file :func:`load_scene` reads (1 MiB); scenes are a few hundred bytes."""
MAX_ANIMATION_FRAMES = 2000
"""Most frames (`run.frames`) of a scene that draws an animation: each frame is drawn and
kept (about 0.3 MB) until the GIF is written. For longer runs, store fewer frames."""
MAX_PHASES = 24
"""Most instants (`draw.phases`) of the phases panel: each is one 3-D panel of the figure."""
MAX_DRAWN_SIZE = 1e100
"""The largest size a scene draws (|`body.signal_point`|, `body.box` edges, the inertia
ellipsoid's semi-axes): drawing squares lengths and view limits, which must stay finite."""


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
    fps: int | None = None
    """The animation's frames per second; None: the default (20)."""
    animation_size: int | None = None
    """The animation's width and height in pixels; None: the default (560)."""

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
    dt: float | None = None
    """The step; None (``dt = "none"`` in a file, or no `dt`): picked for `rtol`."""
    method: str = DEFAULT_METHOD
    box: tuple[float, float, float] | None = None
    """Edges of the box drawn (along x, y, z); None: the uniform box with these moments."""
    signal_point: tuple[float, float, float] = None  # type: ignore[assignment]
    """Body frame; None: on the intermediate axis, a quarter beyond the body's outline (the
    paper's scenes give theirs, (0, 0, 13))."""
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
    rtol: float | None = None
    """The accuracy `dt` = None is picked for, or an adaptive method's relative tolerance
    (default `dzhanibekov.accuracy.DEFAULT_RTOL`)."""
    atol: float | None = None
    """An adaptive method's absolute tolerance (default
    `dzhanibekov.accuracy.DEFAULT_ATOL`)."""
    body_spec: Mapping[str, Any] | None = None
    """The body, when it is more than principal moments: the `[body]` table's keys that
    name it (``tensor``, ``cylinder``, ``sphere``, ``ellipsoid``, ``mesh``, ``parts`` or
    ``preset``, with ``mass``/``density``); `inertia` then holds its principal moments.
    A mesh path is kept absolute."""

    given: System | None = field(default=None, compare=False, repr=False)
    """The system itself, when the scene stages one given as a value (a trajectory drawn as a
    scene, `dzhanibekov.scenes.staging`): its body is drawn as it is, its parts kept."""

    def __post_init__(self) -> None:
        _validate(self)

    # -- running ------------------------------------------------------------------------

    @cached_property
    def body(self) -> Body:
        """The body the scene names (built once): a deployment's at its first knot."""
        if self.given is not None:
            body = self.given.body
            if isinstance(body, Body):
                return body
            return Body._restored(self.given.tensor_at(0.0), None, np.zeros(3))
        if self.body_spec is None:
            return Body(self.inertia)
        return build_body(self.body_spec)

    @cached_property
    def system(self) -> System:
        """What the scene runs: its body (or deployment) with its damper, if any."""
        if self.given is not None:
            return self.given
        body = self.deployment if self.deployment is not None else self.body
        parts = [] if self.damper is None else [
            Damper(self.damper.inertia, self.damper.damping, self.sigma0)]
        return System(body, parts=parts)

    def run(self, **overrides: Any) -> Trajectory:
        """Simulates the scene, keeping every frame; keywords override :func:`simulate`'s."""
        kwargs = self._run_arguments() | overrides
        traj = simulate(self.system, self.omega0, **kwargs)
        assert isinstance(traj, Trajectory), "a scene is one run"
        return traj

    def summarize(self, **overrides: Any) -> Summary:
        """Simulates the scene keeping no frames (:func:`summarize`): flip times only."""
        kwargs = self._run_arguments() | overrides
        kwargs.pop("flips", None)
        summary = summarize(self.system, self.omega0, **kwargs)
        assert isinstance(summary, Summary), "a scene is one run"
        return summary

    def _run_arguments(self) -> dict[str, Any]:
        return dict(q0=self.q0, t_end=self.t_end, frames=self.frames, dt=self.dt,
                    method=self.method, rtol=self.rtol, atol=self.atol, flips=self.flips)

    def replace(self, **changes: Any) -> Scene:
        """A copy with some fields changed (checked again).

        The copy no longer comes from the original's file: its messages name it as
        ``<scene NAME, modified>``, not the file (unless `source` is among the changes).
        A shorter `t_end` drops the phases drawn after it.

        Examples
        --------
        >>> SCENES["fig3a"].replace(t_end=50.0).t_end
        50.0
        """
        changes.setdefault("source", f"<scene {changes.get('name', self.name)}, modified>")
        if "t_end" in changes and "draw" not in changes and self.draw.phases:
            # the phases drawn beyond a shortened run are dropped, not an error
            t_end = changes["t_end"]
            if isinstance(t_end, (int, float)) and not isinstance(t_end, bool):
                kept = tuple(t for t in self.draw.phases if t <= t_end)
                changes["draw"] = dataclasses.replace(self.draw, phases=kept)
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
    def drawn_shape(self) -> Shape | None:
        """What is drawn for the body: its own shape, else the box (`box`, or the uniform
        box of its moments, in its principal axes); None if there is none."""
        if self.body.shape is not None:
            return self.body.shape
        if self.box is None and _uniform_box(self.inertia) is None:
            return None
        return box_shape(*self.drawn_box).placed(self.body.principal_axes, np.zeros(3))

    @property
    def phase_times(self) -> tuple[float, ...]:
        """The instants of the phases panel."""
        if self.draw.phases:
            return self.draw.phases
        return tuple(float(t) for t in np.linspace(0.0, self.t_end, _DEFAULT_PHASES))

    # -- TOML ---------------------------------------------------------------------------

    def to_dict(self) -> dict[str, Any]:
        """The scene as the nested tables of its TOML file (defaults included)."""
        body: dict[str, Any] = (dict(self.body_spec) if self.body_spec is not None
                                else {"inertia": list(self.inertia)})
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
            "run": {"t_end": self.t_end, "frames": self.frames,
                    "dt": "none" if self.dt is None else self.dt, "method": self.method}
            | {k: v for k, v in (("rtol", self.rtol), ("atol", self.atol)) if v is not None},
            "ask": {"flips": self.flips},
            "draw": {n: getattr(d, n) for n in
                     ("box", "ellipsoid", "signal_point", "path", "body_axes", "momentum",
                      "animation")}
            | {"figures": list(d.figures), "phases": list(d.phases)}
            | {n: getattr(d, n) for n in ("fps", "animation_size") if getattr(d, n)},
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
        """Writes the scene to `path` (its stem should be the scene's name), all or nothing:
        the previous file is replaced only once the new one is complete."""
        return write_text(path, self.to_toml(), encoding="utf-8")

    @classmethod
    def from_toml(cls, text: str, name: str, source: str = "",
                  base: str | Path | None = None) -> Scene:
        """Reads a scene from TOML text; `name` is the scene's name (a file's stem), a mesh
        path is relative to `base`."""
        source = source or f"<scene {name}>"
        if not isinstance(text, str):
            raise TypeError(f"`text` must be a str of TOML, got {type(text).__name__}")
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise SceneError(source, None, f"is not valid TOML: {exc}") from None
        except RecursionError:
            raise SceneError(source, None, "is not a scene: its arrays or tables nest too "
                             "deeply to read (a scene nests at most two levels)") from None
        return cls.from_dict(data, name, source, base)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], name: str, source: str = "",
                  base: str | Path | None = None) -> Scene:
        """Builds a scene from the nested tables of a TOML file (see the module's docs);
        a mesh path is relative to `base` (default: the current folder)."""
        source = source or f"<scene {name}>"
        if not isinstance(data, Mapping):
            raise TypeError(f"`data` must be a mapping of a scene file's tables, got "
                            f"{type(data).__name__}")
        return _from_tables(cls, data, name, source, Path(base) if base is not None else None)


# -- reading the tables -----------------------------------------------------------------

_TABLES: dict[str, tuple[str, ...]] = {
    "body": ("inertia", "box", "mass", "signal_point") + ("tensor", "cylinder", "sphere",
             "ellipsoid", "mesh", "density", "parts", "preset"),
    "start": ("omega", "q"),
    "run": ("t_end", "frames", "dt", "method", "rtol", "atol"),
    "ask": ("flips",),
    "draw": ("box", "ellipsoid", "signal_point", "path", "body_axes", "momentum", "figures",
             "animation", "phases", "fps", "animation_size"),
    "ellipsoid": ("convention", "mesh"),
    "deployment": ("times", "inertia"),
    "damper": ("inertia", "damping", "sigma"),
}
_TOP = ("title", "about")


def _from_tables(cls: type[Scene], data: Mapping[str, Any], name: str, source: str,
                 base: Path | None = None) -> Scene:
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
    spec = {k: v for k, v in body.items() if k in BODY_KEYS or k == "density"
            or (k == "mass" and any(n in body for n in BODY_KEYS))}
    inertia: Any = (1.0, 1.0, 1.0)  # replaced by the body's principal moments
    if any(n in body for n in BODY_KEYS):
        named = [n for n in BODY_KEYS + ("inertia",) if n in body]
        if len(named) > 1:
            raise fail(f"body.{named[1]}", f"names a second body beside `body.{named[0]}`; "
                       "give one of " + ", ".join(BODY_KEYS + ("inertia", "box")))
        if "box" in body:
            raise fail("body.box", f"draws a box, but `body.{named[0]}` has its own shape")
        if "mesh" in spec and isinstance(spec["mesh"], str):
            mesh = Path(spec["mesh"])
            spec["mesh"] = str(mesh if mesh.is_absolute() else (base or Path.cwd()) / mesh)
    elif "density" in body:
        raise fail("body.density", "is only used with `body.mesh` or `body.parts`")
    elif "inertia" in body:
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
        "body_spec": spec or None,
    }
    optional = {
        ("start", "q"): "q0",
        ("run", "dt"): "dt",
        ("run", "method"): "method",
        ("run", "rtol"): "rtol",
        ("run", "atol"): "atol",
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
    if isinstance(value, (str, bytes)) or _ndim(value) != 1 or len(value) != n:
        raise SceneError(source, key, f"must be a list of {n} numbers, got {value!r}")
    if any(isinstance(x, (bool, np.bool_)) for x in value):
        raise SceneError(source, key, f"must be a list of {n} numbers, got {value!r}")
    try:
        arr = as_array(key, value, f"({n},)", last=n, ndim=(1,))
    except (TypeError, ValueError):
        raise SceneError(source, key, f"must be a list of {n} finite numbers, got {value!r}") \
            from None
    return tuple(float(x) for x in arr)


def _ndim(value: Any) -> int:
    """The number of axes of `value` as an array; -1 for what is none (ragged lists)."""
    try:
        return int(np.ndim(value))
    except Exception:
        return -1


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
    _drawable_text(src, "title", s.title)
    _set(s, "about", _text(src, "about", s.about, required=False))
    if s.body_spec is not None:
        if not isinstance(s.body_spec, Mapping):
            raise SceneError(src, "body", f"must be a table, got {s.body_spec!r}")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                built = build_body(s.body_spec)
        except (TypeError, ValueError, ImportError) as exc:
            key = next((k for k in BODY_KEYS if k in s.body_spec), "body")
            raise SceneError(src, f"body.{key}", f"does not give a body: {exc}") from None
        s.__dict__["body"] = built  # the cached property, filled: built once
        _set(s, "body_spec", dict(s.body_spec))
        _set(s, "inertia", built.inertia)
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
    if s.dt is None or (isinstance(s.dt, str) and s.dt.lower() == "none"):
        _set(s, "dt", None)
    elif isinstance(s.dt, str):
        raise SceneError(src, "run.dt", f'must be a positive number or "none", got {s.dt!r}')
    else:
        _set(s, "dt", _number(src, "run.dt", s.dt, positive=True))
    if not isinstance(s.method, str) or s.method not in METHODS:
        raise SceneError(src, "run.method", f"must be one of {list(METHODS)}, got {s.method!r}")
    for key in ("rtol", "atol"):
        value = getattr(s, key)
        if value is not None:
            _set(s, key, _number(src, f"run.{key}", value, positive=True))
    try:
        run_options(t_end=s.t_end, frames=s.frames, dt=s.dt, method=s.method, rtol=s.rtol,
                    atol=s.atol, max_steps=None, flips=True, threads=None)
    except (TypeError, ValueError) as exc:
        raise SceneError(src, "run", str(exc)) from None
    if s.box is not None:
        _set(s, "box", _triple(src, "body.box", s.box, positive=True))
    if s.signal_point is None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            _set(s, "signal_point", default_signal_point(s.body, s.drawn_shape))
    _set(s, "signal_point", _triple(src, "body.signal_point", s.signal_point))
    _drawable(src, "body.signal_point", float(np.hypot.reduce(s.signal_point)))
    if s.box is not None:
        _drawable(src, "body.box", max(s.box))
    _set(s, "flips", _flag(src, "ask.flips", s.flips))

    draw = _table(src, "draw", s.draw, Draw)
    flags = {n: _flag(src, f"draw.{n}", draw.get(n, False))
             for n in ("box", "ellipsoid", "signal_point", "path", "body_axes", "momentum",
                       "animation")}
    figures = _strings(src, "draw.figures", draw.get("figures", ()), FIGURES)
    phases = draw.get("phases", ())
    if isinstance(phases, str) or not isinstance(phases, (list, tuple)):
        raise SceneError(src, "draw.phases", f"must be a list of times, got {phases!r}")
    if len(phases) > MAX_PHASES:
        raise SceneError(src, "draw.phases", f"must list at most {MAX_PHASES} instants (one "
                         f"3-D panel each), got {len(phases)}")
    times = tuple(_number(src, "draw.phases", t) for t in phases)
    if any(not 0.0 <= t <= s.t_end for t in times):
        raise SceneError(src, "draw.phases", f"must be times in [0, run.t_end = {s.t_end:g}], "
                         f"got {list(times)}")
    movie = {n: None if draw.get(n) is None else _integer(src, f"draw.{n}", draw[n], low, high)
             for n, low, high in (("fps", 1, 1000), ("animation_size", 64, 4096))}
    _set(s, "draw", Draw(**flags, figures=figures, phases=times, fps=movie["fps"],
                         animation_size=movie["animation_size"]))

    style = _table(src, "ellipsoid", s.ellipsoid, EllipsoidStyle)
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

    if flags["box"] and s.box is None and s.body.shape is None:
        derived = _uniform_box(inertia)
        if derived is None:
            raise SceneError(src, "body.box", "is needed to draw the box: no uniform box has "
                             "the moments of `body.inertia`")
        _drawable(src, "body.inertia", max(derived), "the box these moments give")
    if flags["ellipsoid"]:
        semi_axes = ellipsoid_semi_axes(s.body if s.body_spec is not None else inertia,
                                        convention)
        _drawable(src, "body.inertia", float(semi_axes.max()),
                  f"the {convention} ellipsoid's largest semi-axis")
    if flags["animation"] and s.frames > MAX_ANIMATION_FRAMES:
        raise SceneError(src, "run.frames", f"must be at most {MAX_ANIMATION_FRAMES} for an "
                         f"animation (each frame is drawn and kept until the GIF is written), "
                         f"got {s.frames}; store fewer frames or set `draw.animation = false`")


def _table(source: str, key: str, value: Any, kind: type) -> Mapping[str, Any]:
    """A scene's sub-table (`draw`, `ellipsoid`) as a mapping of its keys: from a file, from
    its dataclass, or from a mapping given in Python (``scene.replace(draw={...})``)."""
    if isinstance(value, _Raw):
        return value.table
    if isinstance(value, kind):
        table: dict[str, Any] = dataclasses.asdict(value)  # type: ignore[call-overload]
        return table
    if isinstance(value, Mapping):
        known = [f.name for f in dataclasses.fields(kind)]
        unknown = [k for k in value if k not in known]
        if unknown:
            raise SceneError(source, f"{key}.{unknown[0]}", f"is not a known key; allowed in "
                             f"[{key}]: {', '.join(known)}")
        return value
    raise SceneError(source, key, f"must be a {kind.__name__} or a table of its keys, got "
                     f"{type(value).__name__}")


MAX_TEXT_NESTING = 10
"""The deepest nesting of braces (``{…}``, ``\\left…\\right``) in a title's mathtext
(``$…$``): matplotlib's parser recurses once per level, and runs out of stack at some 30
levels, fewer the deeper the drawing call."""


def _drawable_text(source: str, key: str, text: str) -> None:
    """Refuses text that matplotlib cannot draw as its title: mathtext (an even number of
    unescaped ``$``) nested too deeply for its parser, or that its parser refuses."""
    dollars = text.count("$") - text.count(r"\$")
    if dollars <= 0 or dollars % 2:
        return  # plain text: drawn as it is
    depth = deepest = 0
    for token in re.finditer(r"\\left|\\right|(?<!\\)[{}]", text):
        depth += 1 if token.group() in ("{", "\\left") else -1
        deepest = max(deepest, depth)
    if deepest > MAX_TEXT_NESTING:
        raise SceneError(source, key, f"nests its mathtext ($…$) {deepest} levels deep, more "
                         f"than the {MAX_TEXT_NESTING} a figure draws (matplotlib's parser "
                         "recurses once per level)")
    from matplotlib.mathtext import MathTextParser  # only for a title with mathtext

    try:
        MathTextParser("path").parse(text)
    except (ValueError, RecursionError) as exc:
        first = str(exc).strip().splitlines()
        raise SceneError(source, key, "is mathtext ($…$) that matplotlib cannot draw: "
                         f"{first[-1] if first else type(exc).__name__}") from None


def _drawable(source: str, key: str, size: float, what: str = "") -> None:
    """Refuses a size too large to draw (see :data:`MAX_DRAWN_SIZE`)."""
    if not size <= MAX_DRAWN_SIZE:
        of = f" ({what})" if what else ""
        raise SceneError(source, key, f"gives a size{of} of {size:.3g}, more than the "
                         f"{MAX_DRAWN_SIZE:.0e} a drawing can hold; scale the scene down")


def _validate_models(s: Scene, src: str) -> None:
    """Checks and builds a scene's deployment and damper."""
    _build_model(s, src, "deployment", Deployment, ("times", "inertia"))
    _build_model(s, src, "damper", Damper, ("inertia", "damping"))
    if s.sigma0 is not None:
        if s.damper is None:
            raise SceneError(src, "damper.sigma", "needs a [damper]")
        _set(s, "sigma0", _vector(src, "damper.sigma", s.sigma0, 3))
    if s.deployment is not None and s.damper is not None:
        raise SceneError(src, "damper", "cannot be combined with a [deployment]")


def _build_model(s: Scene, src: str, name: str, kind: type, keys: tuple[str, ...]) -> None:
    """Builds the scene's model `name` (a table of `keys` read from TOML) as a `kind`, or
    checks that it is one."""
    value = getattr(s, name)
    if isinstance(value, _Raw):
        for key in keys:
            if key not in value.table:
                raise SceneError(src, f"{name}.{key}", "is missing")
        try:
            _set(s, name, kind(*(value.table[key] for key in keys)))
        except (TypeError, ValueError) as exc:
            raise SceneError(src, name, str(exc)) from None
    elif value is not None and not isinstance(value, kind):
        raise SceneError(src, name, f"must be a {kind.__name__}, got {value!r}")


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
        The file is missing, not a regular file, larger than :data:`MAX_SCENE_BYTES`, not
        UTF-8 TOML (or nested too deeply to read), or has a key that is unknown, missing, of
        the wrong type or out of range; the message names the file, the key and what is
        allowed.
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
        text = _read_scene_file(p)
    except (OSError, ValueError) as exc:  # ValueError: a NUL in the path, or not UTF-8
        why = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        if isinstance(exc, UnicodeDecodeError):
            why = f"not UTF-8 text: {exc.reason} at byte {exc.start}"
        raise SceneError(str(p), None, f"cannot be read ({why}); give a scene file or one of "
                         f"the shipped scenes: {shipped}") from None
    return Scene.from_toml(text, p.stem, str(p), base=p.parent)


def _read_scene_file(path: Path) -> str:
    """The text of a scene file: a regular file of at most :data:`MAX_SCENE_BYTES`, read
    without ever holding more (a device or a FIFO could give bytes for ever; a FIFO is not
    even opened for a writer to come)."""
    try:
        f = open_regular(path, "a scene file")
    except ReadError as exc:
        raise ValueError(exc.why) from None
    with f:
        data = f.read(MAX_SCENE_BYTES + 1)
    if len(data) > MAX_SCENE_BYTES:
        raise ValueError(f"larger than {MAX_SCENE_BYTES} bytes, the most a scene file may "
                         "hold")
    return data.decode("utf-8")


def _shipped() -> dict[str, Scene]:
    folder = resources.files("dzhanibekov") / "scenes"
    scenes = {}
    for item in sorted(folder.iterdir(), key=lambda f: f.name):
        if item.name.endswith(".toml"):
            name = item.name[: -len(".toml")]
            scenes[name] = Scene.from_toml(item.read_text(encoding="utf-8"), name,
                                           f"dzhanibekov/scenes/{item.name}",
                                           base=Path(str(folder)))
    return scenes


SCENES: Mapping[str, Scene] = _shipped()
"""The shipped scenes by name: the paper's (see :data:`PAPER_SCENES`) and two stable
counter-examples, ``stable-largest`` and ``stable-smallest``."""

PAPER_SCENES = ("example", "fig3a", "fig3b", "fig3c")
"""The scenes of the paper's figures: ``example`` (Fig. 2) and ``fig3a``–``fig3c``."""

STORY_SCENES = ("deployment", "explorer-1")
"""Bodies that change: a stowed major-axis spin deployed to an intermediate one, which
tumbles; and Explorer 1's minor-axis spin going flat through a damper."""
