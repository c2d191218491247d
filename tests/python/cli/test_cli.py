"""The command line end to end, in a temporary folder: the files it promises exist and are
not blank; bad scenes are refused with a clear message and leave nothing behind."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import dzhanibekov as dz
from dzhanibekov.plotting import movie
from dzhanibekov.plotting import figures as plotting
from dzhanibekov.cli import main
from dzhanibekov.render import PAPER_RENDER
from pictures import assert_picture


def test_paper_renders_every_figure_and_the_animation(tmp_path, capsys):
    out = tmp_path / "figures"
    # small GIFs (their frame counts are what is checked here; sizes in test_bodies)
    assert main(["paper", "--out", str(out), "--no-progress", "--gif-size", "128"]) == 0
    expected = {"fig3.png", "stable.png", "example.gif"}
    expected.add("wing-nut.gif")  # the paper's Fig. 1
    for name in list(dz.PAPER_SCENES) + ["wing-nut", "stable-largest", "stable-smallest"]:
        expected |= {f"{name}-{f}.png" for f in dz.SCENES[name].draw.figures} | {f"{name}.json"}
    for name in dz.scenes.STORY_SCENES:  # bodies that change: a deployment, Explorer 1
        expected |= {f"{name}-{f}.png" for f in dz.SCENES[name].draw.figures}
        expected |= {f"{name}.json", f"{name}.gif"}
    if movie.ffmpeg_path() is not None:
        expected |= {"example.mp4", "wing-nut.mp4"} | {f"{n}.mp4" for n in dz.scenes.STORY_SCENES}
    assert {p.name for p in out.iterdir()} == expected
    for path in out.glob("*.png"):
        assert_picture(path)
    for name in dz.SCENES:
        if not dz.SCENES[name].draw.animation:
            continue
        with Image.open(out / f"{name}.gif") as gif:
            # no more frames than the budget (they were 641 to 901), and no fewer than it
            # takes to turn the body at most 10° from one to the next
            scene = dz.SCENES[name]
            rate = np.linalg.norm(scene.run().omega, axis=1).max()
            needed = np.ceil(rate * scene.t_end / np.radians(10.0)) + 1
            assert gif.n_frames == min(movie.MAX_FRAMES, needed)
    summary = json.loads((out / "fig3a.json").read_text())
    assert summary["verdict"] == "2 flips in [0, 100]" and len(summary["flip_times"]) == 2
    assert json.loads((out / "stable-largest.json").read_text())["flip_times"] == []
    captured = capsys.readouterr()
    table = captured.out
    for name in PAPER_RENDER:
        assert name in table
    # a line on stderr as each scene's figures and each animation are done (not a terminal:
    # no bars), counted; the table comes after them, on stdout
    lines = captured.err.strip().splitlines()
    tasks = len(PAPER_RENDER) + 2 + sum(dz.SCENES[n].draw.animation for n in PAPER_RENDER)
    assert len(lines) == tasks and lines[-1].startswith(f"[{tasks}/{tasks}] ")
    for name in PAPER_RENDER:
        assert any(line.split("] ", 1)[1].startswith(f"{name}: ") for line in lines), name
    assert sum("animation" in line and ".gif" in line for line in lines) == \
        sum(dz.SCENES[n].draw.animation for n in PAPER_RENDER)
    # nothing else beside the output folder: the temporary one is gone; and the folder has
    # the usual mode, not the temporary folder's 0700
    assert [p.name for p in tmp_path.iterdir()] == ["figures"]
    umask = os.umask(0)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o777 & ~umask


def test_run_renders_a_scene_file(tmp_path, capsys):
    scene = dz.SCENES["fig3a"].replace(t_end=30.0, frames=61)
    path = scene.save(tmp_path / "mine.toml")
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 0
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted([f"mine-{f}.png" for f in scene.draw.figures] + ["mine.json"])
    for png in out.glob("*.png"):
        assert_picture(png)
    assert "mine.json" in capsys.readouterr().out


def test_run_takes_a_shipped_scene_by_name_and_replaces_files_in_place(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    (out / "fig3b-omega.png").write_text("stale")
    assert main(["run", "fig3b", "--out", str(out)]) == 0
    assert (out / "keep.txt").read_text() == "mine"
    assert_picture(out / "fig3b-omega.png")


@pytest.mark.parametrize("name", ["gravity-gradient", "dual-spin", "spin-up"])
def test_run_renders_the_orbit_scenes(name, tmp_path):
    out = tmp_path / "out"
    assert main(["run", name, "--out", str(out), "--no-progress"]) == 0
    expected = {f"{name}-{f}.png" for f in dz.SCENES[name].draw.figures} | {f"{name}.json"}
    assert {p.name for p in out.iterdir()} == expected
    for path in out.glob("*.png"):
        assert_picture(path)


def test_a_bad_scene_file_is_named_with_its_key_and_nothing_is_written(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(dz.SCENES["fig3a"].to_toml().replace('method = "rk4"', 'method = "rk5"'))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{path}: `run.method` must be one of {list(dz.METHODS)}, got 'rk5'" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_a_failure_while_rendering_leaves_the_folder_as_it_was(tmp_path, monkeypatch, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "fig3a-path.png").write_bytes(b"old")

    def broken(*args, **kwargs):
        raise ValueError("the plot broke")

    # the first figures are written into the temporary folder, then one fails
    monkeypatch.setitem(plotting.FIGURE_FUNCTIONS, "invariants", broken)
    assert main(["run", "fig3a", "--out", str(out)]) == 2
    assert "the plot broke" in capsys.readouterr().err
    assert [p.name for p in out.iterdir()] == ["fig3a-path.png"]
    assert (out / "fig3a-path.png").read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_out_must_be_a_folder(tmp_path, capsys):
    (tmp_path / "file").write_text("")
    assert main(["run", "fig3a", "--out", str(tmp_path / "file")]) == 2
    assert "`--out` must be a folder" in capsys.readouterr().err


def test_scenes_lists_and_shows_the_shipped_scenes(capsys, tmp_path):
    assert main(["scenes"]) == 0
    listing = capsys.readouterr().out
    for name, scene in dz.SCENES.items():
        assert f"{name}" in listing and scene.title in listing
    assert main(["scenes", "--show", "fig3a"]) == 0
    text = capsys.readouterr().out
    (tmp_path / "fig3a.toml").write_text(text)
    assert dz.load_scene(tmp_path / "fig3a.toml") == dz.SCENES["fig3a"]
    assert main(["scenes", "--show", "fig9"]) == 2
    assert "no shipped scene 'fig9'" in capsys.readouterr().err


@pytest.mark.parametrize("argv", [["--help"], ["paper", "--help"], ["run", "--help"],
                                  ["scenes", "--help"]])
def test_help_everywhere(argv, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 0
    assert "usage: dzhanibekov" in capsys.readouterr().out


def test_the_module_and_the_script_run(tmp_path):
    for command in ([sys.executable, "-m", "dzhanibekov"],
                    [str(Path(sys.executable).parent / "dzhanibekov")]):
        done = subprocess.run(command + ["scenes"], capture_output=True, text=True, check=True)
        assert "stable-largest" in done.stdout
    done = subprocess.run([sys.executable, "-m", "dzhanibekov", "run"], capture_output=True,
                          text=True)
    # the scene is required; --out is not (issue 33: a folder named after the scene)
    assert done.returncode == 2 and "required: SCENE\n" in done.stderr


def test_run_overrides_the_scenes_method_end_frames_and_step(tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["run", "fig3a", "--out", str(out), "--no-progress", "--t-end", "40",
            "--frames", "41", "--method", "dop853", "--dt", "none"]
    assert main(argv) == 0
    report = json.loads((out / "fig3a.json").read_text())
    one = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=40.0, frames=41,
                      method="dop853", dt=None)
    assert report["method"] == "dop853" and report["n_steps"] == one.n_steps
    assert report["flip_times"] == one.flip_times.tolist()
    assert main(["run", "example", "--out", str(out), "--t-end", "50", "--dt", "0.01",
                 "--method", "splitting", "--frames", "21", "--no-progress"]) == 0
    # (its phases after t = 50 are dropped)
    report = json.loads((out / "example.json").read_text())
    assert (report["method"], report["dt"], report["n_steps"]) == ("splitting", 0.01, 5000)
    capsys.readouterr()
    assert main(["run", "fig3a", "--out", str(out), "--frames", "1"]) == 2
    assert "`--frames` must be" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["run", "fig3a", "--out", str(out), "--dt", "soon"])


def test_paper_without_animations_asks_for_the_figures_only(tmp_path, monkeypatch, capsys):
    """`--no-animation` reaches the render (which draws no animation when told: see
    `test_run_without_animation`; the full `paper` render runs above)."""
    import dzhanibekov.render as render

    asked = {}

    def fake(folder, **kwargs):
        asked.update(kwargs)
        return [], []

    monkeypatch.setattr(render, "render_paper", fake)
    assert main(["paper", "--out", str(tmp_path / "out"), "--no-animation", "--jobs", "1"]) == 0
    assert asked["animation"] is False and asked["workers"] == 1
    assert main(["paper", "--out", str(tmp_path / "out")]) == 0
    assert asked["animation"] is True and asked["workers"] is None
    capsys.readouterr()


def test_run_without_animation(tmp_path):
    out = tmp_path / "out"
    assert main(["run", "example", "--out", str(out), "--no-animation", "--t-end", "20",
                 "--no-progress"]) == 0
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [f"example-{f}.png" for f in dz.SCENES["example"].draw.figures] + ["example.json"])


def test_paper_help_says_what_it_renders(capsys):
    """Nine scenes, four animated: each named with its title and what it draws."""
    with pytest.raises(SystemExit):
        main(["paper", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    animated = [n for n in PAPER_RENDER if dz.SCENES[n].draw.animation]
    assert (len(PAPER_RENDER), len(animated)) == (9, 4)
    assert "Simulate nine scenes" in text and "four animations" in text
    for name in PAPER_RENDER:
        scene = dz.SCENES[name]
        assert f"{name} {scene.title}" in text
        assert ", ".join(scene.draw.figures) + (" + animation" if name in animated else "") \
            in text
    assert "--no-animation" in text and "--jobs" in text


def merged(argv: list[str], **kwargs) -> subprocess.CompletedProcess[str]:
    """The command line in a process of its own, stderr into stdout (in the order written)."""
    return subprocess.run([sys.executable, "-m", "dzhanibekov", *argv], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=300, **kwargs)


def test_cli_warnings_are_one_line_in_cli_terms_before_the_result(tmp_path):
    """`run fig3a --dt 5` printed a raw StepSizeWarning (a site-packages path, its source
    line, advice in API terms) after the table, and turned the step into 0.5 silently."""
    done = merged(["run", "fig3a", "--dt", "5", "--out", str(tmp_path / "out"),
                   "--no-progress"])
    assert done.returncode == 0, done.stdout
    lines = done.stdout.splitlines()
    warned = [k for k, line in enumerate(lines) if line.startswith("dzhanibekov: warning: ")]
    result = next(k for k, line in enumerate(lines) if line.startswith("rendered in"))
    assert len(warned) == 2 and max(warned) < result
    assert not [line for line in lines if "Warning" in line or "site-packages" in line
                or "warnings.warn" in line]
    step, = (lines[k] for k in warned if "became" in lines[k])
    drift, = (lines[k] for k in warned if "too large" in lines[k])
    assert "--dt 5 became 0.5 in fig3a" in step and "every 0.5" in step
    assert "--dt none" in drift and "--method splitting" in drift and "--dt" in drift
    assert "dt=None" not in drift and "method=" not in drift and "MAX_PREDICTED" not in drift


@pytest.mark.parametrize("argv, option", [
    (["--fps", "0"], "--fps"), (["--fps", "1001"], "--fps"), (["--gif-size", "7"], "--gif-size"),
    (["--gif-size", "5000"], "--gif-size"), (["--dt", "0"], "--dt"), (["--dt", "-1"], "--dt"),
    (["--dt", "nan"], "--dt")])
@pytest.mark.parametrize("command", ["run fig3a", "paper"])
def test_every_option_is_checked_whatever_the_scene(command, argv, option, tmp_path, capsys):
    """fig3a has no animation: `--fps 0` and `--gif-size 7` passed silently."""
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as exit_:
        main([*command.split(), "--out", str(out), *argv])
    assert exit_.value.code == 2
    assert f"argument {option}: must be" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("argv, says", [
    (["--t-end", "-1"], "`--t-end` must be"), (["--frames", "1"], "`--frames` must be"),
    (["--method", "rk5"], "`--method` must be one of"),
    (["--method", "exact", "--dt", "0.1"], None)])
def test_an_override_is_named_by_its_option(argv, says, tmp_path, capsys):
    out = tmp_path / "out"
    code = main(["run", "fig3a", "--out", str(out), "--no-progress", *argv])
    err = capsys.readouterr().err
    if says is None:  # allowed: the exact solution takes no steps, and says so
        assert code == 0 and "--dt 0.1 is ignored by --method exact" in err
        return
    assert code == 2 and says in err and "run." not in err
    assert not out.exists()


def test_view_creates_its_folder_as_the_other_commands_do(tmp_path, capsys):
    pytest.importorskip("plotly")
    out = tmp_path / "new" / "deeper" / "flip.html"
    assert main(["view", "fig3b", "--out", str(out), "--frames", "11"]) == 0
    assert out.stat().st_size > 10_000
    (tmp_path / "plain").write_text("x")
    assert main(["view", "fig3b", "--out", str(tmp_path / "plain" / "flip.html")]) == 2
    assert "is a file" in capsys.readouterr().err


def test_each_command_gives_the_apis_advice_in_its_own_options():
    """The step warning's advice (`dt=None`, a method such as 'splitting') in each command's terms:
    `run` has --dt none and --method; `paper` points to `run`; `map` has only --dt."""
    from dzhanibekov.cli import cli_terms

    with pytest.warns(dz.StepSizeWarning) as caught:
        dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=100.0, dt=0.5)
    message = str(caught[0].message)
    assert "dt=None" in message and "'splitting'" in message
    said = {command: cli_terms(message, command) for command in ("run", "paper", "map")}
    for text in said.values():
        assert "dt=None" not in text and "method=" not in text and "a smaller --dt" in text
        assert "'splitting'" not in text
        assert "\n" not in text
    assert "--dt none" in said["run"] and "--method splitting" in said["run"]
    assert "`dzhanibekov run SCENE --method splitting`" in said["paper"]
    assert said["map"].endswith("Take a smaller --dt.")


def test_run_and_view_write_next_to_you_without_out(tmp_path, monkeypatch, capsys):
    # Issue 33: `run` and `view` required --out; by default they write after the scene's name
    monkeypatch.chdir(tmp_path)
    assert main(["run", "fig3b", "--no-animation", "--no-progress"]) == 0
    assert (tmp_path / "fig3b" / "fig3b.json").exists()
    assert "wrote 5 files to fig3b:" in capsys.readouterr().out
    # the viewer, though a folder `fig3b` is now there: a folder is never the scene
    pytest.importorskip("plotly")
    assert main(["view", "fig3b"]) == 0
    assert (tmp_path / "fig3b.html").exists()
