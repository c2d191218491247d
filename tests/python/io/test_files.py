"""Files out all or nothing, files in refused at once when they are no regular file.

Every writer of a user's file (`dz.save`, `dz.io.write_aem`, `dz.viewer.write_html`,
`Scene.save`, the figures' and maps' `save=`) writes a temporary file beside the destination
and renames it over it once complete: after a failure — a full disk, a file-size limit, an
error of the writer, Ctrl-C — the previous file is intact and nothing else is left in the
folder. The real failures (a file-size limit, which is how a full disk looks to a writer, and
SIGINT) run in child processes; the rest inject an OSError.
"""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

import dzhanibekov as dz

TRAJ = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=100.0, frames=41, dt=1e-2)
OLD = b"the previous file\n"


def _writers() -> dict[str, Callable[[Path], Any]]:
    out: dict[str, Callable[[Path], Any]] = {
        "save": lambda p: dz.save(TRAJ, p.with_suffix(".nc")),
        "write_aem": lambda p: dz.io.write_aem(TRAJ, p.with_suffix(".aem"), "BOX",
                                               "2026-001A", "2026-01-01T00:00:00",
                                               ref_frame_a="EME2000"),
        "Scene.save": lambda p: dz.SCENES["fig3a"].save(p.with_suffix(".toml")),
        "figure save=": lambda p: dz.plotting.path_figure(TRAJ, save=p.with_suffix(".png")),
    }
    try:
        import plotly  # noqa: F401

        out["write_html"] = lambda p: dz.viewer.write_html(TRAJ, p.with_suffix(".html"),
                                                           frames=3)
    except ImportError:
        pass
    return out


WRITERS = _writers()
SUFFIX = {"save": ".nc", "write_aem": ".aem", "Scene.save": ".toml", "figure save=": ".png",
          "write_html": ".html"}


@pytest.mark.parametrize("writer", sorted(WRITERS))
def test_a_writer_replaces_a_file_whole(writer: str, tmp_path: Path) -> None:
    path = (tmp_path / "out").with_suffix(SUFFIX[writer])
    path.write_bytes(OLD)
    os.chmod(path, 0o640)
    WRITERS[writer](tmp_path / "out")
    assert path.read_bytes() != OLD and path.stat().st_size > 100
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]  # no temporary left
    assert path.stat().st_mode & 0o777 == 0o640  # the file's permissions are kept


@pytest.mark.parametrize("writer", sorted(WRITERS))
def test_a_failed_write_leaves_the_previous_file(writer: str, tmp_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    """The disk fills up as the file is flushed: the writer raises OSError naming the
    destination, the previous file is intact and no partial file is left."""
    path = (tmp_path / "out").with_suffix(SUFFIX[writer])
    path.write_bytes(OLD)

    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)  # every write is flushed to disk before it counts
    with pytest.raises(OSError, match="No space left") as caught:
        WRITERS[writer](tmp_path / "out")
    assert str(path) in str(caught.value)
    assert path.read_bytes() == OLD
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


@pytest.mark.parametrize("writer", sorted(WRITERS))
def test_a_writer_refuses_a_missing_folder_and_a_folder(writer: str, tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="does not exist"):
        WRITERS[writer](tmp_path / "no-such-folder" / "out")
    folder = (tmp_path / "out").with_suffix(SUFFIX[writer])
    folder.mkdir()
    with pytest.raises(IsADirectoryError, match="it is a folder"):
        WRITERS[writer](tmp_path / "out")
    assert sorted(p.name for p in tmp_path.iterdir()) == [folder.name]


def test_a_symbolic_link_is_kept_and_its_target_replaced(tmp_path: Path) -> None:
    target = tmp_path / "real.nc"
    target.write_bytes(OLD)
    link = tmp_path / "link.nc"
    link.symlink_to(target)
    dz.save(TRAJ, link)
    assert link.is_symlink() and isinstance(dz.load(link), dz.Trajectory)
    assert target.read_bytes()[:4] == b"\x89HDF"


def test_a_figure_refuses_a_save_that_is_no_path(tmp_path: Path) -> None:
    """`path_figure(save=3)` ended in an AttributeError inside matplotlib."""
    with pytest.raises(TypeError, match="`save` must be a file path"):
        dz.plotting.path_figure(TRAJ, save=3)
    import io

    buffer = io.BytesIO()  # a file object is written to directly
    dz.plotting.path_figure(TRAJ, save=buffer)
    assert buffer.getvalue()[:4] == b"\x89PNG"


