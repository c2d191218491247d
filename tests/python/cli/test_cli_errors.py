"""The command line where its output cannot be written: one line on stderr naming the path and
the cause, exit code 2, and the destination exactly as it was (issues 11, 15 and 16)."""

from __future__ import annotations

import contextlib
import json
import os
import queue
import re
import resource
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import NoReturn

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov.cli import main
from dzhanibekov.render import MAX_JSON_FLIP_TIMES, output_folder
from dzhanibekov.scenes.scene import Draw


def tiny_scene(folder: Path, name: str = "mine") -> Path:
    """A scene that renders fast: a short run drawing one figure."""
    scene = dz.SCENES["fig3a"].replace(t_end=10.0, frames=21,
                                       draw=Draw(figures=("omega",)))
    return scene.save(folder / f"{name}.toml")


def snapshot(folder: Path) -> dict[str, bytes | None]:
    """Every entry below `folder` with its bytes (None for folders)."""
    return {str(p.relative_to(folder)): None if p.is_dir() else p.read_bytes()
            for p in sorted(folder.rglob("*"))}


def one_line_error(err: str, *fragments: str) -> None:
    """`err` is one line of error (after the progress lines "[k/n] …" of what was drawn)."""
    lines = [line for line in err.strip().splitlines() if not re.match(r"\[ *\d+/\d+\] ", line)]
    assert len(lines) == 1, f"not one line: {err!r}"
    assert lines[0].startswith("dzhanibekov: error: "), err
    assert "Traceback" not in err
    for fragment in fragments:
        assert fragment in lines[0], (fragment, err)


def run_cli(argv: list[str], **kwargs) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "dzhanibekov", *argv], capture_output=True,
                          text=True, timeout=120, **kwargs)


def test_out_below_a_file_is_one_line(tmp_path, capsys):
    scene = tiny_scene(tmp_path)
    (tmp_path / "plain").write_text("x")
    out = tmp_path / "plain" / "figures"
    assert main(["run", str(scene), "--out", str(out), "--no-progress"]) == 2
    one_line_error(capsys.readouterr().err, str(tmp_path / "plain"), "is a file")
    assert (tmp_path / "plain").read_text() == "x"


def test_out_as_a_dangling_symlink_is_one_line(tmp_path, capsys):
    scene = tiny_scene(tmp_path)
    out = tmp_path / "link"
    out.symlink_to(tmp_path / "gone")
    assert main(["run", str(scene), "--out", str(out), "--no-progress"]) == 2
    one_line_error(capsys.readouterr().err, str(out), "does not exist")
    assert out.is_symlink() and not (tmp_path / "gone").exists()


def test_out_as_a_file_is_one_line_and_the_file_is_kept(tmp_path, capsys):
    scene = tiny_scene(tmp_path)
    (tmp_path / "file").write_text("mine")
    assert main(["run", str(scene), "--out", str(tmp_path / "file"), "--no-progress"]) == 2
    one_line_error(capsys.readouterr().err, str(tmp_path / "file"), "must be a folder")
    assert (tmp_path / "file").read_text() == "mine"


def test_a_folder_named_like_an_output_leaves_every_file_as_it_was(tmp_path, capsys):
    """The old behaviour: earlier outputs were replaced, then the folder made a traceback."""
    scene = tiny_scene(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine-omega.png").write_bytes(b"old")   # replaced first, alphabetically
    (out / "mine.json").mkdir()                    # in the way of the last output
    (out / "mine.json" / "inner.txt").write_text("keep")
    before = snapshot(out)
    assert main(["run", str(scene), "--out", str(out), "--no-progress"]) == 2
    one_line_error(capsys.readouterr().err, str(out / "mine.json"), "folder")
    assert snapshot(out) == before


def test_the_temporary_folder_is_inside_the_destination(tmp_path):
    """So it is on the destination's filesystem: a mount point as `--out` works."""
    out = tmp_path / "out"
    with output_folder(out) as tmp:
        assert tmp.parent == out
        (tmp / "a.txt").write_text("a")
    assert [p.name for p in out.iterdir()] == ["a.txt"]
    with pytest.raises(KeyError):
        with output_folder(tmp_path / "new" / "deeper") as tmp:
            (tmp / "a.txt").write_text("a")
            raise KeyError("stop")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"], "created folders stay"


@pytest.fixture
def tiny_filesystem(tmp_path):
    """A 2 MiB tmpfs mounted at `tmp_path / "mnt"` (root only; skipped elsewhere)."""
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(mnt)],
                          capture_output=True)
    if done.returncode != 0:
        pytest.skip("cannot mount a tmpfs here (needs root)")
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], check=False)


