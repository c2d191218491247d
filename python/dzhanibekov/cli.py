"""The command line ``dzhanibekov`` (also ``python -m dzhanibekov``).

- ``dzhanibekov paper --out DIR``: every figure of the paper and its animation, and the
  stable counter-examples; prints each run's flip times and drift.
- ``dzhanibekov run SCENE.toml [--out DIR]``: what one scene draws (a file or a shipped name),
  into DIR (default: a folder named after the scene).
- ``dzhanibekov scenes``: the shipped scenes; ``--show NAME`` prints one, to start your own.
- ``dzhanibekov map --out DIR``: stability maps (flip period and tilt over a grid of starts,
  with the separatrix) and their sweeps' numbers.
- ``dzhanibekov view SCENE [--out FILE.html]``: the interactive viewer, one self-contained
  HTML file (the ``viewer`` extra; default: SCENE-NAME.html).
- ``dzhanibekov --version``.

Output is all or nothing: files are drawn in a temporary folder inside DIR and moved in
when all are done; any error (a bad scene, a folder that cannot be written, a full disk)
is one line on stderr with exit code 2, and DIR is left as it was.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import textwrap
import time
import warnings
from collections.abc import Callable, Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ._core import __version__
from ._progress import progress_default
from .methods import is_adaptive
from .render import PAPER_RENDER, CommittedInterrupt
from .scenes.plan import SceneResult
from .scenes.scene import SCENES, Scene, SceneError, load_scene
from .simulate import METHODS

__all__ = ["main"]


_MEASURES = (("energy", "E/E"), ("momentum", "|L|/|L|"), ("momentum_world", "L_world"),
             ("q_norm", "|q|"), ("jacobi", "J/J"))
"""The drift's measures in the table's order, with their short names."""

_NOT_ASKED = "-"
"""The flip count of a run that did not locate its flips."""


def _from_rest(run: Any) -> frozenset[str]:
    """The measures whose initial value is zero (a body started at rest): the drift of those
    is absolute, not relative (see :class:`Drift`). Only a run with frames tells."""
    if not hasattr(run, "energy"):
        return frozenset()
    zero = {"energy": run.energy[0] == 0.0,
            "momentum": not np.any(run.invariants()["momentum_body"][0])}
    zero["momentum_world"] = zero["momentum"]
    return frozenset(name for name, is_zero in zero.items() if is_zero)


def _invariants(drift: Any, from_rest: frozenset[str] = frozenset()) -> tuple[str, str]:
    """What a run's model keeps, with its drift (the integration's error: ``dE/E 2.1e-10``),
    and the rest, with how much the model's own law changed it (a deployment's work, a
    damper's loss, a torque's: ``ΔE/E 5.0e-01``). A measure that starts at zero is printed
    absolute (``ΔE 4.1e-03``): relative to zero it would mean nothing."""
    kept, changed = [], []
    for name, short in _MEASURES:
        value = getattr(drift, name)
        if value is None:  # no Jacobi integral
            continue
        if name in from_rest:
            short = short.split("/")[0]
        if name in drift.kept:
            kept.append(f"d{short} {value:.1e}")
        else:
            changed.append(f"Δ{short} {value:.1e}")
    return " ".join(kept), " ".join(changed)


def _table(results: Sequence[SceneResult], seconds: float) -> str:
    """The summary table: per scene its steps, flips (the count and the first four), the
    drift of what its model keeps and the change of the rest, each column as wide as its
    widest entry; a legend for what needs one. It reads only what it prints: a run of 10⁸
    flips costs four."""
    head = ("scene", "steps", "flips", "first flip times", "drift of what the model keeps",
            "changed by the model")
    rows: list[tuple[str, ...]] = [head]
    for r in results:
        run = r.trajectory if r.trajectory is not None else r.summary
        assert run is not None
        times = r.flip_times
        count = _NOT_ASKED if times is None else str(len(times))
        first = [] if times is None else [float(t) for t in np.asarray(times[:4])]
        more = times is not None and len(times) > 4
        flips = ", ".join(f"{t:.3f}" for t in first) + (", …" if more else "")
        kept, changed = _invariants(r.drift, _from_rest(run))
        rows.append((r.scene.name, str(run.n_steps), count, flips, kept, changed or "none"))
    least = (16, 9, 5, 28, 0, 0)
    widths = [max(least[k], *(len(row[k]) for row in rows)) for k in range(len(head))]
    gaps = ("", " ", " ", "  ", "  ", "  ")  # before each column
    right = (1, 2)  # the counts read from the right; the rest from the left
    lines = ["".join(gap + (cell.rjust(w) if k in right else cell.ljust(w))
                     for k, (gap, cell, w) in enumerate(zip(gaps, row, widths))).rstrip()
             for row in rows]
    lines += textwrap.wrap("d…: the largest drift over the frames of what the model keeps "
                           "(the integration's error); Δ…: the largest change of what it does "
                           "not keep, by its own law (a deployment's work, a damper's loss, a "
                           "torque); relative (L_world to |L|, |q| to 1), absolute (no /) for a "
                           "measure that starts at zero", 79)
    if any(row[2] == _NOT_ASKED for row in rows[1:]):
        lines.append(f"flips {_NOT_ASKED}: not located (the scene's [ask] flips = false)")
    lines.append(f"rendered in {seconds:.1f} s")
    return "\n".join(lines)


def _step(text: str) -> float | str:
    """`--dt`: a positive number, or "none" (the step picked for an accuracy)."""
    if text.strip().lower() == "none":
        return "none"
    return _positive(text)


def _positive(text: str) -> float:
    """A positive, finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not (value > 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text!r}")
    return value


