"""The HTML viewer, loaded in a real headless browser (Debian's chromium).

The page must load without JavaScript errors, hold the plot, its play/pause buttons and its
time slider, and its screenshot must not be blank. Without a browser the browser tests skip
and say why; `.ci/run` installs chromium where apt is available.
"""

import base64
import gzip
import json
import math
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import dzhanibekov as dz

pytest.importorskip("plotly", reason="the `viewer` extra (plotly) is not installed")

BROWSER = next((shutil.which(b) for b in ("chromium", "chromium-browser", "google-chrome")
                if shutil.which(b)), None)
needs_browser = pytest.mark.skipif(
    BROWSER is None,
    reason="no headless browser: `apt-get install chromium` (bash .ci/run installs it as root)")
# messages the page may log that are not errors (WebGL in software, canvas read-backs)
JS_ERROR = re.compile(r"Uncaught|\b\w*Error\b|WebGL is not supported|Failed to load")


def _browser(*args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    assert BROWSER is not None
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
             "--use-angle=swiftshader", "--hide-scrollbars", "--enable-logging=stderr",
             "--v=0", "--virtual-time-budget=10000"]
    env = dict(os.environ, HOME=os.environ.get("HOME", "/tmp"))
    return subprocess.run([BROWSER, *flags, *args], capture_output=True, text=True,
                          timeout=timeout, env=env)


def _console(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if "CONSOLE" in line]


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=100.0, frames=61, dt=1e-2)
    return dz.viewer.write_html(traj, tmp_path_factory.mktemp("viewer") / "flip.html")


def _payload(html: str, name: str) -> str:
    """The page's packed `name` (PLOTLY or FIGURE), unpacked as the browser does."""
    packed = re.search(rf'const {name} = "([A-Za-z0-9+/=]*)";', html)
    assert packed is not None, name
    return gzip.decompress(base64.b64decode(packed.group(1))).decode("utf-8")


def test_the_page_is_self_contained(page):
    html = page.read_text(encoding="utf-8")
    assert "<script src=\"http" not in html and "cdn.plot.ly" not in html.split("</head>")[0]
    assert "Plotly.newPlot" in html or "Plotly.react" in html
    # plotly's bundle is in the page itself, packed
    from plotly.offline import get_plotlyjs

    assert _payload(html, "PLOTLY") == get_plotlyjs()


def test_the_page_of_a_shipped_scene_is_at_most_3_mb_and_loses_nothing_visible(tmp_path):
    # Issue 33: the example's page was 10 MB (plotly's 4.8 MB, every coordinate in full)
    from dzhanibekov.viewer import RESOLUTION

    scene = dz.SCENES["example"]
    page = dz.viewer.write_html(scene, tmp_path / "example.html")
    assert page.stat().st_size <= 3_000_000  # measured 2.49 MB
    fig = dz.viewer.figure(scene)
    shown = json.loads(_payload(page.read_text(encoding="utf-8"), "FIGURE"))
    span = 2 * fig.layout.scene.xaxis.range[1]
    assert len(shown["frames"]) == len(fig.frames)
    for drawn, exact in zip(shown["frames"], fig.frames):
        for a, b in zip(drawn["data"], exact.data):
            for axis in "xyz":
                off = np.abs(np.array(a[axis], dtype=float) - np.array(b[axis], dtype=float))
                assert np.nanmax(off, initial=0.0) <= span / RESOLUTION / 2 + 1e-12 * span


def test_the_figure_has_a_frame_per_frame_and_play_pause_and_a_slider(tmp_path):
    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=10.0, frames=11)
    fig = dz.viewer.figure(traj)
    assert len(fig.frames) == 11
    labels = [b.label for b in fig.layout.updatemenus[0].buttons]
    assert any("play" in s for s in labels) and any("pause" in s for s in labels)
    assert len(fig.layout.sliders[0].steps) == 11
    # the last frame's signal point is where the package's rotation puts it
    point = fig.frames[-1].data[-1]
    expected = dz.rotate(traj.q[-1], (0.0, 0.0, 13.0))
    assert np.allclose([point.x[0], point.y[0], point.z[0]], expected, atol=1e-12)
    assert len(dz.viewer.figure(traj, frames=4).frames) == 4


def test_a_missing_plotly_is_named(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "plotly.graph_objects", None)
    with pytest.raises(ImportError, match=r"pip install \"dzhanibekov\[viewer\]\""):
        dz.viewer.write_html(dz.SCENES["fig3a"], tmp_path / "x.html")


@needs_browser
def test_the_page_loads_without_javascript_errors(page):
    run = _browser("--dump-dom", page.as_uri())
    assert run.returncode == 0, run.stderr[-2000:]
    errors = [m for m in _console(run.stderr) if JS_ERROR.search(m)]
    assert errors == [], errors
    dom = run.stdout
    assert "js-plotly-plot" in dom and "gl-container" in dom  # plotly drew its 3-D scene
    assert dom.count('class="updatemenu-button"') == 2 and "slider-container" in dom


@needs_browser
def test_the_screenshot_is_not_blank(page, tmp_path):
    shot = tmp_path / "shot.png"
    run = _browser(f"--screenshot={shot}", "--window-size=900,800", page.as_uri())
    assert run.returncode == 0 and shot.exists(), run.stderr[-2000:]
    pixels = np.asarray(Image.open(shot).convert("RGB"), dtype=float)
    assert pixels.shape[:2] == (800, 900)
    assert pixels.std() > 20  # not one colour
    # the body is drawn: the box's dark blue and the ellipsoid's orange are on the page
    blue = (np.abs(pixels - [31, 59, 115]).sum(axis=2) < 60).sum()
    orange = ((pixels[..., 0] > 200) & (pixels[..., 1] > 150) & (pixels[..., 2] < 150)).sum()
    assert blue > 500 and orange > 2000, (blue, orange)