def test_a_mount_point_as_out_is_written(tiny_filesystem, tmp_path):
    scene = tiny_scene(tmp_path)
    done = run_cli(["run", str(scene), "--out", str(tiny_filesystem), "--no-progress"])
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in tiny_filesystem.iterdir()) == ["mine-omega.png", "mine.json"]


def test_a_full_disk_is_one_line_and_the_old_files_are_kept(tiny_filesystem, tmp_path):
    scene = tiny_scene(tmp_path)
    out = tiny_filesystem / "out"
    out.mkdir()
    (out / "mine.json").write_text("old")
    (tiny_filesystem / "filler").write_bytes(b"\0" * (2 * 1024 * 1024 - 64 * 1024))
    with open(tiny_filesystem / "filler", "ab") as f:  # fill the last pages
        try:
            f.write(b"\0" * (1 << 20))
        except OSError:
            pass
    before = snapshot(out)
    done = run_cli(["run", str(scene), "--out", str(out), "--no-progress"])
    assert done.returncode == 2
    one_line_error(done.stderr, str(out), "No space left on device")
    assert snapshot(out) == before


def limit_file_size() -> None:
    resource.setrlimit(resource.RLIMIT_FSIZE, (1500, 1500))


def test_a_file_size_limit_is_one_line_and_the_old_files_are_kept(tmp_path):
    """`ulimit -f`: the figure (~50 kB) cannot be written; Python ignores SIGXFSZ, so the
    write fails with EFBIG."""
    scene = tiny_scene(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine-omega.png").write_bytes(b"old")
    before = snapshot(out)
    done = run_cli(["run", str(scene), "--out", str(out), "--no-progress"],
                   preexec_fn=limit_file_size)
    assert done.returncode == 2, done.stderr
    one_line_error(done.stderr, str(out / "mine-omega.png"), "File too large")
    assert snapshot(out) == before


def test_a_read_only_out_is_one_line_and_nothing_is_written(tmp_path):
    """Root ignores permissions: it gets a read-only filesystem instead (a tmpfs remounted
    read-only); anyone else a folder without write permission."""
    scene = tiny_scene(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine.json").write_text("old")
    if os.geteuid() == 0:
        if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(out)],
                          capture_output=True).returncode != 0:
            pytest.skip("cannot mount a tmpfs here")
        (out / "mine.json").write_text("old")
        subprocess.run(["mount", "-o", "remount,ro", str(out)], check=True)
        cause = "Read-only file system"
    else:
        os.chmod(out, 0o555)
        cause = "Permission denied"
    try:
        before = snapshot(out)
        done = run_cli(["run", str(scene), "--out", str(out), "--no-progress"])
        assert done.returncode == 2, done.stderr
        one_line_error(done.stderr, str(out), cause)
        assert snapshot(out) == before
    finally:
        if os.geteuid() == 0:
            subprocess.run(["umount", "-l", str(out)], check=False)
        else:
            os.chmod(out, 0o755)


def test_a_long_flip_list_is_summarised_and_written_in_full_only_when_asked(tmp_path, capsys):
    """A long exact run (more flips than the JSON lists): count, first, last and mean
    spacing in the JSON; every flip time in the .npy with `--flip-times`."""
    scene = dz.SCENES["fig3a"].replace(method="exact", t_end=2e5, frames=2,
                                       draw=Draw())
    path = scene.save(tmp_path / "long.toml")
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--no-progress"]) == 0
    about = json.loads((out / "long.json").read_text())
    assert about["flip_times"] is None and "flip_times_file" not in about
    flips = about["flips"]
    period = dz.flip_period(scene.inertia, scene.omega0)  # a flip (over and back) a period
    n = flips["count"]
    assert n > MAX_JSON_FLIP_TIMES
    assert abs(n - scene.t_end / period) <= 2
    assert flips["mean_spacing"] == pytest.approx(period, rel=1e-6)
    assert 0 < flips["first"] <= period and scene.t_end - period <= flips["last"]
    assert sorted(p.name for p in out.iterdir()) == ["long.json"]

    assert main(["run", str(path), "--out", str(out), "--no-progress", "--flip-times"]) == 0
    about = json.loads((out / "long.json").read_text())
    assert about["flip_times_file"] == "long-flip-times.npy"
    times = np.load(out / "long-flip-times.npy")
    assert len(times) == n and times[0] == flips["first"] and times[-1] == flips["last"]
    assert np.all(np.diff(times) > 0)
    capsys.readouterr()