def _whole(low: int, high: int) -> Callable[[str], int]:
    """An integer in [low, high]."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"must be from {low} to {high}, got {value}")
        return value
    return parse


def _progress(args: argparse.Namespace) -> bool | None:
    return False if args.no_progress else None


def _say(line: str) -> None:
    """A line of progress, on stderr (the results go to stdout)."""
    print(line, file=sys.stderr, flush=True)


_STEP = (re.compile(r"\ba smaller dt\b"), "a smaller --dt")
_DRIFT = (re.compile(r"\bMAX_PREDICTED_DRIFT = ([0-9eE.+-]*[0-9])"), r"the \1 allowed")
_METHOD = r"(?:\bmethod='([\w-]+)'|(?<=\(such as )'([\w-]+)')"
"""A method the API's advice names: ``method='splitting'`` or ``(such as 'splitting', …)``."""
_API_TO_CLI: dict[str, list[tuple[re.Pattern[str], str]]] = {
    "run": [(re.compile(r"\bdt=None\b"), "--dt none"),
            (re.compile(_METHOD), r"--method \1\2"), _STEP, _DRIFT],
    "paper": [(re.compile(r"\bdt=None\b"), "`dzhanibekov run SCENE --dt none`"),
              (re.compile(_METHOD), r"`dzhanibekov run SCENE --method \1\2`"),
              _STEP, _DRIFT],
    # a sweep's step is fixed and its method RK4: only a smaller --dt is the map's to take
    "map": [(re.compile(r", dt=None to pick the step for an accuracy, or [^.]*?(?:method='[\w-]+'"
                        r"|\(such as '[\w-]+'[^)]*\))\."), "."), _STEP, _DRIFT],
}
"""Advice written for the Python API, said in each command's terms."""


def cli_terms(text: str, command: str) -> str:
    """`text` (a warning of the Python API) with its advice in the terms of `command`'s
    options, on one line."""
    for pattern, replacement in _API_TO_CLI.get(command, []):
        text = pattern.sub(replacement, text)
    return " ".join(text.split())


def _warn_all(args: argparse.Namespace) -> None:
    """Prints each warning raised (once), one line in the command's terms, on stderr; empties
    the list."""
    seen = set()
    for w in args.caught:
        line = cli_terms(str(w.message), args.command)
        if line not in seen:
            seen.add(line)
            print(f"dzhanibekov: warning: {line}", file=sys.stderr, flush=True)
    args.caught.clear()


def _note_steps(results: Sequence[SceneResult], dt: float | None) -> None:
    """Warns where a run took steps other than `--dt`: a step never spans more than the
    time between two frames, and the span between frames is cut into equal steps."""
    if dt is None:
        return
    for r in results:
        run = r.trajectory if r.trajectory is not None else r.summary
        assert run is not None
        if run.n_steps == 0:
            warnings.warn(f"--dt {dt:g} is ignored by --method {run.method}, which takes no "
                          "steps", UserWarning, stacklevel=2)
        elif not is_adaptive(run.method) and abs(run.dt - dt) > 1e-12 * dt:
            spacing = r.scene.t_end / (r.scene.frames - 1)
            warnings.warn(f"--dt {dt:g} became {run.dt:g} in {r.scene.name}: a run goes from "
                          f"frame to frame (every {spacing:g}) in equal steps no longer than "
                          "--dt", UserWarning, stacklevel=2)


_OPTIONS = {"t_end": "--t-end", "frames": "--frames", "dt": "--dt", "method": "--method"}
"""The scene fields `run` overrides, and their options."""


