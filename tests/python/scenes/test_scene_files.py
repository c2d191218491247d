"""Scene files that are not scenes: devices, FIFOs, huge or deeply nested files, sizes a
drawing cannot hold and counts of drawn things past their documented maxima, all refused
when the scene loads with a `SceneError` naming the file (and the key). And every exception
of the package survives pickling (a `multiprocessing.Pool` worker raising it)."""

from __future__ import annotations

import inspect
import multiprocessing
import os
import pickle
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest
import tomli_w

import dzhanibekov as dz
from dzhanibekov.scenes import scene as scene_module
from dzhanibekov.scenes.scene import (MAX_ANIMATION_FRAMES, MAX_DRAWN_SIZE, MAX_PHASES, Draw,
                               MAX_SCENE_BYTES, SceneError)


def child(code: str, timeout: float = 60.0) -> subprocess.CompletedProcess[str]:
    """`code` in a fresh interpreter under a 2 GB address-space limit (a reader without a
    size limit would be stopped by it instead of growing for ever)."""
    limit = textwrap.dedent("""
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
    """)
    return subprocess.run([sys.executable, "-c", limit + textwrap.dedent(code)],
                          capture_output=True, text=True, timeout=timeout)


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="needs /dev/zero")
def test_a_device_is_refused_not_read():
    done = child("""
        import dzhanibekov as dz
        try:
            dz.load_scene("/dev/zero")
        except dz.SceneError as exc:
            print(exc)
    """)
    assert done.returncode == 0, done.stderr
    assert "/dev/zero: cannot be read (a device, not a regular file)" in done.stdout


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path):
    fifo = tmp_path / "scene.toml"
    os.mkfifo(fifo)
    done = child(f"""
        import dzhanibekov as dz
        try:
            dz.load_scene({str(fifo)!r})
        except dz.SceneError as exc:
            print(exc)
    """, timeout=30)
    assert "not a regular file" in done.stdout, done.stderr