def test_a_short_flip_list_is_listed_in_full(tmp_path):
    path = tiny_scene(tmp_path)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--no-progress"]) == 0
    about = json.loads((out / "mine.json").read_text())
    assert about["flips"]["count"] == len(about["flip_times"])


class Guarded(np.ndarray):
    """Flip times that may not be walked through: a table that lists them all fails."""

    def __iter__(self):
        if len(self) > 4:
            raise AssertionError("walked through every flip time")
        return super().__iter__()

    def tolist(self):
        if len(self) > 4:
            raise AssertionError("listed every flip time")
        return super().tolist()


def test_the_table_reads_only_what_it_prints():
    """Issue 25: `list(r.flip_times)` of 9.2·10⁷ flips took 30 s and 4.4 GB to print four."""
    from types import SimpleNamespace

    from dzhanibekov.cli import _table
    from dzhanibekov.plotting.figures import compute

    real = compute(dz.SCENES["fig3a"])
    # 10¹² flip times that take no memory (one number, seen 10¹² times)
    times = np.lib.stride_tricks.as_strided(np.array([0.5]), shape=(10**12,),
                                            strides=(0,)).view(Guarded)
    fake = SimpleNamespace(scene=real.scene, trajectory=real.trajectory, summary=None,
                           flip_times=times, drift=real.drift)
    text = _table([fake], 1.0)
    row = text.splitlines()[1]
    assert " 1000000000000  " in row and "0.500, 0.500, 0.500, 0.500, …" in row


def test_the_tables_columns_line_up_past_long_flip_times():
    """A deployment's first four flips (112.117, 122.212, …, and "…") ran past the flip
    column and pushed its drift out from under the header."""
    from types import SimpleNamespace

    from dzhanibekov.cli import _table
    from dzhanibekov.plotting.figures import compute

    real = compute(dz.SCENES["fig3a"])
    long = np.array([112.117, 122.212, 1132.306, 1142.401, 1150.0])
    fake = SimpleNamespace(scene=real.scene, trajectory=real.trajectory, summary=None,
                           flip_times=long, drift=real.drift)
    head, short, wide = _table([real, fake], 1.0).splitlines()[:3]
    assert "1142.401, …" in wide
    # the drift starts under its header in every row, whatever the flips' width
    start = head.index("drift of what the model keeps")
    for row in (short, wide):
        assert row[start:].startswith(f"dE/E {real.drift.energy:.1e} "), row
        assert f"d|q| {real.drift.q_norm:.1e}" in row[start:], row


def test_the_table_names_what_each_model_keeps_and_what_it_changes():
    """Issue 33: the table showed every invariant as a drift (the gravity gradient's energy
    1.4e-1, a deployment's 5.0e-1, as if errors), not the Jacobi integral the model keeps,
    and '?' for flips a scene did not ask for."""
    from dzhanibekov.cli import _table
    from dzhanibekov.plotting.figures import compute

    orbit = compute(dz.SCENES["gravity-gradient"])
    assert orbit.flip_times is None and orbit.drift.jacobi is not None
    head, row, *legend = _table([orbit], 1.0).splitlines()
    kept = row[head.index("drift of what the model keeps"):head.index("changed by the model")]
    changed = row[head.index("changed by the model"):]
    assert f"dJ/J {orbit.drift.jacobi:.1e}" in kept and f"d|q| {orbit.drift.q_norm:.1e}" in kept
    assert "E/E" not in kept and "|L|/|L|" not in kept
    assert f"ΔE/E {orbit.drift.energy:.1e}" in changed
    assert f"Δ|L|/|L| {orbit.drift.momentum:.1e}" in changed
    assert "?" not in row and row.split()[2] == "-"
    assert any("flips -: not located" in line for line in legend)


