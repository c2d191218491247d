"""Rendering scenes into a folder, all or nothing.

Files are drawn into a temporary folder beside the destination and moved into place only
when every one of them is done, so an error or Ctrl-C leaves the destination as it was.
"""

from __future__ import annotations

import dataclasses
import contextlib
import json
import multiprocessing
import multiprocessing.connection
import os
import shutil
import signal
import sys
import tempfile
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import partial
from multiprocessing.connection import Connection
from multiprocessing.process import BaseProcess
from pathlib import Path
from typing import Any

import numpy as np
from tqdm import tqdm

from ._args import as_int
from ._files import partial_prefix, remove_stale
from .scenes.plan import SceneResult
from .scenes.scene import PAPER_SCENES, SCENES, STORY_SCENES, Scene

# matplotlib is imported where something is drawn: `output_folder` and the command line's
# start stay light

__all__ = ["render_scene", "render_paper", "output_folder", "OutputError", "CommittedInterrupt",
           "MAX_JSON_FLIP_TIMES", "PAPER_RENDER", "default_workers"]

MAX_JSON_FLIP_TIMES = 1000
"""Flip times listed in a scene's JSON summary; longer lists are summarised there (count,
first, last, mean spacing) and written in full to ``NAME-flip-times.npy`` only when asked."""


class OutputError(OSError):
    """The output folder cannot be written, or an output cannot replace what is there; the
    message names the path and the cause, and the folder is as it was."""

    def __init__(self, path: str | Path, why: str) -> None:
        super().__init__(f"cannot write {path}: {why}; nothing was written or replaced")
        self.path, self.why = str(path), why

    def __reduce__(self) -> tuple[type[OutputError], tuple[str, str]]:
        return type(self), (self.path, self.why)


def _missing_ancestors(out: Path) -> list[Path]:
    """`out` and its ancestors that do not exist yet, deepest first."""
    missing = []
    for folder in (out, *out.parents):
        if os.path.lexists(folder):
            break
        missing.append(folder)
    return missing


def _check_destination(out: Path) -> None:
    """Refuses an `out` that cannot become a folder: a file, a dangling symbolic link, or a
    path below a file."""
    if os.path.lexists(out) and not out.exists():
        raise OutputError(out, f"it is a symbolic link to {os.readlink(out)}, which does not "
                          "exist; create that folder or give another `--out`")
    if out.exists() and not out.is_dir():
        raise OutputError(out, "it is a file; `--out` must be a folder")
    for parent in out.parents:
        if parent.exists():
            if not parent.is_dir():
                raise OutputError(out, f"{parent} is a file, not a folder")
            break


class CommittedInterrupt(KeyboardInterrupt):
    """Ctrl-C came while the output was being moved into place: the move was finished first
    (it takes microseconds), so every file is written; raised as soon as it is."""


@contextlib.contextmanager
def _ctrl_c_held() -> Iterator[list[int]]:
    """Holds SIGINT back while the block runs (in the main thread; elsewhere nothing is
    held); the list it gives holds the signals that came."""
    came: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield came
        return
    previous = signal.signal(signal.SIGINT, lambda signum, frame: came.append(signum))
    try:
        yield came
    finally:
        signal.signal(signal.SIGINT, previous)


