"""Parsing a scene: the raw values of a TOML file or of ``Scene(...)`` in, checked values out.

Every function here is pure: it takes raw values (a file's tables, the keywords a user
passed) and returns checked, normalised values (tuples of floats, a :class:`Draw`, a
:class:`~dzhanibekov.Deployment`, the body built), or raises :class:`SceneError` naming the
key at fault and what is allowed. :class:`~dzhanibekov.scenes.scene.Scene` is then
constructed once from what :func:`checked` returns (see :mod:`.scene`); nothing here holds
or changes a scene.

Two steps, in order:

- :func:`from_tables`: a file's nested tables → the keyword values of a scene (unknown keys,
  missing keys, the body named by ``[body]``, the ``[deployment]``, ``[damper]``,
  ``[wheel]``, ``[orbit]`` and ``[torque]`` built, and the ``[[parts]]`` and ``[[torques]]``
  of any model);
- :func:`checked`: a scene's keyword values (from a file or from Python) → its checked
  fields and its body, every key checked alone and against the others (the run's options
  together, the phases within the run, sizes a drawing can hold).
"""

from __future__ import annotations

import dataclasses
import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._args import as_array, as_float, as_int, run_options
from ..body import Body, InertiaWarning
from ..control import QuaternionFeedback
from ..damper import Damper
from ..deployment import Deployment
from ..geometry import CONVENTIONS, ellipsoid_semi_axes
from ..lvlh import lvlh_start
from ..methods import DEFAULT_MAX_STEPS, METHODS
from .. import _core
from ..orbit import ConstantTorque, GravityGradient, Wheel
from ..parts import SPECS, from_fields, params_of
from ..parts import Part as AnyPart
from ..parts._columns import storable_models
from ..shapes import Shape, box_shape
from ..system import System
from .bodies import BODY_KEYS, build_body, default_signal_point

__all__ = [
    "CONVENTIONS",
    "FIGURES",
    "MAX_ANIMATION_FRAMES",
    "MAX_DRAWN_SIZE",
    "MAX_PHASES",
    "MAX_TEXT_NESTING",
    "TABLES",
    "Draw",
    "EllipsoidStyle",
    "SceneError",
    "checked",
    "drawn_label",
    "drawn_shape",
    "from_tables",
    "scene_body",
    "uniform_box",
]

FIGURES = ("phases", "path", "omega", "invariants", "polhode", "shares", "energy", "lvlh",
           "wheel_off",
           "detumble", "pointing", "energy_balance", "part_motion", "capture")
"""Figures a scene may ask for: the phases panel (Fig. 2), the signal point's path in 3-D
(Fig. 3), ω(t) with the flips marked, the invariants' drift, the polhode, the share of
``|L|`` on each body axis, the total kinetic energy (with ``|L_world|``), the attitude
relative to the orbiting frame (roll, pitch, yaw; with ``[orbit]``), the spin axis's tilt
beside the same run with its wheel off (with ``[wheel]``), the rate ``|ω|`` against orbits
(a detumble), the angle from a target with the wheels' momenta and torques (with a
``quaternion_feedback`` in ``[[parts]]``), and for energy sinks (``[[parts]]`` of kind
``spring_mass``, ``hinge`` or ``slosh``) the energy balance, the parts' motion and, with a
``slosh``, the flips before capture against its damping."""

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
_MAX_CELLS = 256
"""Most cells of the ellipsoid mesh along either direction, for a drawing."""

