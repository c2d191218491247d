"""What a body's numbers mean, the same for every kind of body (issue 24, "Bodies").

- A symmetric top is one whatever the round-off: two moments equal within
  ``dz.SYMMETRY_TOLERANCE`` (1e-9, relative) give no intermediate axis, no flips and an
  infinite flip period in every path (a run, a batch, the exact method, ``flip_period``); a
  body within ``dz.NEAR_SYMMETRY`` warns.
- ``inertia`` is in the body frame's order for every body (a box, its mesh, its file, its
  tensor); ``principal_moments`` is sorted, with ``principal_directions``.
- The gyration ellipsoid's semi-axes are the radii of gyration ``√(I/m)``.
- ``summarize`` and ``flip_period`` take the (M, 3) batches ``simulate`` takes;
  ``Batch.flip_times_padded`` is the xarray's array; the DataFrame's index is the xarray's
  time dimension; a Body's repr shows its mass and centre of mass.

References are independent of the code: the textbook moments of the solids (Goldstein's
table), the symmetric top's motion (Landau & Lifshitz §33: the transverse rates turn at
``Ω = (I3 − I) ω3 / I`` and nothing flips), scipy's Rotation for turned tensors.
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import dzhanibekov as dz

CYLINDER = (3.0, 20.0)  # radius, height: the cylinder
OMEGA = (0.3, 0.01, 1.0)  # the start: mostly about the symmetry axis z


def cylinder_moments(r, h, m=1.0):  # Goldstein's table
    side = m * (3 * r * r + h * h) / 12
    return np.array([side, side, m * r * r / 2])


def flips_every_way(body, omega, t_end=200.0):
    """The flips of `body` from `omega` by every path that counts them."""
    counts = {
        method: len(dz.simulate(body, omega, t_end=t_end, method=method).flip_times)
        for method in ("rk4", "dop853", "exact")
    }
    batch = dz.simulate(body, [omega, omega], t_end=t_end)
    counts["batch"] = int(batch.flips.max())
    counts["summarize"] = dz.summarize(body, omega, t_end=t_end).flips
    return counts


# -- 1. symmetric tops ------------------------------------------------------------------------

def test_a_cylinder_mesh_is_a_symmetric_top_like_the_cylinder(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    r, h = CYLINDER
    mesh = trimesh.creation.cylinder(radius=r, height=h)
    path = tmp_path / "cylinder.stl"
    mesh.export(path)
    solid = dz.Body.cylinder(r, h)
    for body in (dz.Body.from_mesh(mesh.vertices, mesh.faces, mass=1.0),
                 dz.Body.load(path, mass=1.0)):
        x, y, z = body.inertia
        # the test is about round-off: the mesh's two transverse moments are not equal
        assert x != y and abs(x - y) < 1e-13 * x, body.inertia
        assert body.intermediate_axis is None
        assert body.asymmetry <= dz.SYMMETRY_TOLERANCE
        assert dz.flip_period(body, OMEGA) == np.inf
        assert flips_every_way(body, OMEGA) == flips_every_way(solid, OMEGA) == {
            "rk4": 0, "dop853": 0, "exact": 0, "batch": 0, "summarize": 0}


@pytest.mark.parametrize("seed", range(4))
def test_a_turned_tensor_of_a_symmetric_top_is_one(seed):
    turn = Rotation.random(random_state=seed)
    r = turn.as_matrix()
    tensor = r @ np.diag(cylinder_moments(*CYLINDER)) @ r.T
    body = dz.Body.from_tensor(tensor)
    assert not body.is_principal
    assert body.intermediate_axis is None, body.inertia
    omega = turn.apply(OMEGA)  # the same start in the tensor's axes
    assert dz.flip_period(body, omega) == np.inf
    assert flips_every_way(body, omega) == {
        "rk4": 0, "dop853": 0, "exact": 0, "batch": 0, "summarize": 0}
    # the exact method's symmetric top (Landau & Lifshitz §33) keeps |ω| and ω along the
    # symmetry axis, whatever the round-off in the two equal moments
    traj = dz.simulate(body, omega, t_end=50.0, method="exact")
    axis = r[:, 2]
    np.testing.assert_allclose(traj.omega @ axis, 1.0, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(traj.omega, axis=1),
                               np.linalg.norm(OMEGA), rtol=1e-12)


def test_any_turned_symmetric_tensor_has_moments_equal_to_round_off():
    # what the tolerance is for: over many turns, the eigensolver's two equal moments differ
    moments = cylinder_moments(*CYLINDER)
    gaps = []
    for seed in range(40):
        r = Rotation.random(random_state=seed).as_matrix()
        body = dz.Body.from_tensor(r @ np.diag(moments) @ r.T)
        gaps.append(body.asymmetry)
        assert body.intermediate_axis is None
    assert max(gaps) > 0  # round-off is there
    assert max(gaps) < 1e-3 * dz.SYMMETRY_TOLERANCE  # and far below the tolerance


def test_the_tolerance_is_relative_and_the_near_band_warns():
    tol = dz.SYMMETRY_TOLERANCE
    for scale in (1e-200, 1.0, 1e200):
        within = dz.Body(np.array([1.0, 1.0 + 0.5 * tol, 0.2]) * scale)
        assert within.intermediate_axis is None
        with pytest.warns(dz.InertiaWarning, match="nearly symmetric"):
            near = dz.Body(np.array([1.0, 1.0 + 1e-7, 0.2]) * scale)
        assert near.intermediate_axis == 0  # 1 is between 0.2 and 1 + 1e-7
        apart = dz.Body(np.array([1.0, 1.0 + 10 * dz.NEAR_SYMMETRY, 0.2]) * scale)  # silent
        assert apart.intermediate_axis == 0
    with pytest.warns(dz.InertiaWarning, match="nearly symmetric"):
        dz.Body.from_tensor(np.diag([1.0, 1.0 + 1e-7, 0.2]))
    # a solid's moments are exact by its dimensions: a 1000:1 plate (moments 1e-6 apart) is
    # what it is, no warning
    plate = dz.Body.box(1e3, 1.0, 1e-3)
    assert tol < plate.asymmetry <= dz.NEAR_SYMMETRY and plate.intermediate_axis == 1
    assert dz.NEAR_SYMMETRY > tol


# -- 2. the order of the moments ------------------------------------------------------------

def test_inertia_is_in_the_body_frames_order_for_every_kind_of_body(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    a, b, c = 20.0, 10.0, 15.0
    textbook = np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 12  # Goldstein
    mesh = trimesh.creation.box(extents=(a, b, c))
    mesh.apply_translation((4.0, -3.0, 2.0))  # off the origin: the products are round-off
    path = tmp_path / "box.stl"
    mesh.export(path)
    tiny = Rotation.from_rotvec((1e-4, -2e-4, 3e-4)).as_matrix()  # a box turned a little
    bodies = {
        "box": dz.Body.box(a, b, c),
        "moments": dz.Body(tuple(textbook)),
        "mesh": dz.Body.from_mesh(mesh.vertices, mesh.faces, mass=1.0),
        "file": dz.Body.load(path, mass=1.0),
        "tensor": dz.Body.from_tensor(tiny @ np.diag(textbook) @ tiny.T),
        "composite": dz.Body.compose([(dz.Body.box(a, b, c), (1.0, 2.0, 3.0))]),
    }
    for name, body in bodies.items():
        np.testing.assert_allclose(body.inertia, textbook, rtol=1e-7, err_msg=name)
        np.testing.assert_allclose(body.principal_moments, np.sort(textbook), rtol=1e-7,
                                   err_msg=name)
        d = body.principal_directions
        np.testing.assert_allclose(np.linalg.det(d), 1.0, atol=1e-12, err_msg=name)
        np.testing.assert_allclose(d @ np.diag(body.principal_moments) @ d.T, body.tensor,
                                   atol=1e-9 * textbook.max(), err_msg=name)
        assert body.intermediate_axis == 2, name  # z: 41.7 between 27.1 and 52.1


# -- 3. the gyration ellipsoid ----------------------------------------------------------------

def test_the_gyration_ellipsoid_is_the_radii_of_gyration_whatever_the_mass():
    r = 2.0
    for mass in (1.0, 7.0, 1e-3):
        # a ball's radius of gyration is r √(2/5) (I = 2 m r² / 5), with no mass in it
        np.testing.assert_allclose(dz.ellipsoid_semi_axes(dz.Body.sphere(r, mass=mass)),
                                   r * np.sqrt(0.4), rtol=1e-14)
        a, b, c = 1.0, 2.0, 3.0  # a box: k_x = √((b² + c²) / 12), …
        np.testing.assert_allclose(
            dz.ellipsoid_semi_axes(dz.Body.box(a, b, c, mass=mass)),
            np.sqrt(np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 12), rtol=1e-14)
        # Poinsot's is drawn at the same volume
        poinsot = dz.ellipsoid_semi_axes(dz.Body.box(a, b, c, mass=mass), "poinsot")
        np.testing.assert_allclose(np.prod(poinsot), np.prod(
            np.sqrt(np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 12)), rtol=1e-13)
    nut = dz.Body.wing_nut()
    semi = dz.ellipsoid_semi_axes(nut)
    np.testing.assert_allclose(semi, np.sqrt(np.array(nut.inertia) / nut.mass), rtol=1e-14)
    np.testing.assert_allclose(semi, (4.59, 10.38, 10.11), atol=0.01)  # mm
    # moments alone count as a unit mass: the paper's √I
    np.testing.assert_allclose(dz.ellipsoid_semi_axes((4.0, 9.0, 9.0)), (2.0, 3.0, 3.0))


# -- 5. result types --------------------------------------------------------------------------

def test_summarize_and_flip_period_take_the_batches_simulate_takes():
    body = dz.Body(dz.PAPER_INERTIA)
    starts = np.array([(0.01, 0.01, 1.0), (0.0, 0.0, 1.0), (0.3, 0.0, 1.0)])
    summaries = dz.summarize(body, starts, t_end=100.0)
    assert isinstance(summaries, tuple) and len(summaries) == 3
    batch = dz.simulate(body, starts, t_end=100.0)
    for k, s in enumerate(summaries):
        # a batch takes one step for every row; alone, with that step, each row is the same
        alone = dz.summarize(body, starts[k], t_end=100.0, dt=s.dt)
        np.testing.assert_array_equal(s.flip_times, alone.flip_times)
        np.testing.assert_array_equal(s.flip_times, batch.flip_times[k])
    periods = dz.flip_period(body, starts)
    assert periods.shape == (3,)
    for k in range(3):
        assert periods[k] == dz.flip_period(body, tuple(starts[k]))
    # the messages say what is taken
    with pytest.raises(ValueError, match=r"\(3,\) or \(M, 3\), got \(2, 2, 3\)"):
        dz.flip_period(body, np.ones((2, 2, 3)))
    with pytest.raises(ValueError, match=r"\(3,\) or \(M, 3\), got \(2, 2, 3\)"):
        dz.summarize(body, np.ones((2, 2, 3)))


def test_a_batchs_flip_times_padded_are_its_xarrays_and_one_time_name():
    pytest.importorskip("xarray")
    pytest.importorskip("pandas")
    batch = dz.simulate(dz.PAPER_INERTIA, [(0.01, 0.01, 1.0), (0.0, 0.0, 1.0)], t_end=100.0)
    padded = batch.flip_times_padded
    assert padded.shape == (2, max(len(f) for f in batch.flip_times))
    for row, times in zip(padded, batch.flip_times):
        np.testing.assert_array_equal(row[: len(times)], times)
        assert np.isnan(row[len(times):]).all()
    ds = batch.to_xarray()
    np.testing.assert_array_equal(ds.flip_times.values, padded)
    traj = batch[0]
    assert traj.to_dataframe().index.name in traj.to_xarray().dims
    assert batch.to_dataframe().index.names[1] in ds.dims


# -- 6. the repr ------------------------------------------------------------------------------

def test_a_bodys_repr_shows_its_mass_and_centre_of_mass():
    assert "mass=2.5" in repr(dz.Body.box(1.0, 2.0, 3.0, mass=2.5))
    assert "mass" not in repr(dz.Body((1.0, 2.0, 3.0)))
    nut = dz.Body.wing_nut()
    text = repr(nut)
    assert f"mass={nut.mass!r}" in text and "center_of_mass=" in text
    assert repr(float(nut.center_of_mass[2])) in text
