"""Stability maps draw what they claim (on Agg): the sweep's values on the grid's axes, and
the separatrix where the formula and the flips put it; the `map` command end to end."""

import numpy as np
import pytest
from matplotlib.collections import QuadMesh

import dzhanibekov as dz
from dzhanibekov.plotting import maps
from dzhanibekov.cli import main
from pictures import assert_picture

PAPER = np.array(dz.PAPER_INERTIA)


@pytest.fixture(scope="module")
def rate_sweep():
    u, v = np.linspace(0.0, 1.2, 13), np.linspace(0.0, 1.0, 11)
    return dz.sweep(PAPER, dz.grid(u, v, 1.0), t_end=150.0, frames=2, dt=1e-2)


def test_the_map_shows_the_sweep_on_its_axes(rate_sweep):
    for quantity in maps.QUANTITIES:
        fig = maps.stability_map(rate_sweep, quantity=quantity)
        ax = fig.axes[0]
        assert ax.get_xlabel().startswith("u₀") and ax.get_ylabel().startswith("v₀")
        (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
        shown = np.ma.filled(mesh.get_array(), np.nan).reshape(11, 13)  # rows are v, columns u
        expected = {
            "tilt": rate_sweep.tilt_degrees,
            "flips": rate_sweep.flips,
            "period": rate_sweep.period,
            "exact_period": np.where(np.isfinite(rate_sweep.exact_period),
                                     rate_sweep.exact_period, np.nan),
        }[quantity]
        assert np.array_equal(shown, expected.T, equal_nan=True), quantity
        assert fig.axes[1].get_ylabel()  # the colour bar says what it shows


def test_the_separatrix_is_where_the_formula_and_the_flips_put_it(rate_sweep):
    fig = maps.stability_map(rate_sweep, quantity="tilt")
    ax = fig.axes[0]
    (lines,) = [c for c in ax.collections if c.get_label() == "separatrix"]
    points = np.concatenate([p.vertices for p in lines.get_paths()])
    # for the paper's body (z intermediate) and w0 = 1 it is the line
    # Ix (Ix − Iz) u² = Iy (Iz − Iy) v², through the origin
    ix, iy, iz = PAPER
    slope = np.sqrt(ix * (ix - iz) / (iy * (iz - iy)))
    assert len(points) > 10
    # to within the contour's linear interpolation on its grid (steps of 0.023 and 0.027)
    assert np.allclose(points[:, 1], slope * points[:, 0], atol=0.01)
    assert points[:, 0].max() > 0.8
    # beyond it, a start nearest x (u0 > 0.8) wobbles about x without turning over (tilt < 90°);
    # before it, it circulates y and x turns over
    u, v = rate_sweep.omega0[..., 0], rate_sweep.omega0[..., 1]
    nearest_x = ix * u > iz
    below = nearest_x & (v < slope * u - 0.05)
    above = nearest_x & (v > slope * u + 0.05)
    assert below.any() and above.any()
    assert np.all(rate_sweep.tilt[below] < np.pi / 2) and np.all(rate_sweep.tilt[above] > np.pi / 2)


def test_separatrix_gap_is_zero_on_the_separatrix():
    ix, iy, iz = PAPER
    v = 0.3
    u = v * np.sqrt(iy * (iz - iy) / (ix * (ix - iz)))
    assert maps.separatrix_gap(PAPER, [u, v, 1.0]) == pytest.approx(0.0, abs=1e-15)
    assert maps.separatrix_gap(PAPER, [u + 0.01, v, 1.0]) > 0  # about x, the largest moment
    assert maps.separatrix_gap(PAPER, [u - 0.01, v, 1.0]) < 0  # about y, the smallest
    # the flip period grows without bound as the start nears it
    assert dz.flip_period(PAPER, (u * (1 + 1e-9), v, 1.0)) > 4 * dz.flip_period(PAPER,
                                                                                (0.0, v, 1.0))


def test_a_map_over_inertia_ratios():
    ratios = np.linspace(0.6, 1.4, 7)
    s = dz.sweep(dz.grid(1.0, ratios, ratios), (0.2, 0.2, 1.0), t_end=60.0, frames=2, dt=1e-2)
    fig = maps.stability_map(s, quantity="tilt")
    ax = fig.axes[0]
    assert ax.get_xlabel().startswith("iy") and ax.get_ylabel().startswith("iz")
    assert any(c.get_label() == "separatrix" for c in ax.collections)


def test_bad_maps_are_refused(rate_sweep):
    with pytest.raises(TypeError, match="`result` must be a Sweep"):
        maps.stability_map(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="`quantity` must be one of"):
        maps.stability_map(rate_sweep, quantity="colour")
    line = dz.sweep(PAPER, dz.grid(np.linspace(0, 1, 4), 0.1, 1.0), t_end=1.0)
    with pytest.raises(ValueError, match="2-D grid"):
        maps.stability_map(line)
    mixed = dz.sweep(PAPER, np.random.default_rng(0).normal(size=(3, 4, 3)), t_end=1.0)
    with pytest.raises(ValueError, match="varies none"):
        maps.stability_map(mixed)


def test_map_command_writes_the_maps_and_their_numbers(tmp_path, capsys):
    out = tmp_path / "maps"
    args = ["map", "--out", str(out), "--size", "12", "--t-end", "40", "--no-progress"]
    assert main(args) == 0
    names = sorted(p.name for p in out.iterdir())
    assert names == ["map-inertia.npz", "map-inertia.png", "map-rates.npz", "map-rates.png"]
    for png in out.glob("*.png"):
        assert_picture(png)
    data = np.load(out / "map-rates.npz")
    assert data["tilt"].shape == (12, 12) and data["omega0"].shape == (12, 12, 3)
    assert (data["flips"] > 0).any() and (data["flips"] == 0).any()
    table = capsys.readouterr().out
    assert "rates" in table and "inertia" in table and "wrote 4 files" in table
    assert [p.name for p in tmp_path.iterdir()] == ["maps"]


def test_map_command_refuses_bad_arguments_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "maps"
    assert main(["map", "--out", str(out), "--size", "1"]) == 2
    assert "`size` must be at least 2" in capsys.readouterr().err
    assert not out.exists() and list(tmp_path.iterdir()) == []
    with pytest.raises(SystemExit) as exit_:
        main(["map", "--help"])
    assert exit_.value.code == 0
    assert "--kind" in capsys.readouterr().out


def test_the_grey_of_a_map_is_explained_on_it(rate_sweep):
    """Starts without a period (fewer than two flips by t_end) are grey: the legend says so,
    below the map where it covers none of it."""
    fig = maps.stability_map(rate_sweep, quantity="period")
    fig.canvas.draw()
    ax = fig.axes[0]
    assert not np.isfinite(rate_sweep.period).all()  # there is grey to explain
    legend = ax.get_legend()
    labels = [t.get_text() for t in legend.get_texts()]
    assert labels == ["separatrix", maps.NO_VALUE_MEANS["period"]]
    patch = legend.legend_handles[1]
    assert patch.get_facecolor()[:3] == pytest.approx(
        tuple(int(maps.NO_VALUE[i:i + 2], 16) / 255 for i in (1, 3, 5)))
    assert not legend.get_window_extent().overlaps(ax.get_window_extent())
    # a map with a value everywhere has nothing grey to explain
    fig = maps.stability_map(rate_sweep, quantity="flips")
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == ["separatrix"]
