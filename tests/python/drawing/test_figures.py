"""The figures, on the Agg backend: each draws what it claims, checked against the physics."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402
from PIL import Image  # noqa: E402

import dzhanibekov as dz  # noqa: E402
from dzhanibekov.plotting import figures as plotting  # noqa: E402
from dzhanibekov.scenes.scene import Draw  # noqa: E402


@pytest.fixture(scope="module")
def computed():
    return {name: plotting.compute(s) for name, s in dz.SCENES.items()}


def line(fig, label):
    found = [ln for ax in fig.axes for ln in ax.lines if ln.get_label() == label]
    assert found, f"no line labelled {label!r}"
    return found[0]


def momentum_direction(scene):
    """L in space from the initial state, independently of the package: M(q0) · I ω0."""
    q = np.array(scene.q0) / np.linalg.norm(scene.q0)
    w, x, y, z = q
    m = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                  [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                  [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    ell = m @ (np.array(scene.inertia) * scene.omega0)
    return ell / np.linalg.norm(ell)


def test_fig3a_path_crosses_to_the_other_hemisphere_at_each_flip(computed):
    result = computed["fig3a"]
    fig = plotting.path_figure(result)
    assert isinstance(fig, Figure)
    dense = np.array(line(fig, "signal point's path").get_data_3d()).T
    # drawn smooth from the run's interpolant (issue 11): k points per stored frame interval,
    # through the stored frames, the body turning at most 1.5° from one point to the next
    k = (len(dense) - 1) // 200
    assert dense.shape == (200 * k + 1, 3) and k >= 2
    np.testing.assert_allclose(dense[::k], result.path, atol=1e-12 * 13.0)
    turn = np.arccos(np.clip(np.sum(dense[1:] * dense[:-1], axis=1) / 13.0**2, -1, 1))
    assert turn.max() < np.radians(1.5)
    # the point moves on its sphere: rotation keeps its distance from the centre
    np.testing.assert_allclose(np.linalg.norm(dense, axis=1), 13.0, rtol=1e-12)
    path = dense[::k]
    height = path @ momentum_direction(result.scene)
    assert height[0] > 0 and height.min() < -0.9 * 13.0  # right over to the other pole
    # the signal point sits on the intermediate axis z: it crosses the equator exactly when
    # the intermediate-axis rate changes sign, which is how a flip's time is defined
    crossings = np.flatnonzero(np.sign(height[1:]) != np.sign(height[:-1]))
    flips = result.flip_times
    assert len(flips) == 2
    t = result.trajectory.t
    for flip in flips:
        assert any(t[k] <= flip <= t[k + 1] for k in crossings)
    # a crossing is a flip once the intermediate axis gets nearest L on the other side
    # (|L_z| > |L|/√2); one begun near t = 100 and not completed is not counted
    for k in crossings:
        if not any(t[k] <= flip <= t[k + 1] for flip in flips):
            assert np.abs(height[k + 1:]).max() < 13.0 / np.sqrt(2)
    assert line(fig, "L (angular momentum)") and line(fig, "equator ⊥ L")


@pytest.mark.parametrize("name", ["stable-largest", "stable-smallest"])
def test_nothing_flips_in_the_stable_counter_examples(computed, name):
    result = computed[name]
    assert len(result.flip_times) == 0 and result.verdict == "no flip in [0, 100]"
    path = np.array(line(plotting.path_figure(result), "signal point's path").get_data_3d()).T
    height = path @ momentum_direction(result.scene) / np.linalg.norm(result.scene.signal_point)
    assert height.min() > np.cos(np.radians(5))  # stays within a few degrees of L
    fig = plotting.omega_figure(result)
    assert not [ln for ln in fig.axes[0].lines if ln.get_label() == "flip"]
    assert len(fig.axes[0].lines) == 3  # u, v, w and no flip marks


def test_omega_figure_draws_the_rates_and_marks_each_flip(computed):
    result = computed["fig3a"]
    fig = plotting.omega_figure(result)
    ax = fig.axes[0]
    for k, name in enumerate("uvw"):
        np.testing.assert_array_equal(line(fig, name).get_ydata(), result.trajectory.omega[:, k])
    marks = [ln for ln in ax.lines if ln.get_linestyle() == ":"]
    assert sorted(m.get_xdata()[0] for m in marks) == sorted(result.flip_times)
    assert [m.get_label() for m in marks].count("flip") == 1
    assert "2 flips in [0, 100]" in ax.get_title()
    assert "2 flips in [0, 100]" in plotting.path_figure(result).axes[0].get_title()


def test_invariants_figure_shows_the_runs_drift(computed):
    result = computed["example"]
    fig = plotting.invariants_figure(result)
    ax = fig.axes[0]
    assert ax.get_yscale() == "log" and len(ax.lines) == 4
    plotted = [np.nanmax(ln.get_ydata()) for ln in ax.lines]
    # the core's drift monitor measured the same maxima while the run went
    np.testing.assert_allclose(plotted, list(result.drift), rtol=0.05)


def test_polhode_figure_puts_omega_on_both_quadrics_and_draws_the_separatrix(computed):
    result = computed["example"]
    fig = plotting.polhode_figure(result)
    inertia = np.array(dz.PAPER_INERTIA)
    omega = np.array(line(fig, "ω(t)").get_data_3d()).T
    np.testing.assert_array_equal(omega, result.trajectory.omega)
    two_e = inertia @ result.trajectory.omega[0] ** 2
    l2 = (inertia**2) @ result.trajectory.omega[0] ** 2
    np.testing.assert_allclose(omega**2 @ inertia, two_e, rtol=1e-12)  # energy ellipsoid
    np.testing.assert_allclose(omega**2 @ inertia**2, l2, rtol=1e-12)  # momentum sphere
    separatrix = [ln for ln in fig.axes[0].lines if ln.get_color() == plotting.COLORS["separatrix"]]
    assert len(separatrix) == 2 and separatrix[0].get_label() == "separatrix"
    i_mid = np.sort(inertia)[1]
    for ln in separatrix:
        curve = np.array(ln.get_data_3d()).T
        np.testing.assert_allclose(curve**2 @ inertia, two_e, rtol=1e-12)
        np.testing.assert_allclose(curve**2 @ inertia**2, two_e * i_mid, rtol=1e-12)
        # it passes through both ends of the intermediate axis (z)
        ends = np.sqrt(two_e / inertia[2])
        assert np.isclose(curve[:, 2].max(), ends) and np.isclose(curve[:, 2].min(), -ends)
    # the paper's example hugs the separatrix: |L|² / 2E is the intermediate moment
    assert l2 / two_e == pytest.approx(i_mid, rel=1e-9)


def test_the_polhodes_lie_where_the_energy_ellipsoid_meets_a_momentum_sphere():
    inertia = np.array([1.0, 2.5, 4.0])
    family, separatrix = plotting.polhodes(inertia, energy=0.7, levels=3)
    assert len(family) == 2 * 2 * 3 and len(separatrix) == 2
    levels = []
    for curve in family:
        np.testing.assert_allclose(curve**2 @ inertia, 1.4, rtol=1e-12)
        d = curve**2 @ inertia**2 / 1.4
        np.testing.assert_allclose(d, d[0], rtol=1e-12)  # one momentum sphere per curve
        assert 1.0 < d[0] < 4.0 and not np.isclose(d[0], 2.5)
        levels.append(d[0])
    assert min(levels) < 2.5 < max(levels)  # about both stable axes
    # a symmetric top has no separatrix
    assert plotting.polhodes((2.0, 2.0, 1.0), energy=1.0)[1] == []


def test_phases_figure_draws_the_body_at_each_instant(computed):
    result = computed["example"]
    fig = plotting.phases_figure(result)
    assert len(fig.axes) == 8
    assert [ax.get_title() for ax in fig.axes] == [
        f"t = {t:g}" for t in (0, 36, 40, 43, 46, 49, 52, 100)]
    for ax in fig.axes:
        assert sum(isinstance(c, Poly3DCollection) for c in ax.collections) == 1  # ellipsoid
        assert sum(isinstance(c, Line3DCollection) for c in ax.collections) == 1  # box
        assert line(fig, "signal point")
    # the signal point is drawn where the path says it is at that instant
    marker = np.array([ln for ln in fig.axes[4].lines
                       if ln.get_label() == "signal point"][0].get_data_3d()).ravel()
    np.testing.assert_array_equal(marker, result.path[92])


def test_fig3_puts_a_b_c_side_by_side_and_saves_a_picture(computed, tmp_path):
    fig = plotting.fig3_figure([computed[n] for n in ("fig3a", "fig3b", "fig3c")],
                               save=tmp_path / "fig3.png")
    assert len(fig.axes) == 3
    assert [ax.get_title().split(":")[0] for ax in fig.axes] == ["Fig. 3a", "Fig. 3b", "Fig. 3c"]
    image = np.asarray(Image.open(tmp_path / "fig3.png").convert("RGB"))
    assert image.shape[1] > image.shape[0] and len(np.unique(image.reshape(-1, 3), axis=0)) > 16


def test_figures_accept_a_scene_and_an_axes():
    fig = Figure()
    ax = fig.add_subplot()
    assert plotting.omega_figure(dz.SCENES["fig3b"], ax=ax) is fig
    with pytest.raises(TypeError, match="`scene` must be a Scene"):
        plotting.compute("fig3a")


def test_a_figure_the_scene_was_not_computed_for_says_what_is_missing():
    result = plotting.compute(dz.SCENES["fig3a"].replace(draw=Draw(figures=("omega",))))
    with pytest.raises(ValueError, match=r"without what the path figure needs \(signal\)"):
        plotting.path_figure(result)
    flips_only = plotting.compute(dz.SCENES["fig3a"].replace(draw=Draw()))
    with pytest.raises(ValueError, match=r"needs \(frames\)"):
        plotting.omega_figure(flips_only)


def painted(fig):
    """Every drawn data point of every line of `fig`'s 2-D axes, in pixels, (N, 2)."""
    points = [ln.get_transform().transform(np.column_stack(ln.get_data()))
              for ax in fig.axes for ln in ax.lines if ln.get_visible() and len(ln.get_xdata())]
    return np.concatenate(points)