def test_a_body_started_at_rest_has_its_change_printed_absolute():
    """A wheel slew starts at rest (E(0) = 0, L = 0): the table printed `ΔE/E 4.1e-03`, a
    change relative to zero. The drift of a measure that starts at zero is absolute (the
    core's rule), and the table now says so by leaving out the `/`."""
    from dzhanibekov.cli import _table
    from dzhanibekov.plotting.figures import compute

    slew = compute(dz.SCENES["slew"])
    energy = slew.trajectory.energy
    assert energy[0] == 0.0 and not np.any(slew.trajectory.invariants()["momentum_body"][0])
    head, row, *legend = _table([slew], 1.0).splitlines()
    changed = row[head.index("changed by the model"):]
    # the printed change is the largest energy over the frames, in joules, not a ratio
    assert f"ΔE {np.max(np.abs(energy)):.1e}" in changed and "E/E" not in row
    assert "d|L| " in row and "|L|/|L|" not in row
    assert any("absolute" in line for line in legend)


def test_a_failure_after_the_run_leaves_nothing_written(tmp_path, monkeypatch, capsys):
    """Issue 25: the table came after the output was moved into `--out`, so "out of memory;
    nothing written" (or "interrupted; nothing written") was false: the JSON was there."""
    import dzhanibekov.cli as cli

    scene = tiny_scene(tmp_path)
    out = tmp_path / "out"
    for failure, code, says in ((MemoryError, 2, "out of memory; nothing written"),
                                (KeyboardInterrupt, 130, "interrupted; nothing written")):
        def table(*args, failure=failure):
            raise failure()

        monkeypatch.setattr(cli, "_table", table)
        assert main(["run", str(scene), "--out", str(out), "--no-progress"]) == code
        assert says in capsys.readouterr().err
        assert not out.exists()


def test_ctrl_c_while_the_files_move_in_waits_for_all_of_them(tmp_path, monkeypatch, capsys):
    """Ctrl-C half-way through moving the files in left some replaced and said "nothing
    written"; now the move finishes and the message says every file is there."""
    import signal

    import dzhanibekov.render as render

    scene = tiny_scene(tmp_path)
    out = tmp_path / "out"
    real = os.replace
    calls = []

    def replace(source, target):
        # the files' own atomic writes into the temporary folder rename too: count only the
        # moves into `out`
        if Path(target).parent == out:
            calls.append(target)
            if len(calls) == 1:
                os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C, as the first file moves in
        real(source, target)

    monkeypatch.setattr(render.os, "replace", replace)
    assert main(["run", str(scene), "--out", str(out), "--no-progress"]) == 130
    err = capsys.readouterr().err
    assert f"interrupted; every file was written to {out}" in err
    assert sorted(p.name for p in out.iterdir()) == ["mine-omega.png", "mine.json"]
    assert len(calls) == 2


def test_a_failure_in_a_drawing_process_is_one_line_and_nothing_is_written(tmp_path):
    """`paper` draws in worker processes: a file they cannot write (`ulimit -f`) is reported
    as in one process, and `--out` is left as it was."""
    out = tmp_path / "out"
    done = run_cli(["paper", "--out", str(out), "--no-progress", "--no-animation", "--jobs",
                    "2"], preexec_fn=limit_file_size)
    assert done.returncode == 2, done.stderr
    one_line_error(done.stderr, "File too large", ".png")
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == []


def assert_none_left(mark: str) -> None:
    """No process marked `mark` is left within 10 s (the killed ones take a moment to go)."""
    deadline = time.monotonic() + 10
    while processes_marked(f"DZ_TEST_MARK={mark}") and time.monotonic() < deadline:
        time.sleep(0.1)
    assert processes_marked(f"DZ_TEST_MARK={mark}") == []