@contextlib.contextmanager
def output_folder(out: str | Path) -> Iterator[Path]:
    """A temporary folder inside `out` (created if need be) to write into; its files replace
    those of the same name in `out` when the block ends normally, and it is removed whatever
    happens. Made inside `out`, it is on the same filesystem (a mount point works) and its
    files move in by renaming.

    Every destination is checked before any is replaced: a folder named like an output
    leaves `out` untouched. Any failure to write (a read-only folder, a full disk, a file-size
    limit) raises :class:`OutputError` naming the path, and `out` is as it was; folders this
    call created are removed again. A folder that a killed run left in `out` (named for its
    host and process, which is gone) is removed. Ctrl-C while the files move in is held until
    they all have, then raised as :class:`CommittedInterrupt`.
    """
    out = Path(out)
    _check_destination(out)
    created = _missing_ancestors(out)
    done = False
    tmp: Path | None = None
    try:
        out.mkdir(parents=True, exist_ok=True)
        # what a killed run left here (its process gone), then this run's own
        remove_stale(out, "partial", "")
        tmp = Path(tempfile.mkdtemp(prefix=partial_prefix("partial"), dir=out))
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)
        yield tmp
        items = sorted(tmp.iterdir())
        for item in items:
            target = out / item.name
            if target.is_dir() and not target.is_symlink():
                raise OutputError(target, "a folder of that name is in the way of the output "
                                  "file; move it away")
        with _ctrl_c_held() as came:  # all of the files or none: no Ctrl-C half-way
            for item in items:
                os.replace(item, out / item.name)
            done = True
        if came:
            raise CommittedInterrupt()
    except OutputError:
        raise
    except OSError as exc:
        path = exc.filename if exc.filename is not None else out
        if tmp is not None and Path(path).is_relative_to(tmp):
            path = out / Path(path).relative_to(tmp)  # the file it was to become
        raise OutputError(path, exc.strerror or str(exc)) from None
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        if not done:
            for folder in created:  # deepest first; only those still empty
                try:
                    folder.rmdir()
                except OSError:
                    break


@contextlib.contextmanager
def _writing(path: Path) -> Iterator[None]:
    """Names `path` in an OSError raised while writing it (matplotlib's and Pillow's writes
    through file objects leave the name out)."""
    try:
        yield
    except OSError as exc:
        if exc.filename is None:
            exc.filename = str(path)
        raise


def summary(result: SceneResult) -> dict[str, Any]:
    """What the run measured, for a JSON file.

    ``dt`` is the step the run took (a fixed-step method's, or an adaptive method's first
    try) and null for a method that takes no steps (``"exact"``: the closed form at each
    frame, ``n_steps`` 0)."""
    run = result.trajectory if result.trajectory is not None else result.summary
    assert run is not None
    flips = result.flip_times
    listed = flips is not None and len(flips) <= MAX_JSON_FLIP_TIMES
    return {
        "scene": result.scene.name,
        "title": result.scene.title,
        "verdict": result.verdict,
        "flip_times": [float(t) for t in flips] if listed and flips is not None else None,
        "flips": None if flips is None else {
            "count": len(flips),
            "first": float(flips[0]) if len(flips) else None,
            "last": float(flips[-1]) if len(flips) else None,
            "mean_spacing": float((flips[-1] - flips[0]) / (len(flips) - 1))
            if len(flips) > 1 else None,
        },
        "drift": dataclasses.asdict(run.drift),
        "method": run.method,
        "dt": run.dt if run.n_steps > 0 else None,
        "n_steps": run.n_steps,
    }


Report = Callable[[str], None]
"""Takes one line of progress (no newline)."""


@dataclass(frozen=True)
class _Task:
    """A unit of drawing work, done in this process or a worker: the figures of a scene, its
    animation, or a figure of several scenes."""

    kind: str  # "figures", "animation", "fig3", "stable"
    label: str
    results: tuple[SceneResult, ...]
    folder: Path
    fps: int | None = None
    size: int | None = None
    cost: float = 1.0  # relative, to start the longest first


def _figures(result: SceneResult, folder: Path) -> list[Path]:
    from .plotting.figures import FIGURE_FUNCTIONS

    written = []
    for figure in result.scene.draw.figures:
        path = folder / f"{result.scene.name}-{figure}.png"
        with _writing(path):
            FIGURE_FUNCTIONS[figure](result, save=path)
        written.append(path)
    return written


def _animation(result: SceneResult, folder: Path, fps: int | None, size: int | None,
               progress: bool | None, on_frame: Callable[[int, int], None] | None
               ) -> list[Path]:
    from .plotting.movie import animate

    path = folder / f"{result.scene.name}.gif"
    with _writing(path):
        return animate(result, path, progress=progress, fps=fps, size=size, on_frame=on_frame)


def _do(task: _Task, progress: bool | None = False,
        on_frame: Callable[[int, int], None] | None = None) -> list[Path]:
    """Does `task`; returns the files it wrote."""
    if task.kind == "figures":
        return _figures(task.results[0], task.folder)
    if task.kind == "animation":
        return _animation(task.results[0], task.folder, task.fps, task.size, progress,
                          on_frame)
    from .plotting.figures import fig3_figure

    path = task.folder / f"{task.kind}.png"
    with _writing(path):
        fig3_figure(list(task.results), save=path)
    return [path]


