"""The command line ``dzhanibekov`` (also ``python -m dzhanibekov``).

- ``dzhanibekov paper --out DIR``: every figure of the paper and its animation, and the
  stable counter-examples; prints each run's flip times and drift.
- ``dzhanibekov run SCENE.toml --out DIR``: what one scene draws (a file or a shipped name).
- ``dzhanibekov scenes``: the shipped scenes; ``--show NAME`` prints one, to start your own.
- ``dzhanibekov map --out DIR``: stability maps (flip period and tilt over a grid of starts,
  with the separatrix) and their sweeps' numbers.
- ``dzhanibekov view SCENE --out FILE.html``: the interactive viewer, one self-contained
  HTML file (the ``viewer`` extra).
- ``dzhanibekov --version``.

Output is all or nothing: files are drawn in a temporary folder inside DIR and moved in
when all are done; any error (a bad scene, a folder that cannot be written, a full disk)
is one line on stderr with exit code 2, and DIR is left as it was.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from importlib import resources
from pathlib import Path

import numpy as np

from ._core import __version__
from .scenes.plan import SceneResult
from .scenes.scene import SCENES, SceneError, load_scene
from .simulate import METHODS

__all__ = ["main"]


def _table(results: Sequence[SceneResult], seconds: float) -> None:
    print(f"{'scene':<16} {'steps':>9} {'flips':>5}  {'first flip times':<28}"
          f" {'dE/E':>8} {'d|L|/|L|':>8} {'dL_world':>8} {'d|q|':>8}")
    for r in results:
        run = r.trajectory if r.trajectory is not None else r.summary
        assert run is not None
        times = [] if r.flip_times is None else list(r.flip_times)
        flips = ", ".join(f"{t:.3f}" for t in times[:4]) + (", …" if len(times) > 4 else "")
        d = r.drift
        count = "?" if r.flip_times is None else str(len(times))
        print(f"{r.scene.name:<16} {run.n_steps:>9} {count:>5}  {flips:<28}"
              f" {d.energy:>8.1e} {d.momentum:>8.1e} {d.momentum_world:>8.1e} {d.q_norm:>8.1e}")
    print(f"rendered in {seconds:.1f} s")


def _step(text: str) -> float | str:
    """`--dt`: a number, or "none" (the step picked for an accuracy)."""
    if text.strip().lower() == "none":
        return "none"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number or 'none', got {text!r}") from None


def _progress(args: argparse.Namespace) -> bool | None:
    return False if args.no_progress else None


def _paper(args: argparse.Namespace) -> int:
    from .render import output_folder, render_paper

    start = time.perf_counter()
    with output_folder(args.out) as tmp:
        files, results = render_paper(tmp, dt=args.dt, progress=_progress(args),
                                      fps=args.fps, size=args.gif_size)
    _table(results, time.perf_counter() - start)
    print(f"wrote {len(files)} files to {args.out}")
    return 0


def _run(args: argparse.Namespace) -> int:
    from .plotting.figures import compute
    from .render import output_folder, render_scene

    scene = load_scene(args.scene)  # errors name the file and key, before any output
    overrides = {key: getattr(args, key) for key in ("method", "t_end", "frames", "dt")
                 if getattr(args, key) is not None}
    if overrides:
        scene = scene.replace(**overrides)  # checked as the scene file's keys are
    start = time.perf_counter()
    with output_folder(args.out) as tmp:
        result = compute(scene)
        files = render_scene(result, tmp, progress=_progress(args), flip_times=args.flip_times,
                             fps=args.fps, size=args.gif_size)
    _table([result], time.perf_counter() - start)
    print(f"wrote {len(files)} files to {args.out}: " + ", ".join(f.name for f in files))
    return 0


def _map(args: argparse.Namespace) -> int:
    from .plotting.maps import MAPS, render_maps
    from .render import output_folder

    kinds = MAPS if args.kind == "both" else (args.kind,)
    start = time.perf_counter()
    with output_folder(args.out) as tmp:
        files, results = render_maps(tmp, kinds, size=args.size, t_end=args.t_end, dt=args.dt,
                                     progress=_progress(args))
    print(f"{'map':<10} {'runs':>7} {'flipped':>8} {'turned over':>12} {'steps per run':>14}")
    for kind, r in zip(kinds, results):
        turned = int((r.tilt > np.pi / 2).sum())
        print(f"{kind:<10} {len(r):>7} {int((r.flips > 0).sum()):>8} {turned:>12}"
              f" {int(r.n_steps.flat[0]):>14}")
    print(f"rendered in {time.perf_counter() - start:.1f} s")
    print(f"wrote {len(files)} files to {args.out}: " + ", ".join(f.name for f in files))
    return 0


def _view(args: argparse.Namespace) -> int:
    from .viewer import write_html

    scene = load_scene(args.scene)  # errors name the file and key, before any output
    out = Path(args.out)
    if out.is_dir():
        raise ValueError(f"`--out` must be an HTML file, but {out} is a folder")
    path = write_html(scene, out, frames=args.frames)
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


def _movie_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--fps", type=int, default=None,
                        help="animation frames per second (default: the scene's, else 20)")
    parser.add_argument("--gif-size", type=int, default=None, dest="gif_size", metavar="PX",
                        help="animation width and height in pixels (default: the scene's, "
                        "else 560)")


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
        help="render every figure of the paper and its animation",
        description="Simulate the paper's scenes (Fig. 2 and Fig. 3a-c) and two stable "
        "counter-examples, render their figures, the animation (GIF; MP4 too when ffmpeg is "
        "found) and a JSON summary of each into DIR, and print flip times and the "
        "invariants' drift.",
    )
    paper.add_argument("--out", required=True, type=Path, metavar="DIR",
                       help="folder to write into (created; files of the same name replaced)")
    paper.add_argument("--dt", type=float, default=None,
                       help="step for every scene (default: each scene's own)")
    paper.add_argument("--no-progress", action="store_true", help="no progress bar")
    _movie_options(paper)
    paper.set_defaults(run=_paper)

    run = commands.add_parser(
        "run",
        help="render one scene (a TOML file, or a shipped scene's name)",
        description="Simulate one scene and render what it draws into DIR: NAME-FIGURE.png "
        "for each figure, NAME.gif (and .mp4) if it asks for an animation, NAME.json with "
        "its flip times and drift. See `dzhanibekov scenes --show fig3a` for a file to "
        "start from.",
    )
    run.add_argument("scene", metavar="SCENE", help="a scene file (.toml) or a shipped name")
    run.add_argument("--out", required=True, type=Path, metavar="DIR",
                     help="folder to write into (created; files of the same name replaced)")
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
    run.add_argument("--no-progress", action="store_true", help="no progress bar")
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
        description="Simulate one scene and write FILE.html: the body, its inertia "
        "ellipsoid and the signal point's path, to rotate in a browser, with play/pause and "
        "a time slider. One self-contained file (plotly embedded): it opens offline. Needs "
        'the viewer extra: pip install ".[viewer]".',
    )
    view.add_argument("scene", metavar="SCENE", help="a scene file (.toml) or a shipped name")
    view.add_argument("--out", required=True, type=Path, metavar="FILE.html",
                      help="the HTML file to write")
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
    try:
        return int(args.run(args))
    except (SceneError, ValueError, TypeError, ImportError, OSError) as exc:
        # OSError: the output folder cannot be written (render.OutputError names the path)
        print(f"dzhanibekov: error: {exc}", file=sys.stderr)
        return 2
    except MemoryError as exc:
        print(f"dzhanibekov: error: out of memory{f': {exc}' if str(exc) else ''}; nothing "
              "written", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("dzhanibekov: interrupted; nothing written", file=sys.stderr)
        return 130