def test_a_file_past_the_size_limit_is_refused(tmp_path):
    path = tmp_path / "huge.toml"
    text = dz.SCENES["fig3a"].to_toml()
    padding = "# " + "x" * 78 + "\n"
    path.write_text(text + padding * (MAX_SCENE_BYTES // len(padding) + 1))
    with pytest.raises(SceneError, match=rf"{path}: cannot be read \(larger than "
                                         rf"{MAX_SCENE_BYTES} bytes"):
        dz.load_scene(path)
    path.write_text(text + padding * ((MAX_SCENE_BYTES - len(text)) // len(padding)))
    assert path.stat().st_size <= MAX_SCENE_BYTES
    assert dz.load_scene(path).omega0 == dz.SCENES["fig3a"].omega0


@pytest.mark.parametrize("nested", ["x = " + "[" * 1200 + "]" * 1200,
                                    "x = " + "{a = " * 1200 + "1" + "}" * 1200])
def test_deep_nesting_is_a_scene_error_naming_the_file(tmp_path, nested):
    path = tmp_path / "deep.toml"
    path.write_text(nested + "\n")
    with pytest.raises(SceneError, match=rf"{path}: is not a scene: its arrays or tables "
                                         "nest too deeply"):
        dz.load_scene(path)


@pytest.mark.parametrize("key, value", [("signal_point", [0.0, 0.0, 1e308]),
                                        ("box", [20.0, 1e200, 15.0])])
def test_sizes_too_large_to_draw_are_refused_at_load(tmp_path, key, value):
    """Valid numbers that fail later, when drawn (with a message about `points`)."""
    tables = dz.SCENES["example"].to_dict()
    tables["body"][key] = value
    path = tmp_path / "big.toml"
    path.write_text(tomli_w.dumps(tables))
    with pytest.raises(SceneError, match=rf"{path}: `body.{key}` gives a size of "
                                         rf"[\d.e+]+, more than the {re.escape(f'{MAX_DRAWN_SIZE:.0e}')}"):
        dz.load_scene(path)


def test_an_ellipsoid_too_large_to_draw_is_refused_at_load():
    scene = dz.SCENES["example"]
    with pytest.raises(SceneError, match=r"`body.inertia` gives a size \(the gyration "
                                         r"ellipsoid's largest semi-axis\) of 1.41e\+150"):
        scene.replace(inertia=(1e300, 2e300, 1.5e300), box=(1.0, 1.0, 1.0))


def test_animation_frames_past_the_maximum_are_refused_naming_the_key():
    scene = dz.SCENES["example"]
    assert scene.draw.animation
    scene.replace(frames=MAX_ANIMATION_FRAMES)  # the maximum itself is allowed
    with pytest.raises(SceneError, match=rf"`run.frames` must be at most "
                                         rf"{MAX_ANIMATION_FRAMES} for an animation"):
        scene.replace(frames=MAX_ANIMATION_FRAMES + 1)
    # without an animation, frames are bounded by memory only
    still = scene.replace(frames=MAX_ANIMATION_FRAMES + 1,
                          draw=Draw(figures=("omega",)))
    assert still.frames == MAX_ANIMATION_FRAMES + 1


def test_phase_panels_past_the_maximum_are_refused_naming_the_key():
    scene = dz.SCENES["example"]
    times = tuple(float(t) for t in range(MAX_PHASES))
    scene.replace(draw=Draw(figures=("phases",), box=True, phases=times))
    with pytest.raises(SceneError, match=rf"`draw.phases` must list at most {MAX_PHASES} "
                                         rf"instants \(one 3-D panel each\), got "
                                         rf"{MAX_PHASES + 1}"):
        scene.replace(draw=Draw(figures=("phases",), box=True,
                                   phases=times + (float(MAX_PHASES),)))


def package_exceptions() -> list[type[BaseException]]:
    """Every exception class defined in the package's modules."""
    import dzhanibekov.cli
    import dzhanibekov.render  # noqa: F401  (their exceptions too)
    found: dict[str, type[BaseException]] = {}
    for name, module in list(sys.modules.items()):
        if name == "dzhanibekov" or name.startswith("dzhanibekov."):
            for _, obj in inspect.getmembers(module, inspect.isclass):
                if issubclass(obj, BaseException) and obj.__module__.startswith("dzhanibekov"):
                    found[f"{obj.__module__}.{obj.__qualname__}"] = obj
    return list(found.values())


def an_instance(cls: type[BaseException]) -> BaseException:
    try:
        signature = inspect.signature(cls)
    except ValueError:  # a built-in __init__ (warnings): one message
        return cls("a message")
    params = [p for p in signature.parameters.values()
              if p.default is inspect.Parameter.empty
              and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    return cls(*(f"arg{i}" for i in range(len(params)))) if params else cls("a message")


def test_every_package_exception_pickles():
    classes = package_exceptions()
    assert SceneError in classes
    for cls in classes:
        exc = an_instance(cls)
        back = pickle.loads(pickle.dumps(exc))
        assert type(back) is cls and str(back) == str(exc), cls
        assert vars(back).keys() == vars(exc).keys(), cls
        for key, value in vars(exc).items():  # arrays (a study's partial outcomes) by value
            if isinstance(value, np.ndarray):
                assert np.array_equal(vars(back)[key], value) and (
                    vars(back)[key].dtype == value.dtype), (cls, key)
            else:
                assert vars(back)[key] == value, (cls, key)


def raise_scene_error(_: int) -> None:
    raise SceneError("mine.toml", "run.frames", "must be at least 2, got 1")


def test_a_pool_worker_raising_a_scene_error_returns_it():
    """Unpicklable, it hung the pool for ever; the result arrives within the timeout."""
    context = multiprocessing.get_context("spawn")
    with context.Pool(1) as pool:
        result = pool.map_async(raise_scene_error, [0])
        with pytest.raises(SceneError, match=r"mine.toml: `run.frames` must be at least 2") \
                as info:
            result.get(timeout=60)
    assert info.value.key == "run.frames" and info.value.source == "mine.toml"


def test_the_bounds_are_documented_in_the_module():
    for name in ("MAX_SCENE_BYTES", "MAX_ANIMATION_FRAMES", "MAX_PHASES", "MAX_DRAWN_SIZE"):
        assert name in scene_module.__all__


@pytest.mark.parametrize("draw", [{}, {"box": True, "figures": ["path"]}, Draw(path=True)])
def test_replace_takes_a_draw_table(draw):
    """`Scene.replace(draw={})` failed with a TypeError inside `dataclasses.asdict`."""
    scene = dz.SCENES["fig3a"].replace(draw=draw)
    want = draw if isinstance(draw, Draw) else Draw(**{k: tuple(v) if isinstance(v, list)
                                                       else v for k, v in draw.items()})
    assert scene.draw == want


@pytest.mark.parametrize("draw, key", [({"boxx": True}, "draw.boxx"), (3, "draw"),
                                       ({"figures": ["nope"]}, "draw.figures")])
def test_replace_refuses_a_draw_that_is_no_table_of_draw_keys(draw, key):
    with pytest.raises(SceneError, match=rf"`{key}`"):
        dz.SCENES["fig3a"].replace(draw=draw)


@pytest.mark.parametrize("title, why", [
    ("$" + "{" * 60 + "x" + "}" * 60 + "$", "nests its mathtext .* 60 levels deep"),
    ("$" + r"\frac{" * 40 + "x" + "}{2}" * 40 + "$", "nests its mathtext .* 40 levels deep"),
    (r"$\notacommand{x}$", "is mathtext .* that matplotlib cannot draw: .*notacommand"),
])
def test_a_title_matplotlib_cannot_draw_is_refused_when_the_scene_loads(tmp_path, title, why):
    """A title of deeply nested mathtext loaded, then `dzhanibekov run` died in matplotlib's
    parser with a ~3000-line RecursionError traceback."""
    table = dz.SCENES["fig3a"].to_dict() | {"title": title}
    path = tmp_path / "deep.toml"
    path.write_text(tomli_w.dumps(table))
    with pytest.raises(SceneError, match=rf"deep\.toml: `title` {why}"):
        dz.load_scene(path)


def test_a_title_with_mathtext_or_dollars_loads_and_draws():
    for title in (r"$\omega_0 = (0.01, 0.01, 1)$: $x^{2^{y}}$", "costs $5, or $6",
                  "a lone $ sign"):
        scene = dz.SCENES["fig3a"].replace(title=title, t_end=10.0, frames=11)
        dz.plotting.path_figure(scene).canvas.draw()