def _done_line(task: _Task, files: list[Path], seconds: float) -> str:
    """What a finished task says: what it drew, in how long."""
    if task.kind == "figures":
        what = ", ".join(task.results[0].scene.draw.figures)
        return f"{task.label}: {len(files)} figure{'s' if len(files) != 1 else ''} ({what})" \
               f" in {seconds:.1f} s"
    if task.kind == "animation":
        sizes = ", ".join(f"{p.name} {p.stat().st_size / 1e6:.1f} MB" for p in files)
        return f"{task.label}: animation {sizes} in {seconds:.1f} s"
    return f"{task.label}: {files[0].name} in {seconds:.1f} s"


# -- the workers ---------------------------------------------------------------------------

_Frame = Callable[[str, int, int], None]
"""Takes a task's label, the frames drawn and the frames in all."""


def _work(task: _Task, on_frame: _Frame | None
          ) -> tuple[str, list[Path], float, list[tuple[type[Warning], str]]]:
    """A worker's task: done, with its files, its time and the warnings it raised."""
    start = time.perf_counter()

    def frame(done: int, total: int) -> None:
        if on_frame is not None and (done % 5 == 0 or done == total):
            on_frame(task.label, done, total)

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        files = _do(task, on_frame=frame)
    return task.label, files, time.perf_counter() - start, \
        [(w.category, str(w.message)) for w in caught]


def _serve(conn: Connection, frames: bool) -> None:
    """A worker process: does each task it is sent on `conn` and sends back ``("done",
    what _work returns)`` or ``("error", exception)``, and with `frames` ``("frame", label,
    done, total)`` on the way; ends when the parent closes its end. Ctrl-C is the parent's
    to handle (it kills its workers)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)

    def on_frame(label: str, done: int, total: int) -> None:
        conn.send(("frame", label, done, total))

    while True:
        try:
            task = conn.recv()
        except EOFError:
            return
        try:
            reply: tuple[str, Any] = ("done", _work(task, on_frame if frames else None))
        except Exception as exc:
            reply = ("error", exc)
        try:
            conn.send(reply)
        except BrokenPipeError:  # the parent is gone
            return
        except Exception as exc:  # `reply` cannot be pickled: its words can
            what = reply[1] if reply[0] == "error" else exc
            conn.send(("error", RuntimeError(f"{task.label}: {type(what).__name__}: {what}")))


def _died(proc: BaseProcess, task: _Task) -> ChildProcessError:
    """The error of a worker that ended (killed, out of memory) before `task` was done."""
    proc.join(1)
    code = proc.exitcode
    how = f"was killed by {signal.Signals(-code).name}" if code is not None and code < 0 \
        else f"ended (exit code {code})"
    return ChildProcessError(f"the process drawing {task.label} {how} before it was done")


def default_workers() -> int:
    """The processes a render uses by default: one per CPU this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


class _Bars:
    """Progress bars of the animations being drawn (tqdm on stderr), and the lines of the
    finished tasks printed above them."""

    def __init__(self, report: Report | None, show: bool | None) -> None:
        self.report = report
        self.show = sys.stderr.isatty() if show is None else show
        self.bars: dict[str, Any] = {}
        self.lock = threading.Lock()

    def frame(self, label: str, done: int, total: int) -> None:
        if not self.show:
            return
        with self.lock:
            bar = self.bars.get(label)
            if bar is None:
                bar = self.bars[label] = tqdm(total=total, desc=label, unit="frame",
                                              leave=False, file=sys.stderr)
            bar.update(done - bar.n)

    def line(self, label: str, text: str) -> None:
        with self.lock:
            bar = self.bars.pop(label, None)
            if bar is not None:
                bar.close()
            if self.report is not None:
                if self.bars:
                    tqdm.write(text, file=sys.stderr)
                else:
                    self.report(text)

    def close(self) -> None:
        with self.lock:
            for bar in self.bars.values():
                bar.close()
            self.bars.clear()