def test_legends_cover_no_curve_and_no_3d_box(computed):
    """The legends of fig3 sat on the 3-D boxes, the shares' legend on the −1 troughs."""
    fig = plotting.fig3_figure([computed[n] for n in ("fig3a", "fig3b", "fig3c")])
    fig.canvas.draw()
    (legend,) = fig.legends  # one, for the row
    assert [t.get_text() for t in legend.get_texts()] == [
        "signal point's path", "start", "end", "L (angular momentum)", "equator ⊥ L"]
    for ax in fig.axes:
        assert ax.get_legend() is None
        assert not legend.get_window_extent().overlaps(ax.get_window_extent())
    fig = plotting.path_figure(computed["fig3a"])
    fig.canvas.draw()
    assert not fig.legends[0].get_window_extent().overlaps(fig.axes[0].get_window_extent())
    for name, figure in (("deployment", "shares"), ("explorer-1", "shares"),
                         ("deployment", "omega"), ("fig3a", "omega")):
        fig = plotting.FIGURE_FUNCTIONS[figure](computed[name])
        fig.canvas.draw()
        box = fig.axes[0].get_legend().get_window_extent()
        x, y = painted(fig).T
        inside = (box.x0 <= x) & (x <= box.x1) & (box.y0 <= y) & (y <= box.y1)
        assert not inside.any(), (name, figure)


