"""The one declaration a part's Python class follows: the core's.

Each part class names its kind (a name of the core's registry, ``dz.MODELS``); its fields are
the kind's parameters as the core declares them (name, kind of value, whether optional, what
words a choice allows), read once when the class is made. From them follow, for every part:
``__init__``'s coercion (kinds and shapes here, ranges by the core, which builds the part at
once), ``==``, ``hash``, ``repr``, pickling, the core's part, the fields files and scenes store
(:meth:`Part.fields`, :meth:`Part.from_fields`). A class states only what the core cannot: its
defaults, its docstring, the attributes' types for mypy, and helpers for plots.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from .. import _core
from .._args import as_array, as_float
from ._knots import knot_times

__all__ = ["Part", "Param", "choice", "params_of"]

REGISTRY: dict[str, type[Part]] = {}
"""The class of each part model, by the model's name: filled as the classes are made (a
class makes the models of its ``examples``, or its ``kind``)."""


class Param:
    """A parameter of a part, as the core declares it: `name`, `kind` (``scalar``,
    ``vector``, ``times``, ``values``, ``vectors``, ``choice``, ``function``), whether it is
    `optional`, one line `about` it and, for a choice, the words it allows."""

    __slots__ = ("name", "kind", "optional", "about", "choices")

    def __init__(self, name: str, kind: str, optional: bool, about: str,
                 choices: tuple[str, ...]) -> None:
        self.name, self.kind, self.optional, self.about = name, kind, optional, about
        self.choices = choices

    def __repr__(self) -> str:
        return f"Param({self.name!r}, {self.kind!r}{', optional' if self.optional else ''})"


def params_of(kind: str) -> tuple[Param, ...]:
    """The parameters of the core's model `kind`."""
    return tuple(Param(name, k, optional, about, tuple(choices))
                 for name, k, optional, about, choices in _core.model_info(kind).params)


def choice(name: str, value: Any, allowed: tuple[str, ...]) -> str:
    """`value` if it is one of the words `allowed`."""
    options = " or ".join(repr(a) for a in allowed)
    if not isinstance(value, str):
        raise TypeError(f"`{name}` must be {options}, got {type(value).__name__}")
    if value not in allowed:
        raise ValueError(f"`{name}` must be {options}, got {value!r}")
    return value


def _frozen(a: np.ndarray) -> np.ndarray:
    out = np.array(a, dtype=np.float64)
    out.flags.writeable = False
    return out


def coerce(param: Param, value: Any, knots: int | None) -> Any:
    """`value` as parameter `param` holds it: a float, a tuple of three floats, a read-only
    float64 array ((K,) or (K, 3), `knots` long if the part's times are known), a word, a
    function. Kinds and shapes only: the core checks the values."""
    name = param.name
    if param.kind == "scalar":
        if type(value) is float and math.isfinite(value):  # (already one: the fast way)
            return value
        return as_float(name, value)
    if param.kind == "vector":
        if type(value) is tuple and len(value) == 3 and all(
                type(x) is float and math.isfinite(x) for x in value):
            return value
        v = as_array(name, value, "(3,)", last=3, ndim=(1,))
        return (float(v[0]), float(v[1]), float(v[2]))
    if param.kind == "times":
        return _frozen(knot_times(value, name))
    if param.kind in ("values", "vectors"):
        shape, width = (("(K,)", None), ("(K, 3)", 3))[param.kind == "vectors"]
        try:
            n = len(value)
        except TypeError:
            raise TypeError(f"`{name}` must be an array of shape {shape}, got "
                            f"{type(value).__name__}") from None
        if knots is not None and n != knots:
            # before any copy: a broadcast view of 2**31 rows would be copied whole first
            raise ValueError(f"`{name}` must give one {'vector' if width else 'value'} per knot "
                             f"time of `times` ({knots}), got {n}")
        return _frozen(as_array(name, value, shape, last=width or n, ndim=(2,) if width else (1,)))
    if param.kind == "choice":
        return choice(name, value, param.choices)
    if param.kind == "function":
        if not callable(value):
            raise TypeError(f"`{name}` must be callable, got {type(value).__name__}")
        return value
    raise TypeError(f"`{name}`: the core declares a kind of parameter this package does not "
                    f"know ({param.kind!r}); update the package")


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return (isinstance(a, np.ndarray) and isinstance(b, np.ndarray)
                and a.shape == b.shape and bool(np.array_equal(a, b)))
    return bool(a == b)


