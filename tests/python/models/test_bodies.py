"""Any rigid body: tensors with products of inertia, solids, composites, meshes, the wing nut.

References are independent of the code: scipy's Rotation for the change of axes, the
textbook formulas of the solids (written out here), the parallel-axis theorem summed here,
and closed-form meshes built here.
"""

import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import dzhanibekov as dz

BOX_FACES = np.array([  # counter-clockwise seen from outside; vertex k = bits (x, y, z)
    (0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
    (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5),
])


def box_mesh(a, b, c, offset=(0.0, 0.0, 0.0)):
    k = np.arange(8)
    signs = np.stack([(k >> j) & 1 for j in range(3)], axis=1) - 0.5
    return signs * [a, b, c] + offset, BOX_FACES.copy()


def box_tensor(a, b, c, m):  # Goldstein's table: m (b² + c²) / 12, …
    return np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * m / 12


def random_rotation(seed):
    return Rotation.random(random_state=seed)


# -- from_tensor ----------------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(8))
def test_from_tensor_recovers_moments_and_a_proper_frame(seed):
    r = random_rotation(seed).as_matrix()
    moments = np.array([3.0, 1.0, 2.5]) * (1 + seed)
    body = dz.Body.from_tensor(r @ np.diag(moments) @ r.T, mass=2.0)
    # the principal moments, each about the principal axis nearest the user's x, y, z
    np.testing.assert_allclose(np.sort(body.inertia), np.sort(moments), rtol=1e-13)
    axes = body.principal_axes
    np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-14)
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-14)
    np.testing.assert_allclose(axes @ np.diag(body.inertia) @ axes.T, body.tensor,
                               atol=1e-13 * moments.max())
    # each principal axis is an eigenvector of the tensor given
    tensor = r @ np.diag(moments) @ r.T
    for k in range(3):
        np.testing.assert_allclose(tensor @ axes[:, k], body.inertia[k] * axes[:, k],
                                   atol=1e-13 * moments.max())