def _run_tasks(tasks: list[_Task], workers: int, bars: _Bars) -> list[Path]:
    """Does every task, longest first, in `workers` processes (here if 1); reports each as
    it ends. Any error ends the workers at once and is raised here."""
    tasks = sorted(tasks, key=lambda t: -t.cost)
    n = len(tasks)
    written: list[Path] = []
    if workers <= 1 or n <= 1:
        for k, task in enumerate(tasks, 1):
            start = time.perf_counter()
            files = _do(task, progress=False, on_frame=partial(bars.frame, task.label))
            written += files
            bars.line(task.label, f"[{k:>{len(str(n))}}/{n}] "
                      + _done_line(task, files, time.perf_counter() - start))
        return written
    # Worker processes of our own, one pipe each, each sent a task only when it is idle: the
    # parent's sends cannot block for long and no thread of ours writes to a pipe. (Pool hung
    # here: after Ctrl-C, Pool.terminate() could kill the workers while its task-handler
    # thread was about to write a pickled task -- 34 kB to 2.2 MB, the pipe holds 64 kB --
    # and then waited for ever for that thread.) On Ctrl-C or an error the workers are killed.
    context = multiprocessing.get_context("spawn")  # no threads inherited from this process
    procs: dict[Connection, BaseProcess] = {}
    doing: dict[Connection, _Task | None] = {}  # what each worker draws (None: it waits)
    todo = list(tasks)
    done = False
    try:
        for _ in range(min(workers, n)):
            here, there = context.Pipe()
            proc = context.Process(target=_serve, args=(there, bars.show), daemon=True)
            with _ctrl_c_held() as came:  # a started worker is always in `procs`
                proc.start()
                procs[here], doing[here] = proc, None
            there.close()  # this end is the worker's: its death is EOF here
            if came:
                raise KeyboardInterrupt
        k = 0
        while k < n:
            for conn, doing_now in doing.items():
                if doing_now is None and todo:
                    doing[conn] = sent = todo.pop(0)
                    try:
                        conn.send(sent)
                    except BrokenPipeError:
                        raise _died(procs[conn], sent) from None
            for ready in multiprocessing.connection.wait(
                    [conn for conn, doing_now in doing.items() if doing_now is not None]):
                assert isinstance(ready, Connection)
                drawing = doing[ready]
                assert drawing is not None
                try:
                    kind, *what = ready.recv()
                except EOFError:
                    raise _died(procs[ready], drawing) from None
                if kind == "frame":
                    bars.frame(*what)
                    continue
                doing[ready] = None
                if kind == "error":
                    raise what[0]
                label, files, seconds, caught = what[0]
                for category, message in caught:
                    warnings.warn(message, category, stacklevel=2)
                written += files
                k += 1
                bars.line(label, f"[{k:>{len(str(n))}}/{n}] "
                          + _done_line(drawing, files, seconds))
        done = True
    finally:
        for conn, worker in procs.items():
            conn.close()  # a waiting worker's recv() ends: it returns
            if not done:
                worker.kill()
        for worker in procs.values():
            worker.join(None if not done else 10)
            if worker.exitcode is None:
                worker.kill()
                worker.join()
        bars.close()
    return written


def render_scene(scene: Scene | SceneResult, folder: str | Path, *,
                 progress: bool | None = None, flip_times: bool = False,
                 fps: int | None = None, size: int | None = None, animation: bool = True,
                 report: Report | None = None) -> list[Path]:
    """Writes what `scene` draws into `folder`: ``NAME-FIGURE.png`` for each of its figures,
    ``NAME.gif`` (and ``NAME.mp4`` with ffmpeg) for its animation unless `animation` is
    False, and last ``NAME.json`` with its flip times (at most :data:`MAX_JSON_FLIP_TIMES`;
    more are summarised), verdict and drift; with `flip_times`, every flip time in
    ``NAME-flip-times.npy``. Returns the files written.

    Write into a folder from :func:`output_folder` for all-or-nothing output. `fps` and
    `size` override the scene's animation settings (see
    :func:`~dzhanibekov.plotting.movie.animate`); `progress` shows the animation's progress
    bar (None: on a terminal); `report` takes a line for each part drawn.
    """
    from .plotting.figures import compute

    result = compute(scene)
    folder = Path(folder)
    name = result.scene.name
    tasks = [_Task("figures", name, (result,), folder)]
    if result.scene.draw.animation and animation:
        tasks.append(_Task("animation", f"{name}.gif", (result,), folder, fps, size))
    written = _run_tasks(tasks, 1, _Bars(report, progress))
    return written + _summaries([result], folder, flip_times=flip_times)


