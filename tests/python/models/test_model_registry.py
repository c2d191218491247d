"""The registry of models (`dz.MODELS`) is the core's declaration of every model, and the
Python side follows it: each part class makes the core's model of its kind, the methods each
model lists run it and the others refuse it, and what a system keeps is what its models'
declarations say (issue 29: a part declares itself once)."""

from __future__ import annotations

import pickle

import pytest

import dzhanibekov as dz
from dzhanibekov.parts import SPECS, example

BODY = dz.Body((1.0, 2.0, 3.0))

PART_MODELS = [n for n, m in dz.MODELS.items() if not m.law]


def system_of(name: str) -> dz.System:
    """A system made of the model `name` alone (a part from its class's example)."""
    if name == "free":
        return dz.System(BODY)
    if name == "deployment":
        return dz.System(dz.Deployment([0.0, 1.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)]))
    part = example(name)
    return dz.System(BODY, **{"torques" if part.external else "parts": [part]})


def test_every_model_of_the_core_has_a_python_class_that_makes_it():
    assert list(dz.MODELS)[:2] == ["free", "deployment"]
    assert [n for n, m in dz.MODELS.items() if m.law] == ["free", "deployment"]
    assert sorted(SPECS) == sorted(PART_MODELS)
    for name in dz.MODELS:
        assert system_of(name).kinds == (name,), name
    for name in PART_MODELS:
        info = dz.MODELS[name]
        part = example(name)
        assert part.model == name and part.external == info.external
        # a part's state is what its runs report beside the body's (none: nothing)
        width = sum(w for _, w, _, _ in info.state)
        assert system_of(name)._core.parts == ([(name, width)] if width else [])


@pytest.mark.parametrize("name", PART_MODELS)
def test_a_part_class_follows_the_core_declaration_of_its_model(name):
    cls = SPECS[name]
    declared = [(p[0], p[1], p[2]) for p in dz.MODELS[name].params]
    # the fields a part gives files and scenes are its model's parameters, in the core's order
    part = example(name)
    assert list(part.fields()) == [n for n, _, _ in declared]
    # a required parameter left out is refused by name
    required = [n for n, _, optional in declared if not optional]
    fields = {k: v for k, v in part.fields().items() if k != required[0]}
    with pytest.raises((TypeError, ValueError), match=required[0]):
        cls.from_fields(name, fields)
    # the fields make the same part again: ==, hash, repr and pickling follow from them
    again = cls.from_fields(name, part.fields())
    assert again == part and hash(again) == hash(part) and repr(again) == repr(part)
    assert pickle.loads(pickle.dumps(part)) == part
    assert part != example(PART_MODELS[(PART_MODELS.index(name) + 1) % len(PART_MODELS)])


@pytest.mark.parametrize("name", list(dz.MODELS))
def test_the_methods_a_model_lists_run_it_and_the_others_refuse_it(name):
    system = system_of(name)
    runs = set(dz.MODELS[name].methods)
    assert runs == {m for m, info in dz.METHODS.items() if name in info.models}
    assert "rk4" in runs and "dop853" in runs  # the general methods run every model
    start = (0.3, 0.2, 1.0), (1.0, 0.0, 0.0, 0.0)
    for method in dz.METHODS:
        if method in runs:
            continue
        with pytest.raises(ValueError, match=method):
            dz.simulate(system, *start, t_end=0.1, frames=2, method=method)


@pytest.mark.parametrize("name", list(dz.MODELS))
def test_a_system_keeps_what_its_models_declare(name):
    system = system_of(name)
    info = dz.MODELS[name]
    assert set(system.conserved) <= set(info.keeps) | set(info.defines) | {"energy_balance"}
    # a part that dissipates makes the energy plus the dissipated work the kept quantity
    assert ("energy_balance" in system.conserved) == (info.energy == "dissipates")
    # what does work keeps no energy; what neither gives nor takes does not stop a free
    # body keeping it
    if info.energy == "does work":
        assert "energy" not in system.conserved