MAX_ANIMATION_FRAMES = 20_000
"""Most frames (`run.frames`) of a scene that draws an animation: its plan rotates every
drawn point at every frame. (The animation itself draws at most
:data:`dzhanibekov.plotting.movie.MAX_FRAMES` frames, whatever the scene stores.)"""
MAX_PHASES = 24
"""Most instants (`draw.phases`) of the phases panel: each is one 3-D panel of the figure."""
MAX_DRAWN_SIZE = 1e100
"""The largest size a scene draws (|`body.signal_point`|, `body.box` edges, the inertia
ellipsoid's semi-axes): drawing squares lengths and view limits, which must stay finite."""
MAX_TEXT_NESTING = 10
"""The deepest nesting of braces (``{…}``, ``\\left…\\right``) in a title's mathtext
(``$…$``): matplotlib's parser recurses once per level, and runs out of stack at some 30
levels, fewer the deeper the drawing call."""


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
    """The animation's frames per second; None: the default
    (:data:`dzhanibekov.plotting.movie.FPS`)."""
    animation_size: int | None = None
    """The animation's width and height in pixels; None: the default
    (:data:`dzhanibekov.plotting.movie.SIZE_PX`)."""

    @property
    def objects(self) -> tuple[str, ...]:
        """The 3-D objects drawn, by name."""
        names = ("box", "ellipsoid", "signal_point", "path", "body_axes", "momentum")
        return tuple(n for n in names if getattr(self, n))


# -- a file's tables ----------------------------------------------------------------------

TABLES: dict[str, tuple[str, ...]] = {
    "body": ("inertia", "box", "mass", "signal_point") + ("tensor", "cylinder", "sphere",
             "ellipsoid", "mesh", "density", "parts", "preset"),
    "start": ("omega", "q", "frame"),
    "run": ("t_end", "frames", "dt", "method", "rtol", "atol"),
    "ask": ("flips",),
    "draw": ("box", "ellipsoid", "signal_point", "path", "body_axes", "momentum", "figures",
             "animation", "phases", "fps", "animation_size"),
    "ellipsoid": ("convention", "mesh"),
    "deployment": ("times", "inertia", "mass"),
    "damper": ("inertia", "damping", "sigma"),
    "wheel": ("axis", "momentum"),
    "orbit": ("rate",),
    "torque": ("vector", "frame"),
}
"""The tables of a scene file and the keys each may hold."""
LISTS = ("parts", "torques")
"""The arrays of tables of a scene file (``[[parts]]``, ``[[torques]]``): any number of parts
and external torques, each a table with its model's ``kind`` (a name of ``dz.MODELS``) and its
parameters by name (``dz.MODELS[kind].params``). ``[damper]``, ``[wheel]``, ``[orbit]`` and
``[torque]`` are aliases of one entry each."""
_TOP = ("title", "about")

_OPTIONAL = {
    ("start", "q"): "q0",
    ("run", "dt"): "dt",
    ("run", "method"): "method",
    ("run", "rtol"): "rtol",
    ("run", "atol"): "atol",
    ("body", "box"): "box",
    ("body", "signal_point"): "signal_point",
    ("ask", "flips"): "flips",
    ("draw", None): "draw",
    ("ellipsoid", None): "ellipsoid",
    ("damper", "sigma"): "sigma0",
}
"""Optional keys of a file (None: the whole table) → the scene's keyword they give."""