FULL_DISK = textwrap.dedent("""
    import os, resource, signal, sys
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit: EFBIG
    import dzhanibekov as dz
    folder = sys.argv[1]
    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=100.0, frames=20001)
    calls = {
        "save": lambda p: dz.save(traj, p + ".nc"),
        "write_aem": lambda p: dz.io.write_aem(traj, p + ".aem", "B", "1",
                                               "2026-01-01T00:00:00", ref_frame_a="ICRF"),
        "Scene.save": lambda p: dz.SCENES["fig3a"].save(p + ".toml"),
    }
    limits = {"save": 200_000, "write_aem": 200_000, "Scene.save": 100}
    for name, call in calls.items():
        base = os.path.join(folder, name)
        ext = {"save": ".nc", "write_aem": ".aem", "Scene.save": ".toml"}[name]
        with open(base + ext, "w") as f:
            f.write("old")
        resource.setrlimit(resource.RLIMIT_FSIZE, (limits[name], resource.RLIM_INFINITY))
        try:
            call(base)
            outcome = "RETURNED"
        except OSError as exc:
            outcome = "OSError " + str(exc).replace(chr(10), " ")[:150]
        resource.setrlimit(resource.RLIMIT_FSIZE, (resource.RLIM_INFINITY,) * 2)
        import gc
        gc.collect()  # h5netcdf closed its half-written file again here, and crashed
        intact = open(base + ext).read() == "old"
        print(name, "|", outcome, "|", "intact" if intact else "REPLACED", flush=True)
    print("left:", sorted(os.listdir(folder)))
""")


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_FSIZE as on Linux")
def test_a_full_disk_leaves_the_previous_file_and_the_interpreter_alive(tmp_path: Path) -> None:
    """A file-size limit fails a write as a full disk does (EFBIG for ENOSPC). `dz.save`
    replaced the previous file with a partial one, raised OSError, then the interpreter died
    with SIGSEGV (exit -11) when h5netcdf closed the half-written HDF5 file a second time;
    `write_aem` left a partial file."""
    done = subprocess.run([sys.executable, "-c", FULL_DISK, str(tmp_path)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, (done.returncode, done.stdout, done.stderr[-2000:])
    lines = done.stdout.strip().splitlines()
    for line in lines[:-1]:
        name, outcome, intact = (part.strip() for part in line.split("|"))
        assert outcome.startswith("OSError") and "too large" in outcome.lower(), line
        assert intact == "intact", line
    assert lines[-1] == "left: ['Scene.save.toml', 'save.nc', 'write_aem.aem']", lines[-1]


SIGINT_SAVE = textwrap.dedent("""
    import os, signal, sys, threading, time
    import dzhanibekov as dz
    folder, delays = sys.argv[1], [float(x) for x in sys.argv[2].split(",")]
    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=100.0, frames=10**6)
    path = os.path.join(folder, "run.nc")
    dz.save(traj, os.path.join(folder, "warm.nc"))  # imports and first-call costs
    for delay in delays:
        with open(path, "w") as f:
            f.write("old")
        sent, done = threading.Event(), threading.Event()
        def fire():
            if not done.wait(delay):
                sent.set()
                os.kill(os.getpid(), signal.SIGINT)
        thread = threading.Thread(target=fire)
        outcome = "none"
        try:
            try:
                thread.start()
                outcome = "started"
                dz.save(traj, path)
                outcome = "completed"
            except KeyboardInterrupt:
                outcome = "interrupted"
            done.set()
            thread.join()
        except KeyboardInterrupt:  # the signal came after the save had returned
            outcome += "+late"
            done.set()
            thread.join()
        if open(path, "rb").read() == b"old":
            state = "intact"
        else:
            state = "whole" if isinstance(dz.load(path), dz.Trajectory) else "broken"
        left = sorted(set(os.listdir(folder)) - {"run.nc", "warm.nc"})
        print(delay, outcome, sent.is_set(), state, left, flush=True)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to oneself")
def test_ctrl_c_during_a_save_interrupts_it_and_keeps_the_previous_file(tmp_path: Path) -> None:
    """Three of six SIGINTs during `dz.save` were swallowed ("Exception ignored in
    WeakValueDictionary": h5py runs code in weak-reference callbacks, where an exception is
    only printed) and the save went on to replace the file; the others left a partial file.
    Now a SIGINT that arrives while the save runs interrupts it, and the previous file is
    intact (or, if it came after the new file was in place, that file is whole)."""
    delays = ",".join(str(d) for d in np.linspace(0.01, 0.2, 8).round(3))
    done = subprocess.run([sys.executable, "-c", SIGINT_SAVE, str(tmp_path), delays],
                          capture_output=True, text=True, timeout=180)
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
    interrupted = 0
    for line in done.stdout.strip().splitlines():
        delay, outcome, sent, state, left = line.split(" ", 4)
        assert left == "[]" and state != "broken", line
        if outcome in ("interrupted", "none+late"):  # in the save, or before it began
            interrupted += outcome == "interrupted"
            assert state in ("intact", "whole"), line
        else:  # completed: no signal, or one that came after the save returned
            assert outcome in ("completed", "completed+late"), line
            assert sent == "False" or outcome.endswith("+late"), f"swallowed: {line}"
            assert state == "whole", line
    assert interrupted >= 3, done.stdout  # a save of 64 MB takes longer than 0.1 s


# -- readers: no regular file -------------------------------------------------------------


def _readers() -> dict[str, Callable[[Path], Any]]:
    return {"load": dz.load, "read_aem": dz.io.read_aem, "load_scene": dz.load_scene,
            "Body.load": dz.Body.load}


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs")
@pytest.mark.parametrize("reader", sorted(_readers()))
def test_a_fifo_is_refused_at_once(reader: str, tmp_path: Path) -> None:
    """`dz.load` and `read_aem` of a FIFO blocked for ever waiting for a writer. (Run in a
    daemon thread: a reader that blocks fails the test rather than hanging it.)"""
    import threading

    if reader == "Body.load":
        pytest.importorskip("trimesh")
    fifo = tmp_path / "pipe.nc"
    os.mkfifo(fifo)
    caught: list[BaseException] = []

    def read() -> None:
        try:
            _readers()[reader](fifo)
        except BaseException as exc:  # noqa: BLE001 - inspected below
            caught.append(exc)

    thread = threading.Thread(target=read, daemon=True)
    thread.start()
    thread.join(20.0)
    assert not thread.is_alive(), f"{reader} blocked on a FIFO"
    assert caught and isinstance(caught[0], ValueError), caught
    assert "FIFO" in str(caught[0]) and str(fifo) in str(caught[0]), caught[0]


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
@pytest.mark.parametrize("reader", sorted(_readers()))
def test_dev_zero_and_a_folder_are_refused(reader: str, tmp_path: Path) -> None:
    if reader == "Body.load":
        pytest.importorskip("trimesh")
    for path, kind in (("/dev/zero", "a device"), (str(tmp_path), "a folder")):
        with pytest.raises(ValueError, match=kind):
            _readers()[reader](path)


# -- killed writers -----------------------------------------------------------------------

KILLED_SAVE = textwrap.dedent("""
import os, signal, sys
import h5py
import numpy as np
import dzhanibekov as dz
path, how = sys.argv[1], sys.argv[2]
traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=10.0, frames=11, dt=1e-2)
real = h5py.Group.create_dataset

def create_dataset(self, *args, **kwargs):  # the signal comes in the middle of the write
    os.kill(os.getpid(), getattr(signal, how))
    return real(self, *args, **kwargs)

h5py.Group.create_dataset = create_dataset
dz.save(traj, path)
print("returned")
""")


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_sigterm_during_a_save_leaves_nothing_and_ends_the_process(tmp_path: Path) -> None:
    """SIGTERM during `dz.save` ended the process with the hidden `.partial.nc` beside the file
    (2 times in 3). Now it stops the write as Ctrl-C does, the temporary file is removed, and
    the process ends by SIGTERM all the same; the previous file is intact."""
    path = tmp_path / "run.nc"
    path.write_bytes(OLD)
    done = subprocess.run([sys.executable, "-c", KILLED_SAVE, str(path), "SIGTERM"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == -signal.SIGTERM, (done.returncode, done.stdout, done.stderr)
    assert "returned" not in done.stdout
    assert sorted(os.listdir(tmp_path)) == ["run.nc"]
    assert path.read_bytes() == OLD


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_the_next_save_removes_what_a_killed_save_left(tmp_path: Path) -> None:
    """SIGKILL cannot be handled: the killed save leaves its temporary file, named for its
    host and process. The next write to the same path removes it (its process is gone), and
    leaves another path's and a live process's alone."""
    path = tmp_path / "run.nc"
    done = subprocess.run([sys.executable, "-c", KILLED_SAVE, str(path), "SIGKILL"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == -signal.SIGKILL, (done.returncode, done.stderr)
    [left] = [n for n in os.listdir(tmp_path) if n.endswith(".partial.nc")]
    assert left.startswith(".run.nc.")
    live = tmp_path / (dz._files.partial_prefix("run.nc") + "x.partial.nc")  # this process
    other = tmp_path / left.replace(".run.nc.", ".other.nc.", 1)  # another path's
    live.write_bytes(b"")
    other.write_bytes(b"")
    dz.save(TRAJ, path)
    assert sorted(os.listdir(tmp_path)) == sorted(["run.nc", live.name, other.name])
    assert isinstance(dz.load(path), dz.Trajectory)


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_the_next_run_into_a_folder_removes_what_a_killed_run_left(tmp_path: Path) -> None:
    """`dzhanibekov run … --out` killed in its figures (an abort, exit 134, under a memory
    limit) left its `.partial-*` folder in `--out`; the next run into the folder removes it."""
    out = tmp_path / "out"
    child = textwrap.dedent("""
        import os, signal, sys
        from pathlib import Path
        from dzhanibekov.render import output_folder
        with output_folder(sys.argv[1]) as tmp:
            (Path(tmp) / "fig.png").write_bytes(b"half")
            os.kill(os.getpid(), signal.SIGKILL)
    """)
    done = subprocess.run([sys.executable, "-c", child, str(out)], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == -signal.SIGKILL, done.stderr
    [left] = os.listdir(out)
    assert left.startswith(".partial.") and (out / left / "fig.png").exists()
    from dzhanibekov.render import output_folder

    with output_folder(out) as tmp:
        (tmp / "fig.png").write_bytes(b"whole")
    assert sorted(os.listdir(out)) == ["fig.png"]
