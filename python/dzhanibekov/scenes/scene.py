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
    # frame = "lvlh"                       # both relative to the orbiting frame ([orbit])

    [run]
    t_end = 100.0
    frames = 201
    dt = 1e-3                              # or "none" (the default): the step for `rtol`
    method = "rk4"                         # one of dzhanibekov.METHODS
    # rtol = 1e-9                          # accuracy of dt = "none", or an adaptive method's
    # atol = 1e-12                         # adaptive methods only (default rtol/1000)

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

Parts and external torques, any number of each, of any model a file can hold
(``dz.MODELS``; each entry its model's ``kind`` and parameters by name)::

    [[parts]]
    kind = "wheel"
    axis = [0.0, 1.0, 0.0]
    momentum = 0.2

    [[torques]]
    kind = "tabulated_torque"
    times = [0.0, 1.0, 2.0]
    vectors = [[0.0, 0.0, 0.0], [0.0, 0.0, 1e-3], [0.0, 0.0, 0.0]]

The single tables ``[damper]``, ``[wheel]``, ``[orbit]`` and ``[torque]`` are aliases of one
entry each (their parts come first).

Loading checks every key: an unknown key, a value of the wrong type or out of range is a
:class:`SceneError` naming the file, the key and what is allowed.

A scene is parsed, then constructed. The checks are pure functions of the raw values
(:mod:`.parse`): :func:`~.parse.from_tables` reads a file's tables, :func:`~.parse.checked`
checks and normalises a scene's keyword values, whether from a file, from ``Scene(...)`` or
from :meth:`Scene.replace`. A :class:`Scene` is a frozen dataclass whose own ``__init__``
stores only what :func:`~.parse.checked` returned: ``Scene(...)`` and
:func:`dataclasses.replace` both call the class, so the class's metaclass (``_Parsed``) is the
one place both go through, and it parses the keywords before the dataclass stores them. The
alternatives would change the public API (a ``Scene.make`` factory beside a ``Scene(...)`` that
takes only normalised values) or write a frozen instance after construction (a
``__post_init__`` that normalises its own fields).
"""

from __future__ import annotations

import dataclasses
import inspect
import os
import re
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from importlib import resources
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import tomli_w

from .._files import ReadError, describe, open_regular, write_text
from ..body import Body
from ..damper import Damper
from ..deployment import Deployment
from ..shapes import Shape
from ..methods import DEFAULT_METHOD
from ..simulate import simulate
from ..summary import Summary, summarize
from ..results import Trajectory
from ..orbit import ConstantTorque, GravityGradient, Wheel
from ..parts import Part
from ..system import System
from .parse import (CONVENTIONS, FIGURES, MAX_ANIMATION_FRAMES, MAX_DRAWN_SIZE, MAX_PHASES,
                    MAX_TEXT_NESTING, Draw, EllipsoidStyle, SceneError, checked, drawn_shape,
                    from_tables, part_table, scene_body, uniform_box)

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
    "MAX_TEXT_NESTING",
    "PAPER_SCENES",
    "SCENES",
    "STORY_SCENES",
    "Draw",
    "EllipsoidStyle",
    "Scene",
    "SceneError",
    "load_scene",
]

_DEFAULT_PHASES = 6

MAX_SCENE_BYTES = 1 << 20
"""The largest scene file :func:`load_scene` reads (1 MiB); scenes are a few hundred bytes."""

_T = TypeVar("_T")


class _Parsed(type):
    """The metaclass of :class:`Scene`: calling the class parses its keywords
    (:func:`~.parse.checked`) before the dataclass's ``__init__`` stores them, and keeps the
    body that parsing built as the scene's `body` (a cached property, filled)."""

    def __call__(cls: type[_T], *args: Any, **kwargs: Any) -> _T:
        init = inspect.signature(cls.__init__)
        try:
            bound = init.bind(None, *args, **kwargs)
        except TypeError as exc:
            raise TypeError(f"{cls.__name__}(): {exc}") from None
        bound.apply_defaults()
        values = dict(bound.arguments)
        del values[next(iter(init.parameters))]  # self
        fields, body = checked(values)
        scene: _T = type.__call__(cls, **fields)
        scene.__dict__["body"] = body  # the cached property `body`, not a field
        return scene


@dataclass(frozen=True)
class Scene(metaclass=_Parsed):
    """A run and what to draw or ask of it. Construct it directly or load a TOML file with
    :func:`load_scene`; both are checked the same way (:class:`SceneError`), and the fields
    hold the checked values (tuples of floats, a :class:`Draw` for a table of its keys).

    Examples
    --------
    >>> s = Scene("mine", "my body", inertia=[1, 2, 3], omega0=[0, 1, 0.01], t_end=10,
    ...           frames=11)
    >>> s.inertia, s.t_end
    ((1.0, 2.0, 3.0), 10.0)
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
    list of principal moments or 3 × 3 tensors, and its ``mass`` to carry parts whose mass
    moves, ``[[parts]]`` of kind ``spring_mass``, ``hinge`` or ``slosh``); `inertia` is then
    the body at ``t = 0`` (the drawn box keeps its size)."""
    damper: Damper | None = None
    """A spherical viscous damper (``[damper]`` with ``inertia`` and ``damping``)."""
    sigma0: tuple[float, float, float] | None = None
    """The damper's initial rate (``damper.sigma``); None: co-rotating."""
    wheel: Wheel | None = None
    """A momentum wheel (``[wheel]`` with ``axis``, body axes, and ``momentum``: a number or
    a schedule ``{ times = [...], values = [...] }``)."""
    orbit: GravityGradient | None = None
    """The gravity gradient of a circular orbit (``[orbit]`` with ``rate``); the start is in
    world axes (:func:`~dzhanibekov.lvlh_start` gives one relative to the orbiting frame)."""
    torque: ConstantTorque | None = None
    """A constant torque (``[torque]`` with ``vector`` and ``frame``, ``"body"`` (default) or
    ``"world"``)."""
    parts: tuple[Part, ...] = ()
    """Any number of parts (``[[parts]]``: tables with the ``kind`` of a model of
    ``dz.MODELS`` and its parameters), after the damper and the wheel of the single tables."""
    torques: tuple[Part, ...] = ()
    """Any number of external torques (``[[torques]]``, as `parts`), after the orbit and the
    torque of the single tables."""
    source: str = field(default="", compare=False, repr=False)
    """Where the scene came from, for messages."""
    rtol: float | None = None
    """The accuracy `dt` = None is picked for, or an adaptive method's relative tolerance
    (default `dzhanibekov.accuracy.DEFAULT_RTOL`)."""
    atol: float | None = None
    """An adaptive method's absolute tolerance (default ``rtol / 1000``:
    `dzhanibekov.accuracy.DEFAULT_ATOL` at the default `rtol`)."""
    body_spec: Mapping[str, Any] | None = None
    """The body, when it is more than principal moments: the `[body]` table's keys that
    name it (``tensor``, ``cylinder``, ``sphere``, ``ellipsoid``, ``mesh``, ``parts`` or
    ``preset``, with ``mass``/``density``); `inertia` then holds its principal moments.
    A mesh path is kept absolute."""

    given: System | None = field(default=None, compare=False, repr=False)
    """The system itself, when the scene stages one given as a value (a trajectory drawn as a
    scene, `dzhanibekov.scenes.staging`): its body is drawn as it is, its parts kept."""

    # -- running ------------------------------------------------------------------------

    @cached_property
    def body(self) -> Body:
        """The body the scene names (built once, when the scene is checked): a deployment's
        at its first knot."""
        return scene_body(self.given, self.body_spec, self.inertia)

    @cached_property
    def system(self) -> System:
        """What the scene runs: its body (or deployment) with its damper, if any."""
        if self.given is not None:
            return self.given
        body = self.deployment if self.deployment is not None else self.body
        parts: list[Part] = [] if self.damper is None else [
            Damper(self.damper.inertia, self.damper.damping, self.sigma0)]
        if self.wheel is not None:
            parts.append(self.wheel)
        parts.extend(self.parts)
        torques = [t for t in (self.orbit, self.torque) if t is not None] + list(self.torques)
        return System(body, parts=parts, torques=torques)

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
        derived = uniform_box(self.inertia)
        if derived is None:
            raise SceneError(self.source or f"<scene {self.name}>", "body.box",
                             "is needed: no uniform box has these moments")
        return derived

    @property
    def drawn_shape(self) -> Shape | None:
        """What is drawn for the body: its own shape, else the box (`box`, or the uniform
        box of its moments, in its principal axes); None if there is none."""
        return drawn_shape(self.body, self.box, self.inertia)

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
            if self.deployment.mass is not None:
                out["deployment"]["mass"] = self.deployment.mass
        if self.damper is not None:
            out["damper"] = {"inertia": self.damper.inertia, "damping": self.damper.damping}
            if self.sigma0 is not None:
                out["damper"]["sigma"] = list(self.sigma0)
        if self.wheel is not None:
            momentum = self.wheel.momentum
            out["wheel"] = {"axis": list(self.wheel.axis), "momentum": momentum
                            if isinstance(momentum, float) else
                            {"times": list(momentum[0]), "values": list(momentum[1])}}
        if self.orbit is not None:
            out["orbit"] = {"rate": self.orbit.orbit_rate}
        if self.torque is not None:
            out["torque"] = {"vector": list(self.torque.vector), "frame": self.torque.frame}
        for key in ("parts", "torques"):
            if getattr(self, key):
                out[key] = [part_table(p) for p in getattr(self, key)]
        return out

    def to_toml(self) -> str:
        """The scene as TOML text that :meth:`from_toml` reads back to an equal scene; short
        arrays on one line, as the shipped files write them (``omega = [0.01, 0.01, 1.0]``).
        """
        return _inline_arrays(tomli_w.dumps(self.to_dict()))

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
        return cls(**from_tables(data, name, source, Path(base) if base is not None else None))





_INIT = inspect.signature(Scene.__init__)
Scene.__signature__ = _INIT.replace(  # type: ignore[attr-defined]
    parameters=list(_INIT.parameters.values())[1:], return_annotation=inspect.Signature.empty)
"""``Scene(...)``'s signature (the dataclass's, not the metaclass's ``*args, **kwargs``), for
:func:`inspect.signature`, :func:`help` and the docs."""

_ARRAY = re.compile(r"\[\n((?:[ ]+[^ \]\n][^\n]*,\n)+)[ ]*\]")
"""An array that tomli_w wrote one item a line, each item on one line."""
_INLINE_WIDTH = 96
"""The longest line an array is put on."""


def _inline_arrays(text: str) -> str:
    """`text` (TOML from tomli_w) with each array that fits on one line put there, inner
    arrays first; the same data (checked by reading both)."""
    def one_line(match: re.Match[str]) -> str:
        items = ", ".join(line.strip().removesuffix(",") for line in match.group(1).splitlines())
        start = text.rfind("\n", 0, match.start()) + 1  # the line the array opens on
        fits = match.start() - start + len(items) + 2 <= _INLINE_WIDTH
        return f"[{items}]" if fits else match.group(0)

    written = compact = text
    while True:
        text = compact
        compact = _ARRAY.sub(one_line, text)
        if compact == text:
            break
    return compact if tomllib.loads(compact) == tomllib.loads(written) else written



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
        # a folder is never a scene file: `run NAME` writes into a folder NAME by default
        if (not p.exists() or p.is_dir()) and isinstance(path, str) and path in SCENES:
            return SCENES[path]
        text = _read_scene_file(p)
    except (OSError, ValueError) as exc:  # ValueError: a NUL in the path, or not UTF-8
        why = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        if isinstance(exc, UnicodeDecodeError):
            kind = describe(exc.object[:64])  # a format it names, or just "binary data"
            why = (f"it is {kind}, not a scene's TOML text"
                   if kind not in ("text", "binary data") else
                   f"not UTF-8 text: {exc.reason} at byte {exc.start}")
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