def test_the_phases_say_what_each_thing_drawn_is(computed):
    fig = plotting.phases_figure(computed["example"])
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == [
        "inertia ellipsoid", "box", "signal point's path", "signal point"]
    fig = plotting.phases_figure(computed["wing-nut"])
    assert [t.get_text() for t in fig.legends[0].get_texts()] == [
        "wing nut", "L (angular momentum)", "signal point's path", "signal point"]
    fig.canvas.draw()
    for ax in fig.axes:
        assert not fig.legends[0].get_window_extent().overlaps(ax.get_window_extent())


def test_axes_carry_units(computed):
    """The wing nut is in grams, millimetres and seconds; the other scenes in any consistent
    units, and say so."""
    wing = computed["wing-nut"]
    ax = plotting.omega_figure(wing).axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("t (s)", "ω (rad/s, body frame)")
    ax = plotting.path_figure(wing).axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()) == ("X (mm)", "Y (mm)", "Z (mm)")
    assert plotting.phases_figure(wing).axes[1].get_title() == "t = 8 s"
    ax = plotting.omega_figure(computed["fig3a"]).axes[0]
    assert ax.get_xlabel() == "t (consistent units)"
    assert ax.get_ylabel() == "ω (rad per unit of time, body frame)"
    for figure in ("shares", "energy"):
        ax = plotting.FIGURE_FUNCTIONS[figure](computed["deployment"]).axes[0]
        assert ax.get_xlabel() == "t (consistent units)"
    ax = plotting.invariants_figure(computed["example"]).axes[0]
    assert ax.get_xlabel() == "t (consistent units)"


