"""Each part's fields as columns of a table (an xarray dataset, a netCDF file), whatever its
model: the columns follow from the core's declaration of the model's parameters, so a new
part is saved and loaded with no code of its own here.

Layout (``lead`` is ``()`` for one run, ``("run",)`` for a batch):

- ``part_kind(lead…, part)``: the model of each part of the system (``dz.MODELS``), internal
  parts first then external torques, each in the system's order; ``""`` pads a run with fewer
  parts than another.
- for each model ``K`` a system holds, one row per part of that model (dim ``part_K``, in the
  order they appear in ``part_kind``) and one column per parameter ``P``: ``part_K_P``, of
  dims ``(lead…, part_K)`` for a number or a word, ``+ (axis,)`` for a vector,
  ``+ (part_K_knot,)`` for knot times and values, ``+ (part_K_knot, axis)`` for vectors at
  knots. Padding (rows beyond a run's parts of that model, knots beyond a part's, an optional
  parameter left out) is NaN, or ``""`` for a word.

A parameter that is a function (a :class:`~dzhanibekov.CallableTorque`'s) has no column: a file
cannot hold code (:func:`unstorable`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from . import SPECS, Part, from_fields, params_of

__all__ = ["KIND", "columns", "column_dims", "column_name", "storable_models", "unstorable",
           "parts_of"]

KIND = "part_kind"
"""The column naming each part's model, in the system's order."""

_SHAPES: Mapping[str, tuple[str, ...]] = {
    "scalar": (), "vector": ("axis",), "times": ("knot",), "values": ("knot",),
    "vectors": ("knot", "axis"), "choice": (),
}
"""The dims a parameter of each kind adds to its part's row (``knot``: the model's knots)."""


def column_name(model: str, param: str) -> str:
    """The column of parameter `param` of model `model`: ``part_<model>_<param>``."""
    return f"part_{model}_{param}"


def column_dims(model: str, kind: str) -> tuple[str, ...]:
    """The dims (after the runs') of a column of a parameter of `kind` of model `model`."""
    return (f"part_{model}",) + tuple(f"part_{model}_knot" if d == "knot" else d
                                      for d in _SHAPES[kind])


def storable_models() -> tuple[str, ...]:
    """The part models a file can hold: those whose parameters all have columns."""
    return tuple(m for m in SPECS if all(p.kind in _SHAPES for p in params_of(m)))


def unstorable(system: Any) -> list[str]:
    """What of `system` a file cannot hold (its parameters would be lost, and the file would
    load as another system): its parts of a model with a parameter that has no column (a
    function), by their type's name and model. Empty when the whole system can be saved."""
    storable = storable_models()
    return [f"{type(p).__name__} ({p.model})"
            for p in (*getattr(system, "parts", ()), *getattr(system, "torques", ()))
            if not isinstance(p, Part) or p.model not in storable]


def _word(kind: str) -> bool:
    return kind == "choice"


def columns(systems: Sequence[Any]) -> dict[str, tuple[tuple[str, ...], np.ndarray, str]]:
    """The columns of the parts of `systems` (one row of each per system): name ->
    (dims after the runs', values with a leading run axis, what it holds). Empty when no
    system has a part."""
    rows = [[*s.parts, *s.torques] for s in systems]
    width = max((len(r) for r in rows), default=0)
    if width == 0:
        return {}
    kind = np.full((len(rows), width), "", dtype=object)
    by_model: dict[str, list[list[Part]]] = {}
    for i, row in enumerate(rows):
        for j, part in enumerate(row):
            kind[i, j] = part.model
            by_model.setdefault(part.model, [[] for _ in rows])[i].append(part)
    out: dict[str, tuple[tuple[str, ...], np.ndarray, str]] = {KIND: (("part",), kind.astype(str),
                  "model of each part in the system's order (dz.MODELS; '': padding)")}
    for model, per_run in by_model.items():
        out |= _model_columns(model, per_run)
    return out


def _model_columns(model: str, per_run: list[list[Part]]
                   ) -> dict[str, tuple[tuple[str, ...], np.ndarray, str]]:
    params = params_of(model)
    fields = [[p.fields() for p in row] for row in per_run]
    count = max(len(row) for row in fields)
    knots = max((len(f[p.name]) for row in fields for f in row for p in params
                 if p.kind in ("times", "values", "vectors") and f[p.name] is not None),
                default=0)
    out: dict[str, tuple[tuple[str, ...], np.ndarray, str]] = {}
    for p in params:
        if p.kind not in _SHAPES:  # a function: no column (see `unstorable`)
            continue
        extra = tuple(knots if d == "knot" else 3 for d in _SHAPES[p.kind])
        a = np.full((len(fields), count) + extra, "" if _word(p.kind) else np.nan,
                    dtype=object if _word(p.kind) else np.float64)
        for i, row in enumerate(fields):
            for j, f in enumerate(row):
                value = f[p.name]
                if value is None:
                    continue
                if p.kind in ("times", "values", "vectors"):
                    a[i, j, :len(value)] = value
                else:
                    a[i, j] = value
        out[column_name(model, p.name)] = (
            column_dims(model, p.kind), a.astype(str) if _word(p.kind) else a,
            f"{model}: {p.about}" + (" (NaN-padded)" if not _word(p.kind) else ""))
    return out


def parts_of(values: Mapping[str, np.ndarray], runs: int | None
             ) -> list[tuple[list[Part], list[Part]]] | str:
    """Each run's (internal parts, external torques) from the columns `values` (a single
    run's without its run axis when `runs` is None), or what is wrong with them. Checks the
    layout (rows first then padding, knots first then NaN, every column of each model named
    and none of another); the parts' classes and the core check the values."""
    n = 1 if runs is None else runs

    def rows(name: str) -> np.ndarray:
        a: np.ndarray = values[name]
        return a[None] if runs is None else a

    present = [name for name in values if name.startswith("part_")]
    if KIND not in values:
        return f"`{present[0]}` needs `{KIND}`" if present else [([], []) for _ in range(n)]
    kind = rows(KIND).reshape(n, -1)
    named = kind != ""
    if not (named == (np.arange(kind.shape[1]) < named.sum(axis=1)[:, None])).all():
        return f"`{KIND}` must hold each run's parts first, then ''"
    storable = storable_models()
    models = [m for m in storable if (kind == m).any()]
    unknown = sorted(set(kind[named].tolist()) - set(storable))
    if unknown:
        return (f"`{KIND}` must name models a file can hold ({', '.join(storable)}), "
                f"got {unknown[0]!r}")
    expected = {column_name(m, p.name) for m in models for p in params_of(m)}
    for name in sorted(set(present) - expected - {KIND}):
        return f"`{name}` is there, but no part of its model is"
    for name in sorted(expected - set(present)):
        return f"`{name}` is missing"
    out: list[tuple[list[Part], list[Part]]] = [([], []) for _ in range(n)]
    counts = {m: (kind == m).sum(axis=1) for m in models}
    cells: list[list[dict[str, Any]]] = [[] for _ in range(n)]
    for m in models:
        params = params_of(m)
        cols = {p.name: rows(column_name(m, p.name)) for p in params}
        length = next(iter(cols.values())).shape[1]
        if counts[m].max() > length:
            return (f"`{KIND}` names {int(counts[m].max())} parts {m!r} in a run, but "
                    f"`part_{m}` holds {length}")
        times = next((p.name for p in params if p.kind == "times"), None)
        for i in range(n):
            fields_i: list[dict[str, Any]] = []
            for j in range(length):
                real = j < counts[m][i]
                fields = {}
                for p in params:
                    value, problem = _cell(p, cols[p.name][i, j], real,
                                           None if times is None else cols[times][i, j])
                    if problem:
                        return f"`{column_name(m, p.name)}` {problem}"
                    fields[p.name] = value
                if real:
                    fields_i.append(fields)
            cells[i].append({"model": m, "rows": fields_i})
    for i in range(n):
        taken = {c["model"]: iter(c["rows"]) for c in cells[i]}
        for m in kind[i][named[i]]:
            part = from_fields(str(m), next(taken[str(m)]))
            out[i][1 if part.external else 0].append(part)
    return out


def _cell(p: Any, a: Any, real: bool, times: Any) -> tuple[Any, str | None]:
    """The value of parameter `p` in one part's row (a real part's, or padding), or what is
    wrong with it."""
    if _word(p.kind):
        word = str(a)
        if not real:
            return None, None if word == "" else "must be '' beyond a run's parts"
        if word == "" and p.optional:
            return None, None
        if word not in p.choices:
            return None, f"must be one of {', '.join(map(repr, p.choices))}, got {word!r}"
        return word, None
    a = np.asarray(a, dtype=np.float64)
    nan = np.isnan(a)
    if not real:
        return None, None if nan.all() else "must be NaN beyond a run's parts"
    if p.kind in ("scalar", "vector"):
        if nan.all() and p.optional:
            return None, None
        if nan.any() or not np.isfinite(a).all():
            return None, "must be finite for each part (NaN: an optional value left out)"
        return (float(a) if p.kind == "scalar" else tuple(a.tolist())), None
    rows = a.reshape(a.shape[0], int(np.prod(a.shape[1:])))
    # a table's rows are its knots' (its model's times), or its own (a table without times)
    given = ~np.isnan(rows).all(axis=1) if times is None else \
        ~np.isnan(np.asarray(times, dtype=np.float64))
    k = int(given.sum())
    if k == 0 and p.optional:
        return None, None
    if not given[:k].all():
        return None, "must hold a part's knots first, then NaN"
    if not np.isfinite(rows[:k]).all() or not np.isnan(rows[k:]).all():
        return None, f"must be finite at a part's {k} knots and NaN beyond them"
    return a[:k], None


# the columns of every model are distinct (a model named like another's prefix cannot make
# two parameters share a column)
_ALL = [column_name(m, p.name) for m in SPECS for p in params_of(m)]
assert len(set(_ALL)) == len(_ALL), "two models' parameters share a column name"