def _override(scene: Scene, overrides: dict[str, Any]) -> Scene:
    """`scene` with the command line's overrides, each checked as the scene file's key is and
    an error naming the option, not the key."""
    try:
        return scene.replace(**overrides)
    except SceneError as exc:
        field = (exc.key or "").removeprefix("run.")
        if field in overrides:
            raise ValueError(f"`{_OPTIONS[field]}` {cli_terms(exc.detail, 'run')}") from None
        if exc.key == "run":  # the options together (a step and a tolerance)
            raise ValueError(f"{scene.name}: {cli_terms(exc.detail, 'run')}") from None
        raise


def _paper(args: argparse.Namespace) -> int:
    from .render import output_folder, render_paper

    if args.dt is not None:
        for name in PAPER_RENDER:  # every scene takes the step, before anything runs
            _override(SCENES[name], {"dt": args.dt})
    start = time.perf_counter()
    with output_folder(args.out) as tmp:
        files, results = render_paper(tmp, dt=args.dt, progress=_progress(args),
                                      fps=args.fps, size=args.gif_size,
                                      animation=not args.no_animation, workers=args.jobs,
                                      report=_say)
        _note_steps(results, args.dt)
        # the last step that can fail, before anything is moved into `--out`
        text = (_table(results, time.perf_counter() - start)
                + f"\nwrote {len(files)} files to {args.out}")
    args.committed = True
    _warn_all(args)
    print(text)
    return 0


def _run(args: argparse.Namespace) -> int:
    from .plotting.figures import compute
    from .render import output_folder, render_scene

    scene = load_scene(args.scene)  # errors name the file and key, before any output
    if args.out is None:  # a folder named after the scene, here
        args.out = Path(scene.name)
    overrides = {key: getattr(args, key) for key in _OPTIONS if getattr(args, key) is not None}
    if overrides:
        scene = _override(scene, overrides)
    start = time.perf_counter()
    with output_folder(args.out) as tmp:
        result = compute(scene)
        step = overrides.get("dt")
        _note_steps([result], step if isinstance(step, float) else None)
        files = render_scene(result, tmp, progress=_progress(args), flip_times=args.flip_times,
                             fps=args.fps, size=args.gif_size, animation=not args.no_animation,
                             report=_say)
        text = (_table([result], time.perf_counter() - start)
                + f"\nwrote {len(files)} files to {args.out}: "
                + ", ".join(f.name for f in files))
    args.committed = True
    _warn_all(args)
    print(text)
    return 0


def _map(args: argparse.Namespace) -> int:
    from .plotting.maps import MAPS, render_maps
    from .render import output_folder

    kinds = MAPS if args.kind == "both" else (args.kind,)
    start = time.perf_counter()
    with output_folder(args.out) as tmp:
        files, results = render_maps(tmp, kinds, size=args.size, t_end=args.t_end, dt=args.dt,
                                     progress=_progress(args))
        lines = [f"{'map':<10} {'runs':>7} {'flipped':>8} {'turned over':>12}"
                 f" {'steps per run':>14}"]
        for kind, r in zip(kinds, results):
            turned = int((r.tilt > np.pi / 2).sum())
            lines.append(f"{kind:<10} {len(r):>7} {int((r.flips > 0).sum()):>8} {turned:>12}"
                         f" {int(r.n_steps.flat[0]):>14}")
        lines.append(f"rendered in {time.perf_counter() - start:.1f} s")
        lines.append(f"wrote {len(files)} files to {args.out}: "
                     + ", ".join(f.name for f in files))
    args.committed = True
    _warn_all(args)
    print("\n".join(lines))
    return 0


def _view(args: argparse.Namespace) -> int:
    from .render import OutputError, _missing_ancestors
    from .viewer import write_html

    scene = load_scene(args.scene)  # errors name the file and key, before any output
    if args.out is None:  # a page named after the scene, here
        args.out = Path(f"{scene.name}.html")
    out = Path(args.out)
    if out.is_dir():
        raise ValueError(f"`--out` must be an HTML file, but {out} is a folder")
    for parent in out.parents:  # its folder is created, as `run`, `map` and `paper` do
        if parent.exists():
            if not parent.is_dir():
                raise OutputError(out, f"{parent} is a file, not a folder")
            break
    created = _missing_ancestors(out.parent)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        path = write_html(scene, out, frames=args.frames)
    except BaseException:
        for folder in created:  # deepest first; only those still empty
            try:
                folder.rmdir()
            except OSError:
                break
        raise
    args.committed = True
    _warn_all(args)
    print(f"wrote {path} ({path.stat().st_size / 1e6:.1f} MB): open it in a browser")
    return 0