def test_explorer_1_is_headed_by_its_reorientation_not_by_flips(computed):
    """A damped body's scene is about its spin going flat: "no flip in [0, 3000]" said
    nothing about it."""
    from dzhanibekov.damper import flat_spin_time

    result = computed["explorer-1"]
    t_flat = flat_spin_time(result.trajectory)
    for figure in result.scene.draw.figures:
        title = plotting.FIGURE_FUNCTIONS[figure](result).axes[0].get_title()
        assert "no flip" not in title
        assert f"flat spin from t ≈ {t_flat:.0f}" in " ".join(title.split()), figure
    # a scene of flips still counts them
    assert "2 flips in [0, 100]" in plotting.omega_figure(computed["fig3a"]).axes[0].get_title()


@pytest.mark.parametrize("name", [n for n, s in dz.SCENES.items()
                                  if {"omega", "shares"} & set(s.draw.figures)])
def test_the_curves_against_time_follow_the_motion(name):
    """A curve drawn through the scene's frames (straight between them) stays within 2 % of
    its range of the motion, as a run with ten times the frames has it: deployment-omega,
    at 301 frames, cut the peaks of the tumbling body (8 %), Explorer 1's shares, at 401,
    were aliased into swings that do not happen (89 %)."""
    from dzhanibekov.damper import axis_shares

    scene = dz.SCENES[name].replace(draw=Draw(figures=("omega",)))
    run = scene.run()
    fine = scene.replace(frames=10 * (scene.frames - 1) + 1).run()
    for curve in (lambda traj: traj.omega, axis_shares):
        ref, drawn = curve(fine), curve(run)
        between = np.stack([np.interp(fine.t, run.t, drawn[:, k]) for k in range(3)], axis=1)
        spread = np.ptp(ref, axis=0)
        error = np.abs(between - ref).max(axis=0) / np.where(spread > 0, spread, 1.0)
        assert error.max() < 0.02, (name, error)


def test_the_invariants_figure_names_what_a_deployment_changes(computed):
    # Issue 33: a deployment's energy, changed by its work, was drawn as a drift
    result = computed["deployment"]
    ax = plotting.invariants_figure(result).axes[0]
    styles = {ln.get_label(): ln.get_linestyle() for ln in ax.lines}
    changed = [k for k in styles if k.startswith("energy")]
    assert changed == ["energy  |E/E₀ − 1| (changed by the model)"] and styles[changed[0]] == "--"
    assert all(style == "-" for k, style in styles.items() if not k.startswith("energy"))
    assert "change (dashed)" in ax.get_ylabel()


def test_a_composite_is_drawn_as_its_parts_without_asking(tmp_path):
    # Issue 33: a composite body needed `[draw] box = true` to be drawn at all, and the
    # legend then said "box"
    path = tmp_path / "dumbbell.toml"
    path.write_text("""title = "A dumbbell"
[body]
parts = [{ sphere = 1.0, mass = 2.0, position = [-3.0, 0.0, 0.0] },
         { sphere = 1.0, mass = 2.0, position = [3.0, 0.0, 0.0] }]
[start]
omega = [0.01, 1.0, 0.01]
[run]
t_end = 5.0
frames = 11
[draw]
path = true
figures = ["phases"]
""", encoding="utf-8")
    scene = dz.load_scene(path)
    assert scene.draw.box
    fig = plotting.phases_figure(scene)
    assert [t.get_text() for t in fig.legends[0].get_texts()][0] == "composite body (2 parts)"
    # the outline drawn is the parts' own: every vertex of both spheres
    assert len(scene.drawn_shape.vertices) == 2 * len(dz.Body.sphere(1.0).shape.vertices)
    # told not to, it is not drawn
    text = path.read_text(encoding="utf-8").replace("path = true", "path = true\nbox = false")
    path.write_text(text, encoding="utf-8")
    assert not dz.load_scene(path).draw.box


def test_titles_never_break_inside_a_tuple(computed):
    # Issue 33: the deployment's figure titles broke "(1, 3, 2)" over two lines
    result = computed["deployment"]
    for figure in result.scene.draw.figures:
        fig = plotting.FIGURE_FUNCTIONS[figure](result)
        for ax in fig.axes:
            for line in ax.get_title().splitlines():
                assert line.count("(") == line.count(")"), (figure, ax.get_title())