def from_tables(data: Mapping[str, Any], name: str, source: str,
                base: Path | None = None) -> dict[str, Any]:
    """The keyword values of the scene a file's nested tables describe, before
    :func:`checked`: the tables' keys are known and the required ones there, the body that
    ``[body]`` names is a `body_spec` (a mesh path made absolute against `base`, default the
    current folder) or principal moments, ``[deployment]`` and ``[damper]`` are built.

    Raises
    ------
    SceneError
        An unknown or missing key, a table that is not one, two bodies named, a model that
        its class refuses.
    """
    def fail(key: str, message: str) -> SceneError:
        return SceneError(source, key, message)

    allowed_top = _TOP + tuple(f"[{t}]" for t in TABLES) + tuple(f"[[{t}]]" for t in LISTS)
    for key, value in data.items():
        if key in LISTS:
            continue  # checked entry by entry below
        if key in TABLES:
            if not isinstance(value, dict):
                raise fail(key, f"must be a table [{key}], got {type(value).__name__}")
            for sub in value:
                if sub not in TABLES[key]:
                    raise fail(f"{key}.{sub}", "is not a known key; allowed in "
                               f"[{key}]: {', '.join(TABLES[key])}")
        elif key not in _TOP:
            raise fail(key, f"is not a known key; allowed: {', '.join(allowed_top)}")
    tables = {t: data.get(t, {}) for t in TABLES}

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
    kwargs: dict[str, Any] = {
        "name": name,
        "inertia": inertia,
        "omega0": need("start", "omega"),
        "t_end": need("run", "t_end"),
        "frames": need("run", "frames"),
        "source": source,
        "about": data.get("about", ""),
        "body_spec": spec or None,
    }
    _check_name(source, name)
    if "title" not in data:
        raise fail("title", "is missing; give the scene a title")
    kwargs["title"] = data["title"]
    for (table, sub), keyword in _OPTIONAL.items():
        if sub is None:
            kwargs[keyword] = tables[table]
        elif sub in tables[table]:
            kwargs[keyword] = tables[table][sub]
    if "deployment" in data:
        kwargs["deployment"] = _model(source, "deployment", Deployment, ("times", "inertia"),
                                      tables["deployment"], optional=("mass",))
    if "damper" in data:
        kwargs["damper"] = _model(source, "damper", Damper, ("inertia", "damping"),
                                  tables["damper"])
    if "wheel" in data:
        kwargs["wheel"] = _model(source, "wheel", Wheel, ("axis", "momentum"),
                                 _wheel_table(source, tables["wheel"]))
    if "orbit" in data:
        kwargs["orbit"] = _model(source, "orbit", GravityGradient, ("rate",), tables["orbit"],
                                 {"orbit_rate": "rate"})
    for key in LISTS:
        if key in data:
            kwargs[key] = scene_parts(source, key, data[key])
    frame = tables["start"].get("frame", "world")
    if frame not in START_FRAMES:
        raise fail("start.frame", f"must be one of {list(START_FRAMES)}, got {frame!r}")
    if frame == "lvlh":
        kwargs["omega0"], kwargs["q0"] = _lvlh_start(source, kwargs, tables["start"])
    if "torque" in data:
        torque = tables["torque"]
        frame = torque.get("frame", "body")
        kwargs["torque"] = _model(source, "torque", ConstantTorque, ("vector", "frame"),
                                  {**torque, "frame": frame})
    return kwargs


START_FRAMES = ("world", "lvlh")
"""What a file's ``[start]`` is relative to: the world (inertial) frame, or the orbiting
frame (LVLH) of its ``[orbit]`` at ``t = 0``."""