def _scenes(args: argparse.Namespace) -> int:
    if args.show is not None:
        if args.show not in SCENES:
            raise ValueError(f"no shipped scene {args.show!r}; the scenes are {', '.join(SCENES)}")
        text = (resources.files("dzhanibekov") / "scenes" / f"{args.show}.toml").read_text(
            encoding="utf-8")
        print(text, end="")
        return 0
    for name, scene in SCENES.items():
        print(f"{name:<16} {scene.title}")
    return 0


def _movie_option(name: str) -> Callable[[str], int]:
    """`--fps` or `--gif-size`, checked against the animation's limits whatever the scene."""
    def parse(text: str) -> int:
        from .plotting.movie import FPS_LIMITS, SIZE_LIMITS

        low, high = FPS_LIMITS if name == "fps" else SIZE_LIMITS
        return _whole(low, high)(text)
    return parse


def _movie_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--fps", type=_movie_option("fps"), default=None,
                        help="animation frames per second (default: the scene's, else 20)")
    parser.add_argument("--gif-size", type=_movie_option("size"), default=None,
                        dest="gif_size", metavar="PX",
                        help="animation width and height in pixels (default: the scene's, "
                        "else 480)")
    parser.add_argument("--no-animation", action="store_true", dest="no_animation",
                        help="draw the figures only, no animation")


def _paper_description() -> str:
    """What `paper` renders, from the scenes themselves."""
    animated = [n for n in PAPER_RENDER if SCENES[n].draw.animation]
    lines = [f"Simulate {_count(len(PAPER_RENDER))} scenes and render, into DIR, their "
             f"figures ({sum(len(SCENES[n].draw.figures) for n in PAPER_RENDER)} PNG files, "
             "SCENE-FIGURE.png), fig3.png (Fig. 3 a-c side by side) and stable.png (the "
             f"stable counter-examples), {_count(len(animated))} animations (SCENE.gif, and "
             "SCENE.mp4 where an ffmpeg is found) and a JSON summary of each scene (flip "
             "times, verdict, drift); then print a table of the flip times and the "
             "invariants' drift. Figures and animations are drawn in parallel processes "
             "(--jobs); a line on stderr says when each is done."]
    lines = [textwrap.fill(lines[0], 79), "", "The scenes:"]
    for name in PAPER_RENDER:
        scene = SCENES[name]
        what = ", ".join(scene.draw.figures) + (" + animation" if scene.draw.animation else "")
        lines.append(f"  {name:<16} {scene.title}")
        lines.append(f"  {'':<16}   ({what})")
    return "\n".join(lines)


def _count(n: int) -> str:
    words = ("no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine",
             "ten", "eleven", "twelve")
    return words[n] if n < len(words) else str(n)