def test_the_cli_writes_the_viewer(tmp_path):
    out = tmp_path / "v.html"
    from dzhanibekov.cli import main

    assert main(["view", "fig3a", "--out", str(out)]) == 0
    assert out.exists() and "Plotly" in out.read_text(encoding="utf-8")[:5_000_000]


def test_a_long_run_is_shown_within_the_viewers_own_bound(tmp_path):
    """A Trajectory of more than 2000 frames was refused with a SceneError about a scene's
    `run.frames` and a GIF (the animation's bound), although the viewer shows 201 frames."""
    from dzhanibekov.viewer import MAX_FRAMES, PATH_POINTS

    traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=100.0, frames=2501)
    fig = dz.viewer.figure(traj)
    assert len(fig.frames) == 201
    whole_path = fig.data[-2]  # the static trace of the whole path
    assert len(whole_path.x) == PATH_POINTS
    # the last frame shows the run's last attitude
    point = fig.frames[-1].data[-1]
    expected = dz.rotate(traj.q[-1], (0.0, 0.0, 13.0))
    assert np.allclose([point.x[0], point.y[0], point.z[0]], expected, atol=1e-12)
    assert len(dz.viewer.figure(traj, frames=300).frames) == 300  # more than a GIF's 201
    with pytest.raises(ValueError, match=r"`frames` must be at most 1000 \(the viewer's "
                                         r"MAX_FRAMES"):
        dz.viewer.figure(traj, frames=MAX_FRAMES + 1)
    scene = dz.SCENES["fig3a"].replace(frames=3001)  # a scene's run of many frames too
    assert len(dz.viewer.figure(scene).frames) == 201


def _sinks_run():
    body = dz.Body.from_tensor(np.diag([52.0833, 27.0833, 41.6666]), mass=1.0)
    parts = [dz.SpringMassDamper(0.05, (0.0, 0.0, 3.0), (1.0, 0.0, 0.0), 0.5, 0.02, x0=0.5),
             dz.Hinge(0.05, (1e-4, 0.01, 0.01), (0.0, 4.0, 0.0), (0.0, 0.0, 1.0),
                      (0.0, 1.0, 0.0), 3.0, 0.5, 0.02, angle0=0.6),
             dz.Slosh(0.05, (0.0, 0.0, -3.0), 4.0, 0.02, (1.0, 0.0, 0.0))]
    return dz.simulate(dz.System(body, parts=parts), (0.01, 0.01, 1.0), t_end=20.0, frames=21,
                       dt=1e-2)


def test_the_parts_move_with_the_body():
    # each sink is drawn where its state puts it, turned with the body: the spring's mass at
    # its displacement along its line, the panel's end at twice its centre's distance from the
    # hinge and at its angle from the turned rest arm, the bob at the rod's length
    traj = _sinks_run()
    fig = dz.viewer.figure(traj, frames=21)
    assert len(fig.frames) == 21
    for frame in fig.frames:
        k = int(frame.name)
        drawn = {t.name: np.column_stack([t.x, t.y, t.z]) for t in frame.data
                 if t.name in ("spring_mass", "hinge", "slosh")}
        assert set(drawn) == {"spring_mass", "hinge", "slosh"}
        turned = dz.rotate(traj.q[k], np.eye(3))  # the body axes in space, one a row
        spring, hinge, slosh = drawn["spring_mass"], drawn["hinge"], drawn["slosh"]
        np.testing.assert_allclose(spring[0], 3.0 * turned[2], atol=1e-9)
        np.testing.assert_allclose(spring[1] - spring[0],
                                   traj.parts["spring_mass"][k, 0] * turned[0], atol=1e-9)
        np.testing.assert_allclose(hinge[0], 4.0 * turned[1], atol=1e-9)
        arm = hinge[1] - hinge[0]
        assert abs(np.linalg.norm(arm) - 6.0) < 1e-9
        beta = traj.parts["hinge"][k, 0]
        assert abs(math.atan2(arm @ -turned[0], arm @ turned[1]) - beta) < 1e-9
        assert abs(arm @ turned[2]) < 1e-9  # in the plane normal to the hinge axis z
        n = traj.parts["slosh"][k, :3]
        np.testing.assert_allclose(slosh[1] - slosh[0], 4.0 * (n @ turned) / np.linalg.norm(n),
                                   atol=1e-9)
    assert len({float(f.data[0].x[1]) for f in fig.frames}) > 10  # they move


@needs_browser
def test_the_parts_are_drawn_in_the_page(tmp_path):
    page = dz.viewer.write_html(_sinks_run(), tmp_path / "sinks.html", frames=21)
    shot = tmp_path / "shot.png"
    run = _browser(f"--screenshot={shot}", "--window-size=900,800", page.as_uri())
    assert run.returncode == 0 and shot.exists(), run.stderr[-2000:]
    errors = [line for line in _console(run.stderr) if JS_ERROR.search(line)]
    assert not errors, errors
    pixels = np.asarray(Image.open(shot).convert("RGB"), dtype=float)
    brown = (np.abs(pixels - [110, 44, 0]).sum(axis=2) < 40).sum()  # the parts' colour
    assert brown > 100, brown