def _lvlh_start(source: str, kwargs: Mapping[str, Any],
                start: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """The world start of a ``[start]`` given relative to LVLH (``frame = "lvlh"``):
    :func:`~dzhanibekov.lvlh_start` of the orbit's rate, ``q`` (LVLH-from-body) and ``omega``
    (rates relative to the orbiting frame, body axes)."""
    orbit = kwargs.get("orbit") or next(
        (t for t in kwargs.get("torques", ()) if isinstance(t, GravityGradient)), None)
    if orbit is None:
        raise SceneError(source, "start.frame", "is \"lvlh\", relative to the orbiting frame, "
                         "but the scene has no [orbit] (or gravity gradient in [[torques]]) "
                         "to give its rate")
    omega = _vector(source, "start.omega", start["omega"], 3)
    q = _quaternion(source, "start.q", start.get("q", (1.0, 0.0, 0.0, 0.0)))
    return lvlh_start(orbit.orbit_rate, q, omega)


def scene_parts(source: str, key: str, entries: Any) -> tuple[AnyPart, ...]:
    """The parts (`key` ``"parts"``) or external torques (``"torques"``) of an array of
    tables ``[[parts]]``: each a table with the ``kind`` of its model and that model's
    parameters by name, built by the model's class (:mod:`dzhanibekov.parts`), or parts
    given as values (``Scene(parts=[dz.Wheel(...)])``). Errors name the entry and its key
    (``parts[1].axis``)."""
    if isinstance(entries, (str, bytes, Mapping)) or not isinstance(entries, (list, tuple)):
        raise SceneError(source, key, f"must be an array of tables [[{key}]], each with a "
                         f"`kind`, got {type(entries).__name__}")
    kinds = [m for m in storable_models() if key in SPECS[m].lists]
    out = []
    for i, entry in enumerate(entries):
        where = f"{key}[{i}]"
        if isinstance(entry, AnyPart):
            if key not in entry.lists:
                raise SceneError(source, where, f"is a {type(entry).__name__}: give it in "
                                 f"`{entry.lists[0]}`")
            out.append(entry)
            continue
        if not isinstance(entry, Mapping):
            raise SceneError(source, where, f"must be a table with a `kind`, got "
                             f"{type(entry).__name__}")
        kind = entry.get("kind")
        if kind is None:
            raise SceneError(source, f"{where}.kind", f"is missing; one of {', '.join(kinds)}")
        if kind not in kinds:
            if isinstance(kind, str) and kind in SPECS and key not in SPECS[kind].lists:
                message = f"is {kind!r}, which goes in [[{SPECS[kind].lists[0]}]]"
            elif isinstance(kind, str) and kind in SPECS:
                message = f"is {kind!r}, which a scene cannot hold (a file cannot hold code)"
            else:
                message = f"must be one of {', '.join(kinds)}, got {kind!r}"
            raise SceneError(source, f"{where}.kind", message)
        names = [p.name for p in params_of(kind)]
        for sub in entry:
            if sub != "kind" and sub not in names:
                raise SceneError(source, f"{where}.{sub}", f"is not a known key; allowed in a "
                                 f"{kind!r}: kind, {', '.join(names)}")
        try:
            out.append(from_fields(kind, {k: v for k, v in entry.items() if k != "kind"}))
        except (TypeError, ValueError) as exc:
            message = str(exc)
            named = next((n for n in names if f"`{n}`" in message), None)
            raise SceneError(source, where if named is None else f"{where}.{named}",
                             message if named is None else
                             message.removeprefix(f"`{named}` ")) from None
    return tuple(out)


def part_table(part: AnyPart) -> dict[str, Any]:
    """The table of `part` in a scene's ``[[parts]]`` or ``[[torques]]`` (see
    :func:`scene_parts`): its kind and its parameters, as TOML holds them."""
    out: dict[str, Any] = {"kind": part.model}
    for name, value in part.fields().items():
        if value is not None:
            out[name] = (value.tolist() if isinstance(value, np.ndarray)
                         else list(value) if isinstance(value, tuple) else value)
    return out


_WHEEL_SCHEDULE = ("times", "values")
"""The keys of a wheel's momentum schedule, ``momentum = { times = [...], values = [...] }``
(linear between the knots, held outside them)."""


def _wheel_table(source: str, table: Mapping[str, Any]) -> Mapping[str, Any]:
    """The ``[wheel]`` table with a schedule ``momentum = { times, values }`` made the pair
    ``(times, values)`` that :class:`~dzhanibekov.Wheel` takes; a number is kept."""
    momentum = table.get("momentum")
    if not isinstance(momentum, Mapping):
        return table
    for key in momentum:
        if key not in _WHEEL_SCHEDULE:
            raise SceneError(source, f"wheel.momentum.{key}", "is not a known key; allowed in "
                             f"a schedule: {', '.join(_WHEEL_SCHEDULE)}")
    for key in _WHEEL_SCHEDULE:
        if key not in momentum:
            raise SceneError(source, f"wheel.momentum.{key}", "is missing; a schedule is "
                             "`momentum = { times = [t0, t1, ...], values = [h0, h1, ...] }`")
    times, values = momentum["times"], momentum["values"]
    for key, value in (("times", times), ("values", values)):
        if isinstance(value, (str, bytes)) or _ndim(value) != 1 or any(
                isinstance(x, (bool, np.bool_)) for x in value):
            raise SceneError(source, f"wheel.momentum.{key}", f"must be a list of numbers, "
                             f"got {value!r}")
    if len(values) != len(times):
        raise SceneError(source, "wheel.momentum.values", f"must hold as many values as "
                         f"`wheel.momentum.times` holds times ({len(times)}), got {len(values)}")
    try:
        Wheel((0.0, 0.0, 1.0), (times, values))
    except (TypeError, ValueError) as exc:
        message = str(exc)
        key = "times" if "times" in message else "values"
        raise SceneError(source, f"wheel.momentum.{key}", message) from None
    return {**table, "momentum": (times, values)}


def _model(source: str, name: str, kind: type, keys: tuple[str, ...],
           table: Mapping[str, Any], renamed: Mapping[str, str] | None = None,
           optional: tuple[str, ...] = ()) -> Any:
    """The model (a `kind`) that the file's table `name` gives with its `keys` (and its
    `optional` keys, as keywords, where given); an error names the key (`renamed`: the
    constructor's argument names that are a key's)."""
    for key in keys:
        if key not in table:
            raise SceneError(source, f"{name}.{key}", "is missing")
    keys += tuple(key for key in optional if key in table)
    try:
        return kind(*(table[key] for key in keys if key not in optional),
                    **{key: table[key] for key in optional if key in table})
    except (TypeError, ValueError) as exc:
        message = str(exc)
        for argument, key in (renamed or {}).items():
            message = message.replace(f"`{argument}`", f"`{key}`")
        at = next((f"{name}.{key}" for key in keys if f"`{key}`" in message), name)
        raise SceneError(source, at, message) from None


# -- a scene's values ---------------------------------------------------------------------


def checked(values: Mapping[str, Any]) -> tuple[dict[str, Any], Body]:
    """A scene's fields, checked and normalised, and the body it names.

    Parameters
    ----------
    values : mapping
        Every field of :class:`~dzhanibekov.scenes.scene.Scene` by name, as given (from
        :func:`from_tables` or the keywords of ``Scene(...)``).

    Returns
    -------
    fields : dict
        The same fields, normalised: tuples of floats, ints, a :class:`Draw` and an
        :class:`EllipsoidStyle`, `inertia` the moments of the body `body_spec` names, the
        default `signal_point` filled in.
    body : Body
        The body drawn and run (at ``t = 0`` for a deployment).

    Raises
    ------
    SceneError
        A value of the wrong type or out of range, alone or with the others; the message
        names the source, the key and what is allowed.
    """
    v = dict(values)
    src = v["source"] or f"<scene {v['name']}>"
    _check_name(src, v["name"])
    title = _text(src, "title", v["title"], required=True)
    _drawable_text(src, "title", title)
    about = _text(src, "about", v["about"], required=False)

    spec, built, inertia_given = v["body_spec"], None, v["inertia"]
    caught: list[warnings.WarningMessage] = []
    if spec is not None:
        if not isinstance(spec, Mapping):
            raise SceneError(src, "body", f"must be a table, got {spec!r}")
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                built = build_body(spec)
        except (TypeError, ValueError, ImportError) as exc:
            key = next((k for k in BODY_KEYS if k in spec), "body")
            raise SceneError(src, f"body.{key}", f"does not give a body: {exc}") from None
        spec, inertia_given = dict(spec), built.inertia
    inertia = _triple(src, "body.inertia", inertia_given, positive=True)
    try:
        with warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")
            plain = Body(inertia)
    except (TypeError, ValueError) as exc:
        raise SceneError(src, "body.inertia", str(exc).replace("`inertia` ", "")) from None
    if spec is None:
        caught = seen
    given = v["given"]
    body = (scene_body(given, None, inertia) if given is not None
            else built if built is not None else plain)

    omega0 = _vector(src, "start.omega", v["omega0"], 3)
    q0 = _quaternion(src, "start.q", v["q0"])
    run = _run(src, v)

    box = None if v["box"] is None else _triple(src, "body.box", v["box"], positive=True)
    signal_point = v["signal_point"]
    if signal_point is None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            signal_point = default_signal_point(body, drawn_shape(body, box, inertia))
    signal_point = _triple(src, "body.signal_point", signal_point)
    _drawable(src, "body.signal_point", float(np.hypot.reduce(signal_point)))
    if box is not None:
        _drawable(src, "body.box", max(box))
    flips = _flag(src, "ask.flips", v["flips"])
    draw = _draw(src, v["draw"], run["t_end"])
    if body.shape is not None and isinstance(v["draw"], Mapping) and "box" not in v["draw"]:
        # a body of its own shape (a composite, a solid, a mesh) is drawn unless told not to
        draw = dataclasses.replace(draw, box=True)
    ellipsoid = _ellipsoid(src, v["ellipsoid"])
    models = _models(src, v)
    given_system = v["given"]
    listed = (*models["parts"], *models["torques"],
              *(() if given_system is None else (*given_system.parts, *given_system.torques)))
    has = {"lvlh": v.get("orbit") is not None or any(
               isinstance(t, GravityGradient) for t in listed),
           "wheel_off": v.get("wheel") is not None or any(isinstance(p, Wheel) for p in listed),
           "pointing": any(isinstance(p, QuaternionFeedback) for p in listed)}
    sinks = {p.model for p in listed} & set(_MOVERS)
    has |= {"energy_balance": bool(sinks), "part_motion": bool(sinks),
            "capture": "slosh" in sinks}
    for figure, table in (("lvlh", "[orbit]"), ("wheel_off", "[wheel]"),
                          ("pointing", "[[parts]] entry of kind \"quaternion_feedback\""),
                          ("energy_balance", "energy sink in [[parts]]"),
                          ("part_motion", "energy sink in [[parts]]"),
                          ("capture", "slosh in [[parts]]")):
        if figure in draw.figures and not has[figure]:
            raise SceneError(src, "draw.figures", f"names {figure!r}, which needs an {table}")

    if draw.box and box is None and body.shape is None:
        derived = uniform_box(inertia)
        if derived is None:
            raise SceneError(src, "body.box", "is needed to draw the box: no uniform box has "
                             "the moments of `body.inertia`")
        _drawable(src, "body.inertia", max(derived), "the box these moments give")
    if draw.ellipsoid:
        semi_axes = ellipsoid_semi_axes(body, ellipsoid.convention)  # its mass divides
        _drawable(src, "body.inertia", float(semi_axes.max()),
                  f"the {ellipsoid.convention} ellipsoid's largest semi-axis")
    if draw.animation and run["frames"] > MAX_ANIMATION_FRAMES:
        raise SceneError(src, "run.frames", f"must be at most {MAX_ANIMATION_FRAMES} for an "
                         f"animation (every drawn point is rotated at every frame), "
                         f"got {run['frames']}; store fewer frames or set "
                         "`draw.animation = false`")
    fields = v | run | models | dict(
        title=title, about=about, body_spec=spec, inertia=inertia, omega0=omega0, q0=q0,
        box=box, signal_point=signal_point, flips=flips, draw=draw, ellipsoid=ellipsoid)
    # a scene that is refused does not also warn
    _warn_inertia(src, "body" if spec is not None else "body.inertia", caught)
    return fields, body


def _check_name(source: str, name: Any) -> None:
    if not isinstance(name, str) or not _NAME.match(name):
        raise SceneError(source, "name", "must be letters, digits, '_', '-' or '.' (it names "
                         f"the output files), got {name!r}")


def _run(src: str, v: Mapping[str, Any]) -> dict[str, Any]:
    """The `[run]` keys, checked alone and together (as :func:`~dzhanibekov.simulate` would)."""
    t_end = _number(src, "run.t_end", v["t_end"], positive=True)
    frames = _integer(src, "run.frames", v["frames"], 2)
    dt = v["dt"]
    if dt is None or (isinstance(dt, str) and dt.lower() == "none"):
        dt = None
    elif isinstance(dt, str):
        raise SceneError(src, "run.dt", f'must be a positive number or "none", got {dt!r}')
    else:
        dt = _number(src, "run.dt", dt, positive=True)
    method = v["method"]
    if not isinstance(method, str) or method not in METHODS:
        raise SceneError(src, "run.method", f"must be one of {list(METHODS)}, got {method!r}")
    tolerances = {key: None if v[key] is None else _number(src, f"run.{key}", v[key],
                                                          positive=True)
                  for key in ("rtol", "atol")}
    try:
        run_options(t_end=t_end, frames=frames, dt=dt, method=method, max_steps=DEFAULT_MAX_STEPS,
                    flips=True, threads=None, **tolerances)
    except (TypeError, ValueError) as exc:
        raise SceneError(src, "run", str(exc)) from None
    return dict(t_end=t_end, frames=frames, dt=dt, method=method, **tolerances)


def _draw(src: str, value: Any, t_end: float) -> Draw:
    """The `[draw]` table (or a :class:`Draw`), checked; its phases within ``[0, t_end]``."""
    draw = _table(src, "draw", value, Draw)
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
    if any(not 0.0 <= t <= t_end for t in times):
        raise SceneError(src, "draw.phases", f"must be times in [0, run.t_end = {t_end:g}], "
                         f"got {list(times)}")
    movie = {n: None if draw.get(n) is None else _integer(src, f"draw.{n}", draw[n], low, high)
             for n, low, high in (("fps", 1, 1000), ("animation_size", 64, 4096))}
    return Draw(**flags, figures=figures, phases=times, fps=movie["fps"],
                animation_size=movie["animation_size"])


def _ellipsoid(src: str, value: Any) -> EllipsoidStyle:
    """The `[ellipsoid]` table (or an :class:`EllipsoidStyle`), checked."""
    style = _table(src, "ellipsoid", value, EllipsoidStyle)
    convention = style.get("convention", "gyration")
    if convention not in CONVENTIONS:
        raise SceneError(src, "ellipsoid.convention",
                         f"must be one of {list(CONVENTIONS)}, got {convention!r}")
    mesh = style.get("mesh", (24, 12))
    if isinstance(mesh, str) or not isinstance(mesh, (list, tuple)) or len(mesh) != 2:
        raise SceneError(src, "ellipsoid.mesh", f"must be [eN, eM], two integers, got {mesh!r}")
    e_n = _integer(src, "ellipsoid.mesh[0]", mesh[0], 3, _MAX_CELLS)  # eN, around
    e_m = _integer(src, "ellipsoid.mesh[1]", mesh[1], 2, _MAX_CELLS)  # eM, pole to pole
    return EllipsoidStyle(convention, (e_n, e_m))


def _models(src: str, v: Mapping[str, Any]) -> dict[str, Any]:
    """The deployment, the damper and its initial rate, the wheel, the orbit and the torque,
    checked alone and together."""
    for name, kind in (("deployment", Deployment), ("damper", Damper), ("wheel", Wheel),
                       ("orbit", GravityGradient), ("torque", ConstantTorque)):
        if v.get(name) is not None and not isinstance(v[name], kind):
            raise SceneError(src, name, f"must be a {kind.__name__}, got {v[name]!r}")
    sigma0 = v["sigma0"]
    if sigma0 is not None:
        if v["damper"] is None:
            raise SceneError(src, "damper.sigma", "needs a [damper]")
        sigma0 = _vector(src, "damper.sigma", sigma0, 3)
    if v["deployment"] is not None and v["damper"] is not None:
        raise SceneError(src, "damper", "cannot be combined with a [deployment]")
    lists = {key: scene_parts(src, key, v.get(key, ())) for key in LISTS}
    for key, aliases in (("parts", ("damper", "wheel")), ("torques", ("orbit", "torque"))):
        seen = [v[a].model for a in aliases if v.get(a) is not None]
        for i, part in enumerate(lists[key]):
            if part.model in seen and _core.model_info(part.model).unique:
                raise SceneError(src, f"{key}[{i}].kind", f"is a second {part.model!r}: a "
                                 "system holds at most one")
            seen.append(part.model)
    orbital = [name for name in ("wheel", "orbit", "torque") if v.get(name) is not None]
    # a deployment carries parts whose mass moves in it (its `mass` then given), no others
    orbital += [f"{key}[{i}]" for key in LISTS for i, part in enumerate(lists[key])
                if key == "torques" or part.model not in _MOVERS]
    if orbital and v["deployment"] is not None:
        raise SceneError(src, orbital[0], "cannot be combined with a [deployment] in a scene")
    return {"sigma0": sigma0, **lists}


_MOVERS = ("spring_mass", "hinge", "slosh")
"""The models of parts whose mass moves in the body (the energy sinks)."""


def _table(source: str, key: str, value: Any, kind: type) -> Mapping[str, Any]:
    """A scene's sub-table (`draw`, `ellipsoid`) as a mapping of its keys: from a file, from
    its dataclass, or from a mapping given in Python (``scene.replace(draw={...})``)."""
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


# -- the body and what is drawn of it -----------------------------------------------------


def _warn_inertia(source: str, key: str, caught: list[warnings.WarningMessage]) -> None:
    """Each `InertiaWarning` the scene's body raised when built, raised again naming the scene
    and its key: moments no mass distribution has, or a nearly symmetric top, warn in a scene
    as they do in Python (the body is built with warnings caught, so that nothing else it says
    reaches the user twice)."""
    said = set()
    for w in caught:
        if issubclass(w.category, InertiaWarning) and str(w.message) not in said:
            said.add(str(w.message))
            warnings.warn(f"{source}: `{key}`: {w.message}", InertiaWarning, stacklevel=4)


def scene_body(given: System | None, body_spec: Mapping[str, Any] | None,
               inertia: tuple[float, ...]) -> Body:
    """The body a scene names: the given system's (a deployment's at ``t = 0``), the one
    `body_spec` names, or the body of principal moments `inertia`."""
    if given is not None:
        body = given.body
        if isinstance(body, Body):
            return body
        return Body._restored(given.tensor_at(0.0), None, np.zeros(3))
    if body_spec is None:
        return Body(inertia)
    return build_body(body_spec)


def uniform_box(inertia: tuple[float, ...]) -> tuple[float, float, float] | None:
    """Edges of the uniform unit-mass box with these principal moments, if there is one
    (``a² = 6 (Iy + Iz − Ix)``, etc.)."""
    ix, iy, iz = inertia
    squares = (6 * (iy + iz - ix), 6 * (ix + iz - iy), 6 * (ix + iy - iz))
    if min(squares) <= 0:
        return None
    a, b, c = (float(np.sqrt(x)) for x in squares)
    return a, b, c


def drawn_label(body: Body, spec: Mapping[str, Any] | None = None) -> str:
    """What the legends call the body drawn: ``box`` for the box of a body given by its
    moments, a preset's name (``wing nut``) for a scene's preset, ``composite body (N parts)``
    for a composite drawn as its parts, ``body`` for a body drawn as its own shape (a solid,
    a mesh)."""
    if body.shape is None:
        return "box"
    if spec is not None and isinstance(spec.get("preset"), str):
        return str(spec["preset"]).replace("-", " ")
    if body.parts:
        return f"composite body ({len(body.parts)} parts)"
    return "body"


def drawn_shape(body: Body, box: tuple[float, ...] | None,
                inertia: tuple[float, ...]) -> Shape | None:
    """What is drawn for `body`: its own shape, else the box (`box`, or the uniform box of
    `inertia`) in its principal axes; None if there is none."""
    if body.shape is not None:
        return body.shape
    edges = box if box is not None else uniform_box(inertia)
    if edges is None:
        return None
    a, b, c = edges
    return box_shape(a, b, c).placed(body.principal_axes, np.zeros(3))


# -- one value ----------------------------------------------------------------------------


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


def _quaternion(source: str, key: str, value: Any) -> tuple[float, ...]:
    """An attitude: four finite numbers, not all zero (scalar first, normalised later)."""
    q = _vector(source, key, value, 4)
    if not any(q):
        raise SceneError(source, key, "must be a non-zero quaternion (Q, U, V, W)")
    return q


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


def _drawable(source: str, key: str, size: float, what: str = "") -> None:
    """Refuses a size too large to draw (see :data:`MAX_DRAWN_SIZE`)."""
    if not size <= MAX_DRAWN_SIZE:
        of = f" ({what})" if what else ""
        raise SceneError(source, key, f"gives a size{of} of {size:.3g}, more than the "
                         f"{MAX_DRAWN_SIZE:.0e} a drawing can hold; scale the scene down")


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