def main(argv: Sequence[str] | None = None) -> int:
    """Runs the command line with `argv` (default ``sys.argv[1:]``); returns the exit code."""
    parser = argparse.ArgumentParser(
        prog="dzhanibekov",
        description="Free rotation of rigid bodies: the Dzhanibekov effect. Renders the "
        "paper's figures and your own scenes (TOML files).",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    paper = commands.add_parser(
        "paper",
        help="render the paper's figures and animations (nine scenes, four animated)",
        description=_paper_description(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    paper.add_argument("--out", required=True, type=Path, metavar="DIR",
                       help="folder to write into (created; files of the same name replaced)")
    paper.add_argument("--dt", type=_positive, default=None,
                       help="step for every scene (default: each scene's own)")
    paper.add_argument("--jobs", type=_whole(1, 1024), default=None, metavar="N",
                       help="processes to draw in (default: one per CPU this process may "
                       "use)")
    paper.add_argument("--no-progress", action="store_true",
                       help="no progress bars (the line per scene stays)")
    _movie_options(paper)
    paper.set_defaults(run=_paper)

    run = commands.add_parser(
        "run",
        help="render one scene (a TOML file, or a shipped scene's name)",
        description="Simulate one scene and render what it draws into DIR (--out; default: "
        "a folder named NAME after the scene, in the current one): NAME-FIGURE.png "
        "for each figure, NAME.gif (and .mp4) if it asks for an animation, NAME.json with "
        "its flip times and drift. See `dzhanibekov scenes --show fig3a` for a file to "
        "start from.",
    )
    run.add_argument("scene", metavar="SCENE", help="a scene file (.toml) or a shipped name")
    run.add_argument("--out", type=Path, metavar="DIR",
                     help="folder to write into (created; files of the same name replaced; "
                     "default: a folder named after the scene, in the current one)")
    run.add_argument("--method", default=None,
                     help="override the scene's method: one of " + ", ".join(METHODS))
    run.add_argument("--t-end", type=float, default=None, dest="t_end", metavar="T",
                     help="override the scene's end time (phases after it are dropped)")
    run.add_argument("--frames", type=int, default=None, metavar="N",
                     help="override the scene's number of frames")
    run.add_argument("--dt", type=_step, default=None, metavar="DT",
                     help="override the scene's step: a number, or 'none' for the step picked "
                     "for the scene's rtol")
    run.add_argument("--flip-times", action="store_true", dest="flip_times",
                     help="also write every flip time to NAME-flip-times.npy (the JSON lists "
                     "at most 1000 and summarises longer lists)")
    run.add_argument("--no-progress", action="store_true",
                     help="no progress: neither the run's (a bar on a terminal, else a line "
                     "every 10 s on stderr) nor the animation's")
    _movie_options(run)
    run.set_defaults(run=_run)

    stability = commands.add_parser(
        "map",
        help="render stability maps: flip period and tilt over a grid of starts",
        description="Sweep a grid of starts and draw, into DIR, the measured flip period "
        "and the largest tilt of the spin axis over it, with the separatrix: map-rates.png "
        "(the paper's body, ω0 = (u0, v0, 1)) and map-inertia.png (bodies (1, iy, iz), "
        "ω0 = (0.2, 0.2, 1)), each with a .npz of the per-run numbers.",
    )
    stability.add_argument("--out", required=True, type=Path, metavar="DIR",
                           help="folder to write into (created; files of the same name "
                           "replaced)")
    stability.add_argument("--kind", choices=["rates", "inertia", "both"], default="both",
                           help="which map (default both)")
    stability.add_argument("--size", type=int, default=81,
                           help="starts per axis of the grid (default 81)")
    stability.add_argument("--t-end", type=float, default=200.0, dest="t_end",
                           help="length of each run (default 200)")
    stability.add_argument("--dt", type=float, default=1e-2, help="RK4 step (default 0.01)")
    stability.add_argument("--no-progress", action="store_true", help="no progress bar")
    stability.set_defaults(run=_map)

    view = commands.add_parser(
        "view",
        help="write the interactive viewer of a scene (one HTML file)",
        description="Simulate one scene and write FILE.html (--out; default: NAME.html after "
        "the scene, in the current folder): the body, its inertia "
        "ellipsoid and the signal point's path, to rotate in a browser, with play/pause and "
        "a time slider. One self-contained file (plotly embedded): it opens offline. Needs "
        'the viewer extra: pip install "dzhanibekov[viewer]".',
    )
    view.add_argument("scene", metavar="SCENE", help="a scene file (.toml) or a shipped name")
    view.add_argument("--out", type=Path, metavar="FILE.html",
                      help="the HTML file to write (default: the scene's name .html, in the "
                      "current folder)")
    view.add_argument("--frames", type=int, default=None,
                      help="frames shown (default: every frame, at most 201)")
    view.set_defaults(run=_view)

    scenes = commands.add_parser(
        "scenes",
        help="list the shipped scenes",
        description="List the scenes shipped with the package, or print one (a template "
        "for your own).",
    )
    scenes.add_argument("--show", metavar="NAME", help="print the TOML file of scene NAME")
    scenes.set_defaults(run=_scenes)

    args = parser.parse_args(argv)
    args.committed = False  # set once the output is in place
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        args.caught = caught
        try:
            # `--no-progress` silences the runs' progress too (a bar, or lines in a log)
            with progress_default(False if getattr(args, "no_progress", False) else None):
                return int(args.run(args))
        except (SceneError, ValueError, TypeError, ImportError, OSError) as exc:
            # OSError: the output folder cannot be written (render.OutputError names the path)
            _warn_all(args)
            print(f"dzhanibekov: error: {exc}", file=sys.stderr)
            return 2
        except MemoryError as exc:
            _warn_all(args)
            print(f"dzhanibekov: error: out of memory{f': {exc}' if str(exc) else ''}; "
                  f"{_what_was_written(args)}", file=sys.stderr)
            return 2
        except KeyboardInterrupt as exc:
            if isinstance(exc, CommittedInterrupt):
                args.committed = True
            print(f"dzhanibekov: interrupted; {_what_was_written(args)}", file=sys.stderr)
            return 130


def _what_was_written(args: argparse.Namespace) -> str:
    """The truth about `--out` after a failure."""
    if args.committed:
        return f"every file was written to {args.out}"
    return "nothing written"