def processes_marked(mark: str) -> list[int]:
    """The processes whose environment holds `mark`."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if mark.encode() in (entry / "environ").read_bytes():
                    found.append(int(entry.name))
            except OSError:
                pass
    return found


class Child:
    """A command run in its own process group, its stderr read line by line by a thread, so
    that every wait on it has a timeout: one that runs out dumps the command's threads
    (faulthandler, on SIGABRT), kills its group and fails the test with all it printed."""

    def __init__(self, argv: list[str], env: dict[str, str]) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "dzhanibekov", *argv], stderr=subprocess.PIPE,
            stdout=subprocess.DEVNULL, text=True, env=dict(env, PYTHONFAULTHANDLER="1"),
            start_new_session=True)
        self.said: list[str] = []
        self.lines: queue.Queue[str | None] = queue.Queue()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.proc.stderr is not None
        for line in self.proc.stderr:
            self.lines.put(line)
        self.lines.put(None)

    def line(self, seconds: float, why: str) -> str | None:
        """The next line on stderr (None: stderr closed); fails saying `why` after
        `seconds`."""
        try:
            line = self.lines.get(timeout=max(0.0, seconds))
        except queue.Empty:
            line = ""  # a line read is never empty
        if line == "":
            self.fail(why)
        if line is not None:
            self.said.append(line)
        return line

    def end(self, seconds: float, why: str) -> tuple[int, str]:
        """The exit code and the rest of stderr, within `seconds` (stderr closes when the
        command and every process it started have ended)."""
        deadline = time.monotonic() + seconds
        start = len(self.said)
        while self.line(deadline - time.monotonic(), why) is not None:
            pass
        try:
            code = self.proc.wait(timeout=max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            code = None
        if code is None:
            self.fail(why)
        return code, "".join(self.said[start:])

    def fail(self, why: str) -> NoReturn:
        with contextlib.suppress(OSError):
            resource.prlimit(self.proc.pid, resource.RLIMIT_CORE, (0, 0))  # no core file
        with contextlib.suppress(ProcessLookupError):
            os.kill(self.proc.pid, signal.SIGABRT)  # its threads' stacks, on stderr
        with contextlib.suppress(subprocess.TimeoutExpired):
            self.proc.wait(timeout=10)
        self.kill()
        with contextlib.suppress(queue.Empty):
            while (line := self.lines.get(timeout=5)) is not None:
                self.said.append(line)
        pytest.fail(f"{why}; the command printed:\n{''.join(self.said)}")

    def kill(self) -> None:
        """Ends the command and every process it started."""
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.proc.pid, signal.SIGKILL)
        self.proc.wait()
        self.reader.join(timeout=10)  # at the end of stderr, now that its writers are dead
        if not self.reader.is_alive():
            assert self.proc.stderr is not None
            self.proc.stderr.close()


@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="needs /proc")
def test_ctrl_c_during_paper_ends_its_drawing_processes_and_writes_nothing(tmp_path):
    """Ctrl-C once the drawing processes are busy: exit code 130, one line, no output, and no
    process left. Each wait has a timeout (the command once hung here for ever)."""
    out = tmp_path / "out"
    mark = f"{os.getpid()}-{time.monotonic_ns()}"
    child = Child(["paper", "--out", str(out), "--no-progress", "--no-animation", "--jobs",
                   "2"], dict(os.environ, DZ_TEST_MARK=mark))
    try:
        first = child.line(300, "no drawing done in 300 s")  # now the workers are busy
        assert first is not None and first.startswith("[ 1/"), first
        assert len(processes_marked(f"DZ_TEST_MARK={mark}")) >= 3  # this one, two workers
        child.proc.send_signal(signal.SIGINT)
        code, rest = child.end(60, "still running 60 s after Ctrl-C")
        assert code == 130, rest
        assert "dzhanibekov: interrupted; nothing written" in rest and "Traceback" not in rest
        assert not out.exists()
        assert_none_left(mark)
    finally:
        child.kill()


def drawing_processes(parent: int) -> list[int]:
    """The worker processes `parent` spawned (not multiprocessing's resource tracker)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                status = (entry / "status").read_text()
                cmdline = (entry / "cmdline").read_bytes()
            except OSError:
                continue
            if f"\nPPid:\t{parent}\n" in status and b"spawn_main" in cmdline:
                found.append(int(entry.name))
    return found


@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="needs /proc")
def test_a_drawing_process_killed_by_the_system_is_one_line_and_nothing_is_written(tmp_path):
    """A worker killed from outside (the OOM killer, a user's kill -9) ends `paper` with one
    line naming the signal, exit code 2, no output and no process left; it does not wait for
    the lost drawing for ever."""
    out = tmp_path / "out"
    mark = f"{os.getpid()}-{time.monotonic_ns()}"
    child = Child(["paper", "--out", str(out), "--no-progress", "--no-animation", "--jobs",
                   "2"], dict(os.environ, DZ_TEST_MARK=mark))
    try:
        first = child.line(300, "no drawing done in 300 s")
        assert first is not None and first.startswith("[ 1/"), first
        workers = drawing_processes(child.proc.pid)
        assert len(workers) == 2, workers
        os.kill(workers[0], signal.SIGKILL)
        code, rest = child.end(60, "still running 60 s after a worker was killed")
        assert code == 2, rest
        one_line_error(rest, "was killed by SIGKILL before it was done")
        assert not out.exists()
        assert_none_left(mark)
    finally:
        child.kill()