def _summaries(results: list[SceneResult], folder: Path, *,
               flip_times: bool = False) -> list[Path]:
    """Each result's ``NAME.json`` (and with `flip_times` its ``NAME-flip-times.npy``)."""
    written = []
    for result in results:
        name = result.scene.name
        about = summary(result)
        if flip_times and result.flip_times is not None:
            path = folder / f"{name}-flip-times.npy"
            with _writing(path):
                np.save(path, result.flip_times)
            written.append(path)
            about["flip_times_file"] = path.name
        path = folder / f"{name}.json"
        with _writing(path):
            path.write_text(json.dumps(about, indent=2) + "\n", encoding="utf-8")
        written.append(path)
    return written


PAPER_RENDER = (list(PAPER_SCENES) + ["wing-nut"]
                + [n for n in SCENES if n.startswith("stable-")] + list(STORY_SCENES))
"""The scenes `dzhanibekov paper` renders, in order: the paper's (Fig. 2, Fig. 3a–c), the wing
nut of its Fig. 1, the stable counter-examples and the bodies that change."""


def render_paper(folder: str | Path, *, dt: float | None = None,
                 progress: bool | None = None, fps: int | None = None,
                 size: int | None = None, animation: bool = True, workers: int | None = None,
                 report: Report | None = None) -> tuple[list[Path], list[SceneResult]]:
    """Writes every figure of the paper and its animation into `folder`, those of the wing
    nut of its Fig. 1, those of the stable counter-examples and of the bodies that change
    (:data:`PAPER_RENDER`: nine scenes, four of them animated): each scene's files as
    :func:`render_scene` writes them, plus ``fig3.png`` (Fig. 3 a–c side by side) and
    ``stable.png`` (the counter-examples' paths).

    The scenes run here (each in a fraction of a second); their figures and animations are
    drawn in `workers` processes (default :func:`default_workers`; 1 draws here), the
    longest first, and the JSON summaries written last.

    Parameters
    ----------
    folder : str or Path
        Where to write (an existing folder; see :func:`output_folder`).
    dt : float, optional
        The step of every scene (default: each scene's own).
    progress : bool, optional
        Progress bars of the animations on stderr: None (default) on a terminal only.
    fps, size : int, optional
        The animations' frame rate and size (default: each scene's).
    animation : bool
        Draw the animations (False: the figures only).
    workers : int, optional
        Processes to draw in.
    report : callable, optional
        Takes a line as each scene's figures or animation are done.

    Returns
    -------
    files : list of Path
    results : list of SceneResult
        The computed scenes, in the order of :data:`PAPER_RENDER`.
    """
    from .plotting.figures import compute

    folder = Path(folder)
    workers = default_workers() if workers is None else as_int("workers", workers, minimum=1,
                                                                maximum=1024)
    results = {}
    for name in PAPER_RENDER:
        scene = SCENES[name] if dt is None else SCENES[name].replace(dt=dt)
        results[name] = compute(scene)
    tasks = []
    for name, result in results.items():
        tasks.append(_Task("figures", name, (result,), folder,
                           cost=1.0 + ("phases" in result.scene.draw.figures)))
        if result.scene.draw.animation and animation:
            tasks.append(_Task("animation", f"{name}.gif", (result,), folder, fps, size,
                               cost=10.0 + 2.0 * result.scene.draw.ellipsoid))
    tasks.append(_Task("fig3", "Fig. 3 a-c", tuple(results[n] for n in ("fig3a", "fig3b",
                                                                          "fig3c")), folder))
    stable = tuple(results[n] for n in PAPER_RENDER if n.startswith("stable-"))
    if stable:
        tasks.append(_Task("stable", "stable", stable, folder))
    written = _run_tasks(tasks, workers, _Bars(report, progress))
    written += _summaries(list(results.values()), folder)
    return written, list(results.values())