def _hashable(v: Any) -> Any:
    return v.tobytes() if isinstance(v, np.ndarray) else v


def _shown(v: Any) -> str:
    if isinstance(v, np.ndarray):
        if v.ndim == 1:
            return f"[{float(v[0])!r} … {float(v[-1])!r}]" if len(v) > 2 else repr(v.tolist())
        return f"<{len(v)} vectors>"
    if callable(v) and not isinstance(v, (str, tuple)):
        return getattr(v, "__qualname__", None) or repr(v)
    return repr(v)


class Part:
    """A part of a system (see the module doc): a frozen value whose fields are its kind's
    parameters. Subclasses set `kind` and, if any, `defaults`."""

    kind: ClassVar[str]
    """The registry name of the part's model (``dz.MODELS[kind]``)."""
    defaults: ClassVar[Mapping[str, Any]] = {}
    """Defaults of parameters the core requires (a torque's frame: ``"body"``)."""
    params: ClassVar[tuple[Param, ...]] = ()
    """The kind's parameters, in the core's order."""
    external: ClassVar[bool] = False
    """Whether the part is an external torque (a system's ``torques``)."""
    _parameters: ClassVar[inspect.Signature]
    lists: ClassVar[tuple[str, ...]] = ()
    """Where a System takes the class's parts: ``("parts",)`` for an internal part,
    ``("torques",)`` for an external torque (the default from the core's declaration), both
    for a part on board that also acts from outside (the closed loop's: magnetorquers)."""
    declares_types: ClassVar[bool] = True
    """Whether the class annotates each parameter (checked when it is made); the closed
    loop's parts, whose flat parameters come from objects (a field, sensors), do not."""
    examples: ClassVar[Mapping[str, Mapping[str, Any]]] = {}
    """Fields of a small, valid part of each model the class makes, by model: what the tests
    run through every result path (files, figures, studies) and the docs show."""
    _core: _core.Part

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "kind" not in cls.__dict__:
            return
        cls.params = params_of(cls.kind)
        cls.external = _core.model_info(cls.kind).external
        if not cls.lists:
            cls.lists = ("torques",) if cls.external else ("parts",)
        # the class states its attributes' types for mypy: they must be the core's parameters
        hints = {k for c in cls.__mro__ for k in getattr(c, "__annotations__", {})}
        missing = [p.name for p in cls.params if p.name not in hints]
        if missing and cls.declares_types:
            raise TypeError(f"{cls.__name__} does not declare the parameters {missing} of the "
                            f"core's model {cls.kind!r}")
        for model in cls.examples or (cls.kind,):
            if model in REGISTRY and REGISTRY[model] is not cls:
                raise TypeError(f"{cls.__name__} makes the model {model!r}, which "
                                f"{REGISTRY[model].__name__} already makes")
            REGISTRY[model] = cls
        for model, fields in cls.examples.items():
            names = {p.name for p in params_of(model)}
            if set(fields) - names:
                raise TypeError(f"{cls.__name__}.examples[{model!r}] names "
                                f"{sorted(set(fields) - names)}, not parameters of the model")
        cls._parameters = cls._signature()
        if "__init__" not in cls.__dict__:  # (a class with its own __init__ keeps its own)
            cls.__signature__ = cls._parameters  # type: ignore[attr-defined]

    @classmethod
    def _signature(cls) -> inspect.Signature:
        def default(p: Param) -> Any:
            if p.name in cls.defaults:
                return cls.defaults[p.name]
            return None if p.optional else inspect.Parameter.empty

        return inspect.Signature([
            inspect.Parameter(p.name, inspect.Parameter.POSITIONAL_OR_KEYWORD,
                              default=default(p)) for p in cls.params])

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        # as the signature binds them (inspect's bind took a third of a part's making)
        cls, params = type(self), type(self).params
        if len(args) > len(params):
            raise TypeError(f"{cls.__name__}() takes {len(params)} arguments, got {len(args)}")
        values = {p.name: a for p, a in zip(params, args)}
        for name, value in kwargs.items():
            if name in values:
                raise TypeError(f"{cls.__name__}() got multiple values for argument {name!r}")
            if not any(p.name == name for p in params):
                raise TypeError(f"{cls.__name__}() got an unexpected keyword argument {name!r}")
            values[name] = value
        for p in params:
            if p.name not in values:
                if p.name in cls.defaults:
                    values[p.name] = cls.defaults[p.name]
                elif not p.optional:
                    raise TypeError(f"{cls.__name__}() missing a required argument: "
                                    f"{p.name!r}")
        self._store(self.kind, values)

    def _store(self, kind: str, values: Mapping[str, Any]) -> None:
        """Coerces `values` (the parameters of the core's `kind`), builds the core's part and
        keeps both."""
        params = self.params if kind == self.kind else params_of(kind)
        times = next((p.name for p in params if p.kind == "times"), None)
        knots = None
        out: dict[str, Any] = {}
        for p in params:
            value = values.get(p.name)
            if value is None:
                if not p.optional:
                    raise TypeError(f"{type(self).__name__}(): `{p.name}` must be given")
                out[p.name] = None
                continue
            out[p.name] = self._coerce(p, value, knots if p.name != times else None)
            if p.name == times:
                knots = len(out[p.name])
        core = _core.Part(kind, {k: v for k, v in out.items() if v is not None})
        for name, value in self._public(kind, out).items():
            object.__setattr__(self, name, value)
        object.__setattr__(self, "_core", core)

    def _coerce(self, param: Param, value: Any, knots: int | None) -> Any:
        """`value` as `param` holds it (:func:`coerce`; a class may take a parameter its
        own way, as the closed loop's parts take their sensors' seed)."""
        return coerce(param, value, knots)

    def _public(self, kind: str, values: dict[str, Any]) -> dict[str, Any]:
        """The attributes a part shows of the core's parameters `values` (the same, unless a
        class shows one value for several kinds' parameters)."""
        return values

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"a {type(self).__name__} is immutable")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"a {type(self).__name__} is immutable")

    # -- the declaration's consequences --------------------------------------------------

    @property
    def model(self) -> str:
        """The registry name of the core's model this part makes (its ``kind``, or, for a
        class that makes several, the one of its parameters)."""
        return str(self._core.kind)

    def fields(self) -> dict[str, Any]:
        """The core's parameters of this part by name (None for an optional one left out):
        what files and scenes store, and :meth:`from_fields` reads back."""
        return {p.name: getattr(self, p.name) for p in self.params}

    @classmethod
    def from_fields(cls, kind: str, fields: Mapping[str, Any]) -> Part:
        """The part of the core's model `kind` from its parameters `fields` (see
        :meth:`fields`)."""
        if kind != cls.kind:
            raise ValueError(f"a {cls.__name__} makes a {cls.kind!r}, not a {kind!r}")
        cls._require(kind, fields)
        return cls(**{k: v for k, v in fields.items() if v is not None})

    @classmethod
    def _require(cls, kind: str, fields: Mapping[str, Any]) -> None:
        """Refuses `fields` that leave out a required parameter of the model `kind` or name
        one it does not have."""
        params = cls.params if kind == getattr(cls, "kind", None) else params_of(kind)
        for p in params:
            if not p.optional and p.name not in cls.defaults and fields.get(p.name) is None:
                raise TypeError(f"a {kind!r} needs `{p.name}` ({p.about})")
        unknown = set(fields) - {p.name for p in params}
        if unknown:
            raise TypeError(f"a {kind!r} has no parameter {', '.join(sorted(map(repr, unknown)))}"
                            f" (it has {', '.join(p.name for p in params)})")

    def _key(self) -> tuple[Any, ...]:
        return tuple(getattr(self, p.name) for p in type(self).params)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Part) or type(other) is not type(self):
            return False
        mine, theirs = self._key(), other._key()
        return len(mine) == len(theirs) and all(_same(a, b) for a, b in zip(mine, theirs))

    def __hash__(self) -> int:
        return hash((type(self).__name__, *map(_hashable, self._key())))

    def __repr__(self) -> str:
        shown = ", ".join(f"{p.name}={_shown(getattr(self, p.name))}" for p in type(self).params
                          if getattr(self, p.name) is not None)
        return f"{type(self).__name__}({shown})"

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (type(self), self.model, self.fields()))


def _rebuild(cls: type[Part], kind: str, fields: dict[str, Any]) -> Part:
    return cls.from_fields(kind, fields)