def test_from_tensor_refuses_what_is_not_an_inertia_tensor():
    with pytest.raises(ValueError, match="symmetric"):
        dz.Body.from_tensor([[1.0, 0.2, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    with pytest.raises(ValueError, match="positive definite"):
        dz.Body.from_tensor(np.diag([1.0, -1.0, 1.0]))
    with pytest.raises(ValueError, match="shape"):
        dz.Body.from_tensor(np.eye(4))
    with pytest.raises(ValueError, match="finite"):
        dz.Body.from_tensor(np.diag([1.0, np.nan, 1.0]))


def test_a_square_array_where_moments_are_expected_points_to_from_tensor():
    tensor = np.diag([1.0, 2.0, 3.0])
    for call in (lambda: dz.Body(tensor), lambda: dz.simulate(tensor, (0.1, 1.0, 0.1)),
                 lambda: dz.flip_period(tensor, (0.1, 1.0, 0.1)),
                 lambda: dz.sweep(tensor, (0.1, 1.0, 0.1), t_end=1.0)):
        with pytest.raises(ValueError, match="from_tensor"):
            call()
    # three bodies: said with a list of Bodies
    batch = dz.simulate([dz.Body(row) for row in ([1, 2, 3], [2, 3, 4], [1, 3, 3.5])],
                        (0.01, 1.0, 0.01), t_end=5.0, frames=3, dt=1e-2)
    assert batch.omega.shape == (3, 3, 3)


def runs_of(seed, moments, method, **kwargs):
    """A tensor body's run, and the run of its principal body (its moments, in the order of
    its principal axes R) from the start turned by R, turned back by R (scipy)."""
    turn = random_rotation(seed).as_matrix()
    body = dz.Body.from_tensor(turn @ np.diag(moments) @ turn.T)
    r = body.principal_axes
    rot = Rotation.from_matrix(r)
    moments = np.array(body.inertia)
    omega_user = np.array([0.3, -0.2, 0.9])
    q_user = np.array([0.9, 0.1, -0.3, 0.2])
    q_user /= np.linalg.norm(q_user)
    traj = dz.simulate(body, omega_user, q_user, method=method, **kwargs)
    # principal run: ω_p = Rᵀ ω; attitude of the principal frame: M(q_u) R
    q_r = rot.as_quat(scalar_first=True)
    world_from_principal = Rotation.from_quat(q_user, scalar_first=True) * rot
    ref = dz.simulate(dz.Body(moments), r.T @ omega_user,
                      world_from_principal.as_quat(scalar_first=True), method=method, **kwargs)
    omega_ref = ref.omega @ r.T
    q_ref = (Rotation.from_quat(ref.q, scalar_first=True) * rot.inv()).as_quat(scalar_first=True)
    assert q_r.shape == (4,)
    return traj, omega_ref, q_ref, body


def same_attitude(q, q_ref, atol):
    # q and −q are the same attitude: compare the rotation matrices
    m = Rotation.from_quat(q, scalar_first=True).as_matrix()
    m_ref = Rotation.from_quat(q_ref, scalar_first=True).as_matrix()
    np.testing.assert_allclose(m, m_ref, atol=atol)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("method", ["exact", "rk4", "dop853", "splitting"])
def test_a_tensor_body_runs_as_its_principal_body_turned(seed, method):
    traj, omega_ref, q_ref, _ = runs_of(seed, np.array([1.0, 2.0, 3.0]), method,
                                        t_end=20.0, frames=41, dt=1e-3)
    np.testing.assert_allclose(traj.omega, omega_ref, atol=1e-12)
    same_attitude(traj.q, q_ref, atol=1e-12)


def test_unsorted_moments_and_the_exact_solution():
    traj, omega_ref, q_ref, body = runs_of(7, np.array([3.0, 1.0, 2.0]), "exact",
                                           t_end=50.0, frames=101)
    assert sorted(body.inertia) == pytest.approx((1.0, 2.0, 3.0), rel=1e-14)
    np.testing.assert_allclose(traj.omega, omega_ref, atol=1e-11)
    same_attitude(traj.q, q_ref, atol=1e-11)


def test_the_angular_momentum_in_space_is_kept_in_user_axes():
    r = random_rotation(11).as_matrix()
    tensor = r @ np.diag([2.0, 5.0, 4.0]) @ r.T
    body = dz.Body.from_tensor(tensor)
    traj = dz.simulate(body, (0.1, 0.8, -0.3), (1, 0, 0, 0), t_end=30.0, frames=61, dt=1e-3)
    momentum = traj.omega @ tensor.T  # T ω in the user's axes, frame by frame
    world = Rotation.from_quat(traj.q, scalar_first=True).apply(momentum)
    np.testing.assert_allclose(world, np.broadcast_to(world[0], world.shape),
                               atol=1e-9 * np.linalg.norm(world[0]))
    np.testing.assert_allclose(traj.invariants()["momentum_body"], momentum, rtol=1e-12,
                               atol=1e-14)
    np.testing.assert_allclose(traj.invariants()["momentum_world"], world, atol=1e-12)
    # rotate of user-axes points gives world points
    tip = dz.rotate(traj.q, np.array([[0.0, 0.0, 1.0]]))[:, 0]
    np.testing.assert_allclose(tip, Rotation.from_quat(traj.q, scalar_first=True).apply(
        [0.0, 0.0, 1.0]), atol=1e-14)


def test_exact_and_rk4_agree_for_a_tensor_body():
    r = random_rotation(3).as_matrix()
    body = dz.Body.from_tensor(r @ np.diag([1.0, 2.0, 3.0]) @ r.T)
    w0 = r @ np.array([0.05, 1.0, 0.05])  # near the intermediate axis, in user axes
    exact = dz.simulate(body, w0, t_end=40.0, frames=81, method="exact")
    rk4 = dz.simulate(body, w0, t_end=40.0, frames=81, method="rk4", dt=1e-3)
    np.testing.assert_allclose(rk4.omega, exact.omega, atol=1e-9)
    same_attitude(rk4.q, exact.q, atol=1e-8)
    assert len(exact.flip_times) == len(rk4.flip_times) > 0
    np.testing.assert_allclose(rk4.flip_times, exact.flip_times, atol=1e-6)


def test_batches_sweeps_and_periods_take_a_tensor_body():
    r = random_rotation(5).as_matrix()
    body = dz.Body.from_tensor(r @ np.diag([1.0, 2.0, 3.0]) @ r.T)
    starts = np.array([r @ [0.01, 1.0, 0.02], r @ [0.1, 1.0, 0.0], r @ [1.0, 0.1, 0.1]])
    batch = dz.simulate(body, starts, t_end=30.0, frames=31, dt=1e-3)
    for i, w in enumerate(starts):
        single = dz.simulate(body, w, t_end=30.0, frames=31, dt=1e-3)
        np.testing.assert_array_equal(batch[i].omega, single.omega)
        np.testing.assert_array_equal(batch[i].q, single.q)
        assert batch[i].body is body
    sweep = dz.sweep(body, starts, t_end=30.0, dt=1e-3)
    np.testing.assert_array_equal(sweep.flips, batch.flips)
    np.testing.assert_array_equal(sweep.omega0, starts)
    principal = dz.Body((1.0, 2.0, 3.0))
    for w in starts:
        assert dz.flip_period(body, w) == pytest.approx(dz.flip_period(principal, r.T @ w),
                                                        rel=1e-12)


# -- solids --------------------------------------------------------------------------------

def test_solids_have_their_textbook_moments():
    m, r, h = 3.0, 2.0, 5.0
    # Goldstein's table: cylinder Iz = m r²/2, Ix = Iy = m (3r² + h²)/12
    assert dz.Body.cylinder(r, h, mass=m).inertia == pytest.approx(
        (m * (3 * r * r + h * h) / 12, m * (3 * r * r + h * h) / 12, m * r * r / 2))
    assert dz.Body.sphere(r, mass=m).inertia == pytest.approx((0.4 * m * r * r,) * 3)
    a, b, c = 1.0, 2.0, 3.0
    assert dz.Body.ellipsoid(a, b, c, mass=m).inertia == pytest.approx(
        (m * (b * b + c * c) / 5, m * (a * a + c * c) / 5, m * (a * a + b * b) / 5))
    assert dz.Body.box(a, b, c, mass=m).inertia == pytest.approx(np.diag(box_tensor(a, b, c, m)))
    for body in (dz.Body.cylinder(r, h), dz.Body.sphere(r), dz.Body.box(a, b, c)):
        assert body.mass == 1.0 and body.shape is not None
    with pytest.raises(ValueError, match="radius"):
        dz.Body.cylinder(-1.0, 1.0)


# -- meshes --------------------------------------------------------------------------------

def test_a_box_mesh_off_the_origin_is_the_box():
    v, f = box_mesh(4.0, 2.0, 1.0, offset=(1e3, -250.0, 7.5))
    body = dz.Body.from_mesh(v, f, density=0.5)
    assert body.mass == pytest.approx(0.5 * 8.0, rel=1e-12)
    np.testing.assert_allclose(body.center_of_mass, (1e3, -250.0, 7.5), rtol=1e-14)
    np.testing.assert_allclose(body.tensor, box_tensor(4.0, 2.0, 1.0, 4.0), atol=1e-10)
    assert sorted(body.inertia) == pytest.approx(sorted(dz.Body.box(4, 2, 1, mass=4.0).inertia),
                                                 rel=1e-12)
    # turned: the tensor turns with it
    rot = random_rotation(2)
    turned = dz.Body.from_mesh(rot.apply(v), f, mass=4.0)
    r = rot.as_matrix()
    np.testing.assert_allclose(turned.tensor, r @ box_tensor(4.0, 2.0, 1.0, 4.0) @ r.T,
                               atol=1e-10)


def test_an_icosphere_converges_to_the_ball_at_second_order():
    trimesh = pytest.importorskip("trimesh")
    errors = []
    for level in range(1, 5):
        ico = trimesh.creation.icosphere(subdivisions=level, radius=1.0)
        body = dz.Body.from_mesh(ico.vertices, ico.faces, mass=1.0)
        np.testing.assert_allclose(body.center_of_mass, 0.0, atol=1e-14)
        errors.append(abs(np.mean(body.inertia) - 0.4))  # 2/5 m r²
        assert max(body.inertia) - min(body.inertia) < 1e-3 * 0.4 / 4 ** (level - 1)
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    # the inscribed polyhedron's error falls with the edge length squared: ×4 per level
    assert np.all((ratios > 3.5) & (ratios < 4.5)), ratios


def test_open_inverted_and_non_manifold_meshes_are_refused():
    v, f = box_mesh(1.0, 1.0, 1.0)
    with pytest.raises(dz.MeshError, match="open"):
        dz.Body.from_mesh(v, f[:-1])
    with pytest.raises(dz.MeshError, match="inward"):
        dz.Body.from_mesh(v, f[:, ::-1])
    flipped = f.copy()
    flipped[0] = flipped[0, ::-1]
    with pytest.raises(dz.MeshError, match="oriented"):
        dz.Body.from_mesh(v, flipped)
    with pytest.raises(dz.MeshError, match="non-manifold"):
        dz.Body.from_mesh(np.concatenate([v, v]), np.concatenate([f, f]))
    with pytest.raises(TypeError, match="faces"):
        dz.Body.from_mesh(v, f.astype(float))
    with pytest.raises(ValueError, match="not both"):
        dz.Body.from_mesh(v, f, mass=1.0, density=1.0)


def test_load_reads_a_mesh_file_through_trimesh(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    v, f = box_mesh(3.0, 2.0, 1.0, offset=(5.0, 0.0, 0.0))
    path = tmp_path / "box.stl"
    trimesh.Trimesh(v, f).export(path)
    body = dz.Body.load(path, mass=2.0)
    np.testing.assert_allclose(body.tensor, box_tensor(3.0, 2.0, 1.0, 2.0), atol=1e-9)
    with pytest.raises(ValueError, match="cannot be read"):
        dz.Body.load(tmp_path / "missing.stl")


def test_load_without_trimesh_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "trimesh", None)
    with pytest.raises(ImportError, match=r"\[mesh\]"):
        dz.Body.load("anything.stl")


# -- composites ----------------------------------------------------------------------------

def test_a_composite_of_two_boxes_follows_the_parallel_axis_theorem():
    rot = Rotation.from_euler("z", 90, degrees=True) * Rotation.from_euler("x", 30,
                                                                            degrees=True)
    parts = [(dz.Body.box(2.0, 1.0, 1.0, mass=3.0), (1.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0)),
             (dz.Body.box(1.0, 1.0, 4.0, mass=1.0), (0.0, 2.0, 1.0),
              tuple(rot.as_quat(scalar_first=True)))]
    body = dz.Body.compose(parts)
    # the theorem, summed here: G = Σ m p / Σ m; T = Σ R T_i Rᵀ + m (|d|² 1 − d dᵀ)
    com = (3.0 * np.array([1.0, 0.0, 0.0]) + 1.0 * np.array([0.0, 2.0, 1.0])) / 4.0
    expected = np.zeros((3, 3))
    for (a, b, c, m), p, r in (((2, 1, 1, 3.0), (1, 0, 0), np.eye(3)),
                               ((1, 1, 4, 1.0), (0, 2, 1), rot.as_matrix())):
        d = np.array(p, dtype=float) - com
        expected += r @ box_tensor(a, b, c, m) @ r.T + m * (d @ d * np.eye(3) - np.outer(d, d))
    assert body.mass == 4.0
    np.testing.assert_allclose(body.center_of_mass, com, rtol=1e-15)
    np.testing.assert_allclose(body.tensor, expected, atol=1e-13)
    assert len(body.parts) == 2 and body.shape is not None and len(body.shape.edges) == 24
    # at equal densities (1: masses 2 and 4), the same two boxes as one mesh, by the
    # divergence theorem
    even = dz.Body.compose([(dz.Body.box(2.0, 1.0, 1.0, mass=2.0), (1.0, 0.0, 0.0)),
                            (dz.Body.box(1.0, 1.0, 4.0, mass=4.0), (0.0, 2.0, 1.0),
                             tuple(rot.as_quat(scalar_first=True)))])
    v1, f1 = box_mesh(2.0, 1.0, 1.0, offset=(1.0, 0.0, 0.0))
    v2, f2 = box_mesh(1.0, 1.0, 4.0)
    v2 = rot.apply(v2) + (0.0, 2.0, 1.0)
    mesh = dz.Body.from_mesh(np.concatenate([v1, v2]), np.concatenate([f1, f2 + 8]))
    assert mesh.mass == pytest.approx(6.0, rel=1e-14)
    np.testing.assert_allclose(mesh.center_of_mass, even.center_of_mass, atol=1e-14)
    np.testing.assert_allclose(mesh.tensor, even.tensor, atol=1e-12)
    with pytest.raises(ValueError, match="no mass"):
        dz.Body.compose([(dz.Body((1.0, 1.0, 1.0)), (0, 0, 0))])


# -- the wing nut --------------------------------------------------------------------------

def test_the_wing_nut_has_three_distinct_moments_and_flips_about_its_bolt():
    nut = dz.Body.wing_nut()
    i1, i2, i3 = sorted(nut.inertia)
    assert i1 < i2 < i3 and (i2 - i1) > 0.5 * i1 and (i3 - i2) > 0.02 * i2
    bolt = nut.principal_axes[:, nut.intermediate_axis]
    np.testing.assert_allclose(np.abs(bolt), (0.0, 0.0, 1.0), atol=1e-12)
    period = dz.flip_period(nut, (0.01, 0.01, 1.0))
    traj = dz.simulate(nut, (0.01, 0.01, 1.0), t_end=3 * period, dt=None)
    assert len(traj.flip_times) >= 2
    np.testing.assert_allclose(np.diff(traj.flip_times), period, rtol=1e-3)


# -- scenes and pictures ---------------------------------------------------------------------

SCENE = """
title = "a body"
[start]
omega = [0.01, 1.0, 0.01]
[run]
t_end = 30.0
frames = 61
[draw]
box = true
signal_point = true
path = true
figures = ["phases", "path"]
"""


@pytest.mark.parametrize("body_table, expected", [
    ('tensor = [[2.0, -0.5, 0.0], [-0.5, 2.0, 0.0], [0.0, 0.0, 3.0]]',
     lambda: dz.Body.from_tensor([[2.0, -0.5, 0.0], [-0.5, 2.0, 0.0], [0.0, 0.0, 3.0]])),
    ("cylinder = [1.0, 4.0]\nmass = 2.0", lambda: dz.Body.cylinder(1.0, 4.0, mass=2.0)),
    ("sphere = 2.0", lambda: dz.Body.sphere(2.0)),
    ("ellipsoid = [1.0, 2.0, 3.0]", lambda: dz.Body.ellipsoid(1.0, 2.0, 3.0)),
    ('preset = "wing-nut"', dz.Body.wing_nut),
    ('parts = [{ box = [1.0, 1.0, 1.0], mass = 2.0, position = [-1.0, 0.0, 0.0] },\n'
     '         { cylinder = [0.5, 2.0], position = [1.0, 0.0, 0.0], q = [0.0, 1.0, 0.0, 0.0] }]',
     lambda: dz.Body.compose([(dz.Body.box(1, 1, 1, mass=2.0), (-1, 0, 0)),
                              (dz.Body.cylinder(0.5, 2.0), (1, 0, 0), (0, 1, 0, 0))])),
])
def test_scenes_name_any_body(body_table, expected, tmp_path):
    text = SCENE + "[body]\n" + body_table + "\n"
    scene = dz.Scene.from_toml(text, "mine")
    body = expected()
    assert scene.body == body and scene.inertia == body.inertia
    again = dz.Scene.from_toml(scene.to_toml(), "mine")
    assert again == scene and again.body == body
    # the signal point scales with the body: a quarter beyond its outline (a tensor's: the
    # uniform box of its moments, in its principal axes)
    outline = body.shape if body.shape is not None else scene.drawn_shape
    assert np.linalg.norm(scene.signal_point) == pytest.approx(1.25 * outline.radius)
    if body.shape is None:  # a box along the principal axes: corners (±a/2, ±b/2, ±c/2)
        corners = np.abs(outline.vertices @ body.principal_axes)
        np.testing.assert_allclose(corners, np.broadcast_to(corners[0], corners.shape),
                                   rtol=1e-12)
        a, b, c = 2 * corners[0]
        np.testing.assert_allclose(body.inertia, np.diag(box_tensor(a, b, c, 1.0)), rtol=1e-12)


def test_a_scene_mesh_file_is_relative_to_the_scene(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    v, f = box_mesh(3.0, 2.0, 1.0)
    (tmp_path / "parts").mkdir()
    trimesh.Trimesh(v, f).export(tmp_path / "parts" / "box.stl")
    path = tmp_path / "mesh.toml"
    path.write_text(SCENE + '[body]\nmesh = "parts/box.stl"\ndensity = 2.0\n')
    scene = dz.load_scene(path)
    assert scene.body.mass == pytest.approx(12.0)
    np.testing.assert_allclose(scene.body.tensor, box_tensor(3.0, 2.0, 1.0, 12.0), atol=1e-9)
    bad = tmp_path / "bad.toml"
    bad.write_text(SCENE + '[body]\nmesh = "nowhere.stl"\n')
    with pytest.raises(dz.SceneError, match="body.mesh"):
        dz.load_scene(bad)
    two = tmp_path / "two.toml"
    two.write_text(SCENE + '[body]\nsphere = 1.0\ninertia = [1.0, 2.0, 2.5]\n')
    with pytest.raises(dz.SceneError, match="second body"):
        dz.load_scene(two)


def test_the_wing_nut_scene_flips_and_its_pictures_draw_the_nut():
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    from dzhanibekov import plotting

    scene = dz.SCENES["wing-nut"]
    nut = dz.Body.wing_nut()
    assert scene.body == nut
    result = plotting.compute(scene)
    period = dz.flip_period(nut, scene.omega0)
    assert len(result.flip_times) == int((scene.t_end - result.flip_times[0]) // period) + 1 >= 3
    np.testing.assert_allclose(np.diff(result.flip_times), period, rtol=1e-3)
    fig = plotting.phases_figure(result)
    FigureCanvasAgg(fig).draw()  # 3-D collections get their paths when drawn
    for ax in fig.axes:
        faces = [c for c in ax.collections if isinstance(c, Poly3DCollection)]
        edges = [c for c in ax.collections if isinstance(c, Line3DCollection)]
        # the nut's faces (a mesh) and the wings' (boxes), and their outline
        assert len(faces) == 1 and len(faces[0].get_paths()) == 72 + 2 * 12
        assert len(edges) == 1 and len(edges[0].get_segments()) == len(nut.shape.edges)
    # the outline is the nut turned by the run's attitude at that instant
    frame = 0
    world = dz.rotate(result.trajectory.q[frame], nut.shape.vertices)
    np.testing.assert_allclose(result.at("box", frame), world, atol=1e-12)
    assert "wing-nut" in dz.SCENES and dz.SCENES["wing-nut"].draw.animation


def test_the_animation_size_and_rate_come_from_the_scene_or_the_command_line(tmp_path):
    from PIL import Image

    from dzhanibekov.cli import main

    scene = dz.SCENES["wing-nut"].replace(t_end=6.0, frames=13, draw=dz.scenes.Draw(
        box=True, signal_point=True, animation=True, fps=5, animation_size=96))
    path = scene.save(tmp_path / "nut.toml")
    assert dz.load_scene(path).draw.fps == 5  # round trip of draw.fps, draw.animation_size
    assert main(["run", str(path), "--out", str(tmp_path / "a"), "--no-progress"]) == 0
    with Image.open(tmp_path / "a" / "nut.gif") as gif:
        assert gif.size == (96, 96) and gif.info["duration"] == 200
    assert main(["run", str(path), "--out", str(tmp_path / "b"), "--no-progress",
                 "--gif-size", "128", "--fps", "10"]) == 0
    with Image.open(tmp_path / "b" / "nut.gif") as gif:
        assert gif.size == (128, 128) and gif.info["duration"] == 100


def test_bodies_of_every_kind_pickle_with_their_axes_and_shapes():
    import pickle

    r = random_rotation(9).as_matrix()
    for body in (dz.Body.wing_nut(), dz.Body.from_tensor(r @ np.diag([1.0, 2.0, 3.0]) @ r.T),
                 dz.Body.cylinder(1.0, 2.0)):
        again = pickle.loads(pickle.dumps(body))
        assert again == body and again.mass == body.mass
        np.testing.assert_array_equal(again.principal_axes, body.principal_axes)
        w = np.array([0.1, 1.0, 0.2])
        assert dz.flip_period(again, w) == dz.flip_period(body, w)


# -- valid inputs at the edges of float64 (issue 25) ------------------------------------------


@pytest.mark.parametrize("moments", [(1e308, 1e308, 1e308), (1e-15, 1.0, 1.0),
                                     (1.0, 1e-15, 1.0), (3e-300, 2e-300, 1e-300),
                                     (1e-140, 1.0, 1.0)])
def test_a_diagonal_tensor_is_taken_exactly_at_any_scale(moments):
    """`from_tensor(diag(1e308))` was refused although `Body((1e308,) * 3)` is accepted (the
    tensor plus its transpose overflowed), and `diag(1e-15, 1, 1)`, positive definite, was
    refused as "not positive definite"."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.InertiaWarning)
        body = dz.Body.from_tensor(np.diag(moments))
    assert body.inertia == moments  # in the body frame's order, as for every body
    assert body.principal_moments == tuple(sorted(moments))
    assert np.array_equal(body.tensor, np.diag(moments))


def test_a_tensor_singular_to_round_off_is_refused_naming_the_resolution():
    r = random_rotation(3).as_matrix()
    with pytest.raises(ValueError, match=r"singular to round-off.*ε × the largest"):
        dz.Body.from_tensor(r @ np.diag([0.0, 1.0, 2.0]) @ r.T)
    # a small moment within float64's resolution beside the largest is kept, to ~ε of it
    body = dz.Body.from_tensor(r @ np.diag([1e-12, 1.0, 1.0 + 1e-12]) @ r.T)
    assert body.inertia[0] == pytest.approx(1e-12, abs=4 * np.finfo(float).eps)


def test_compose_takes_a_tiny_quaternion():
    """q = (1e-300, 0, 0, 0) is non-zero and normalisable; its norm underflowed to 0."""
    box = dz.Body.box(1.0, 2.0, 3.0)
    for q in ((1e-300, 0.0, 0.0, 0.0), (5e-324, 0.0, 0.0, 0.0), (1e300, 0.0, 0.0, 1e300)):
        composite = dz.Body.compose([(box, (0.0, 0.0, 0.0), q)])
        turn = Rotation.from_quat(np.roll(np.array(q) / np.abs(q).max(), -1)).as_matrix()
        np.testing.assert_allclose(composite.tensor, turn @ box.tensor @ turn.T, atol=1e-15)
    with pytest.raises(ValueError, match=r"`parts\[0\] q` must be a non-zero quaternion"):
        dz.Body.compose([(box, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0))])


@pytest.mark.parametrize("scale", [1e100, 1e-100, 1e150, 1e-150])
def test_a_mesh_at_any_scale_with_a_mass(scale):
    """A box mesh scaled by 1e100 was refused: its volume integrals (length⁵) overflowed."""
    v, f = box_mesh(1.0, 2.0, 3.0)
    body = dz.Body.from_mesh(v * scale, f, mass=1.0)
    want = box_tensor(scale, 2 * scale, 3 * scale, 1.0)
    np.testing.assert_allclose(body.tensor, want, rtol=0, atol=1e-14 * want.max())


def test_a_mesh_whose_mass_or_moments_float64_cannot_hold_names_the_limit():
    v, f = box_mesh(1.0, 2.0, 3.0)
    with pytest.raises(ValueError, match=r"exceed float64's 1.8e\+308; give a smaller `mass` "
                                         r"or `density`"):
        dz.Body.from_mesh(v * 1e100, f)  # density 1: a mass of 6e300, moments of 1e500
    with pytest.raises(ValueError, match=r"fall below float64's .*larger `mass` or `density`"):
        dz.Body.from_mesh(v * 1e-100, f)
    with pytest.raises(ValueError, match=r"`density` × its volume .* is beyond"):
        dz.Body.from_mesh(v * 1e105, f)


def _two_boxes(offset, *, inward=False, scale=1.0):
    v, f = box_mesh(1.0, 2.0, 3.0)
    w, g = box_mesh(scale, 2.0 * scale, 3.0 * scale, offset=offset)
    return np.concatenate([v, w]), np.concatenate([f, (g[:, ::-1] if inward else g) + 8])


@pytest.mark.parametrize("offset, scale, why", [
    ((0.5, 0.0, 0.0), 1.0, "one inside the other"),   # the issue's: overlapping by half
    ((0.5, 1.0, 1.5), 1.0, "one inside the other"),   # at a corner
    ((0.0, 0.0, 0.0), 0.5, "one inside the other"),   # nested
])
def test_a_mesh_of_overlapping_parts_is_refused(offset, scale, why):
    """Two overlapping unit-density boxes of volume 6 weighed 12: the overlap counted twice."""
    v, f = _two_boxes(offset, scale=scale)
    with pytest.raises(dz.MeshError, match=why):
        dz.Body.from_mesh(v, f)


def test_crossing_parts_are_refused_and_touching_parts_a_cavity_and_an_island_kept():
    v, f = box_mesh(1.0, 2.0, 3.0)
    w, g = box_mesh(3.0, 0.5, 0.5)  # through the box like a plus sign
    with pytest.raises(dz.MeshError, match="surfaces cross"):
        dz.Body.from_mesh(np.concatenate([v, w]), np.concatenate([f, g + 8]))
    assert dz.Body.from_mesh(*_two_boxes((1.0, 0.0, 0.0))).mass == pytest.approx(12.0)
    assert dz.Body.from_mesh(*_two_boxes((1.0, 0.5, 0.5))).mass == pytest.approx(12.0)
    hollow = dz.Body.from_mesh(*_two_boxes((0.0, 0.0, 0.0), inward=True, scale=0.5))
    assert hollow.mass == pytest.approx(6.0 - 6.0 / 8)
    v, f = _two_boxes((0.0, 0.0, 0.0), inward=True, scale=0.5)
    u, h = box_mesh(0.2, 0.4, 0.6)  # an island inside the cavity
    island = dz.Body.from_mesh(np.concatenate([v, u]), np.concatenate([f, h + 16]))
    assert island.mass == pytest.approx(6.0 - 6.0 / 8 + 6.0 * 0.2**3)


@pytest.mark.parametrize("error", [IndexError("index 7 is out of bounds"),
                                   NotImplementedError("file_type 'x' not supported"),
                                   ModuleNotFoundError("No module named 'networkx'",
                                                       name="networkx"),
                                   KeyError("vertex"), AttributeError("no faces")])
def test_load_turns_whatever_trimesh_raises_into_a_mesh_error(error, tmp_path, monkeypatch):
    """trimesh's IndexError, NotImplementedError and ModuleNotFoundError escaped `Body.load`,
    and `dzhanibekov run` printed a traceback (exit 1)."""
    trimesh = pytest.importorskip("trimesh")
    path = tmp_path / "part.3mf"
    path.write_bytes(b"PK\x03\x04 not really")

    def fail(*args, **kwargs):
        raise error

    monkeypatch.setattr(trimesh, "load", fail)
    with pytest.raises(dz.MeshError, match=r"`path` '.*part\.3mf' cannot be read as a mesh") \
            as caught:
        dz.Body.load(path)
    if isinstance(error, ModuleNotFoundError):
        assert "needs the module 'networkx'" in str(caught.value)


def test_a_scene_whose_mesh_trimesh_cannot_read_exits_2_with_one_line(tmp_path):
    """A mesh file of a kind trimesh does not read (its NotImplementedError escaped the
    scene's checks): `dzhanibekov run` printed a traceback and exited 1."""
    pytest.importorskip("trimesh")
    import subprocess

    import tomli_w

    (tmp_path / "part.dat").write_text("solid x\nfacet normal 0 0 1\n")
    scene = dz.SCENES["fig3a"].to_dict()
    scene["body"] = {"mesh": "part.dat", "signal_point": [0.0, 0.0, 2.0]}
    (tmp_path / "s.toml").write_text(tomli_w.dumps(scene))
    done = subprocess.run([sys.executable, "-m", "dzhanibekov", "run", str(tmp_path / "s.toml"),
                           "--out", str(tmp_path / "out")], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr and "body.mesh" in done.stderr
    assert "cannot be read as a mesh (NotImplementedError" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
