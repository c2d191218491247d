"""Regression tests for what the hostile-input search (test_hostile.py) found: each failed
before its fix, with an OverflowError, an AttributeError, a silent NaN or inf, a hang, or an
error that did not name the argument."""

from __future__ import annotations

import math
import subprocess
import sys
import warnings
from fractions import Fraction

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

import dzhanibekov as dz  # noqa: E402
from dzhanibekov.methods import METHODS  # noqa: E402
from dzhanibekov.plotting import figures as plotting  # noqa: E402
from dzhanibekov.scenes.scene import Draw  # noqa: E402

BODY = dz.Body(dz.PAPER_INERTIA)
W = (0.01, 0.01, 1.0)


# -- numbers beyond float64 and integers beyond the core's ---------------------------------------

@pytest.mark.parametrize("value", [10**400, -(10**400), Fraction(10**400, 3)])
def test_numbers_beyond_float64_are_a_value_error_naming_the_argument(value):
    # a run's options are checked by the core; a number float64 cannot hold, before it
    with pytest.raises(ValueError, match=r"`t_end` must be finite in float64"):
        dz.simulate(BODY, W, t_end=value)
    with pytest.raises(ValueError, match=r"`a` must be positive and finite in float64"):
        dz.Body.box(value, 1.0, 1.0)


def test_integers_beyond_64_bits_are_a_value_error_naming_the_argument():
    with pytest.raises(ValueError, match=r"`max_steps` must be at most 9223372036854775807"):
        dz.simulate(BODY, W, t_end=1.0, frames=3, max_steps=2**64)
    with pytest.raises(ValueError, match=r"`frames` must be at most"):
        dz.summarize(BODY, W, frames=2**64)
    with pytest.raises(ValueError, match=r"`n_around` must be at most"):
        dz.ellipsoid_mesh((1.0, 1.0, 1.0), 2**64, 3)
    # the largest allowed is a clear "too large", not an overflow
    with pytest.raises(ValueError, match=r"max_steps|steps"):
        dz.simulate(BODY, W, t_end=1e300, frames=3, dt=1e-300, max_steps=2**63 - 1)


def test_flips_must_be_a_bool():
    with pytest.raises(TypeError, match="`flips` must be True or False"):
        dz.simulate(BODY, W, t_end=1.0, flips="yes")
    with pytest.raises(TypeError, match="`flips`"):
        dz.simulate(BODY, W, t_end=1.0, flips=np.array([True, False]))


def test_a_body_that_is_not_one_is_named_as_the_body():
    with pytest.raises(TypeError, match=r"`system` must be a Body or its principal moments"):
        dz.simulate("paper", W)
    with pytest.raises(ValueError, match=r"`body` must be a Body .*`inertia` must be finite"):
        dz.flip_period((1.0, np.nan, 2.0), W)


# -- boxes ------------------------------------------------------------------------------------------

def test_a_box_whose_moments_overflow_names_its_edges():
    with pytest.raises(ValueError, match=r"`a, b, c` and `mass` must give principal moments"):
        dz.Body.box(1e200, 1.0, 1.0)
    with pytest.raises(ValueError, match=r"`a, b, c` and `mass`"):
        dz.Body.box(1e-200, 1e-200, 1.0)  # Iz = m (a² + b²) / 12 underflows


@pytest.mark.parametrize("edges, mass", [((1e-170, 2e-170, 3e-170), 1e40),
                                         ((1e160, 2e160, 3e160), 1e-20)])
def test_boxes_whose_squares_over_or_underflow_still_get_their_moments(edges, mass):
    # before, a² underflowed to 0 (or overflowed) although the moments fit in float64
    a, b, c = (Fraction(x) for x in edges)
    m = Fraction(mass)
    exact = [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12]
    got = dz.Body.box(*edges, mass=mass).inertia
    for g, e in zip(got, exact):
        assert abs(Fraction(g) - e) <= Fraction(1e-15) * e


def test_box_vertices_refuse_edges_that_are_not_lengths():
    for bad in (np.nan, 0.0, -1.0, math.inf):
        with pytest.raises(ValueError, match="`a` must be positive and finite"):
            dz.box_vertices(bad)
    with pytest.raises(TypeError, match="`c` must be a real number"):
        dz.box_vertices(1.0, 2.0, "3")


# -- the ellipsoid and the polhodes -----------------------------------------------------------------

@pytest.mark.parametrize("inertia", [(1e300, 1e300, 1e299), (1e-300, 1e-300, 1.5e-300),
                                     (1.0, 1e100, 1e100)])
def test_poinsot_semi_axes_of_extreme_moments_are_finite_and_right(inertia):
    axes = dz.ellipsoid_semi_axes(inertia, "poinsot")
    i = np.array(inertia)
    assert np.isfinite(axes).all() and (axes > 0).all()
    # ∝ 1/√I, with the volume of the gyration ellipsoid (√I): checked on ratios
    np.testing.assert_allclose(axes * np.sqrt(i / i.max()), axes[0] * np.sqrt(i[0] / i.max()),
                               rtol=1e-13)
    gyration = dz.ellipsoid_semi_axes(inertia)
    np.testing.assert_allclose(np.prod(axes / gyration.max()), np.prod(gyration / gyration.max()),
                               rtol=1e-12)


def test_the_convention_is_checked_before_the_body():
    with pytest.raises(ValueError, match="`convention` must be one of"):
        dz.ellipsoid_semi_axes(BODY, np.array(["gyration"]))


def test_polhodes_refuse_bad_input_and_scale_to_any_body():
    with pytest.raises(ValueError, match="`energy` must be non-negative"):
        plotting.polhodes((1.0, 2.0, 3.0), -1.0)
    with pytest.raises(ValueError, match="`inertia`"):
        plotting.polhodes((1.0, np.nan, 3.0), 1.0)
    with pytest.raises(ValueError, match="`points` must be at least 2"):
        plotting.polhodes((1.0, 2.0, 3.0), 1.0, points=1)
    with pytest.raises(ValueError, match="`energy`.*beyond float64"):
        plotting.polhodes((5e-324, 1e-323, 1.5e-323), 1e300)  # rates of 1e311
    for scale in (1e-300, 1.0, 1e300):
        inertia = np.array([1.0, 2.0, 3.0]) * scale
        family, separatrix = plotting.polhodes(inertia, 0.5 * scale * 1e-6)
        assert len(family) == 16 and len(separatrix) == 2
        for curve in family + separatrix:  # on ω·Iω = 2E: 1e-6 in units of the moments
            np.testing.assert_allclose(np.sum(inertia / scale * curve**2, axis=1), 1e-6,
                                       rtol=1e-9)


# -- rotation ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("size", [1e-306, 1e-200, 1e-160, 1e160, 1e200, 1e300])
def test_quaternions_of_any_finite_size_rotate(size):
    # |q|² under- or overflows for all of these; before, they were refused as "not finite"
    q = np.array([0.3, -0.1, 0.7, 0.2])
    points = np.array([[1.0, 2.0, 3.0], [-4.0, 0.5, 1e300]])
    expected = Rotation.from_quat(q[[1, 2, 3, 0]]).apply(points)
    got = dz.rotate(q * size, points)
    assert (np.abs(got - expected) <= 1e-14 * np.abs(points).max(axis=1)[:, None]).all()


def test_points_that_would_overflow_are_refused_and_the_largest_allowed_are_not():
    q = np.array([0.9, 0.3, -0.2, 0.1])
    with pytest.raises(ValueError, match="`points` must have coordinates of magnitude at most"):
        dz.rotate(q, [1e308, 1e308, 1e308])
    edge = dz.simulate.__globals__["MAX_COORDINATE"]
    out = dz.rotate(q, [edge, -edge, edge])
    assert np.isfinite(out).all()
    np.testing.assert_allclose(np.linalg.norm(out / edge), math.sqrt(3), rtol=1e-15)


# -- scenes and plans --------------------------------------------------------------------------------

def test_plans_and_results_take_only_their_own_kind():
    with pytest.raises(TypeError, match="`scene` must be a Scene, got int"):
        dz.scenes.make_plan(3)
    with pytest.raises(TypeError, match="`plan` must be a Plan"):
        dz.scenes.execute(dz.SCENES["fig3a"])
    with pytest.raises(TypeError, match="`scene` must be a Scene or a SceneResult"):
        plotting.path_figure(np.zeros(3))


def test_scene_files_that_are_not_text_or_not_paths_are_named(tmp_path):
    with pytest.raises(TypeError, match="`path` must be a scene file"):
        dz.load_scene(None)
    with pytest.raises(dz.SceneError, match="`path` is empty"):
        dz.load_scene("  ")
    with pytest.raises(dz.SceneError, match="a\x00b: cannot be read"):
        dz.load_scene("a\x00b")
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\xff\xfe title = 'x'")
    with pytest.raises(dz.SceneError, match=r"binary.toml: cannot be read \(not UTF-8 text"):
        dz.load_scene(binary)
    with pytest.raises(TypeError, match="`text` must be a str"):
        dz.Scene.from_toml(b"title = 'x'", "x")
    with pytest.raises(TypeError, match="`data` must be a mapping"):
        dz.Scene.from_dict([("title", "x")], "x")


# -- the exact solution --------------------------------------------------------------------------

def test_an_exact_phase_beyond_float64_is_an_error_not_nan():
    # t_end · |ω| = 1e309 radians: the elliptic argument overflows; it used to give NaN frames
    with pytest.raises(ValueError, match=r"exact solution needs its phase .* float64"):
        dz.simulate(BODY, (10.0, 1.0, 10.0), t_end=1e308, frames=3, method="exact")
    # rates far from 1 run in their own units, where the span itself is what overflows
    with pytest.raises(ValueError, match=r"t_end · max\|omega0\| = .* float64"):
        dz.simulate(BODY, (1e300, 1e299, 1e300), t_end=1e10, frames=3, method="exact")


def test_an_exact_motion_a_hair_from_the_separatrix_ends():
    # m1 underflowed to 0 off the separatrix: K = ∞ and the quadrature looped for ever
    code = ("import warnings, dzhanibekov as dz; warnings.simplefilter('ignore');"
            "b = dz.Body((1.0, 1e100, 1.0754702073318891));"
            "w = [2.361424947942503e146, -2.6696505570924898e147, -2.6696505570924898e147];"
            "t = dz.simulate(b, w, t_end=3.7458085940996626e-198, frames=8, method='exact');"
            "import numpy as np; assert np.isfinite(t.omega).all() and np.isfinite(t.q).all()")
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)


# -- rates of any size -----------------------------------------------------------------------------------

# the methods that run the free body (splitting_exact runs bodies under torques)
_FREE_METHODS = [m for m, info in dz.METHODS.items() if "free" in info.models]


@pytest.mark.parametrize("method", _FREE_METHODS)
@pytest.mark.parametrize("k", [-1000, -600, 600, 900])
def test_a_run_at_any_rate_is_the_run_at_unit_rate_scaled(method, k):
    # (ω, t) → (2^k ω, t / 2^k) leaves the motion unchanged; the runs integrate in the
    # motion's own units, so the results are the same bits, scaled. Before, rates of 1e-300
    # stood still (their products underflowed) and rates of 1e200 diverged.
    omega = np.array([0.01, 0.3, 1.0])
    dt = None if method in ("dopri5", "dop853") else 0.01
    unit = dz.simulate(BODY, omega, t_end=20.0, frames=11, dt=dt, method=method)
    scale = 2.0**k
    scaled = dz.simulate(BODY, omega * scale, t_end=20.0 / scale, frames=11,
                         dt=None if dt is None else dt / scale, method=method)
    np.testing.assert_array_equal(scaled.q, unit.q)
    np.testing.assert_array_equal(scaled.omega / scale, unit.omega)
    np.testing.assert_array_equal(scaled.flip_times * scale, unit.flip_times)
    assert tuple(scaled.drift) == tuple(unit.drift) and scaled.n_steps == unit.n_steps


# bodies in orbit: moments scaled by 2^a, rates (and the orbit's) by 2^k, time by 2^-k; a
# torque scales as I ω², by 2^(a + 2k), a wheel's momentum as I ω, by 2^(a + k): the motion is
# the same, and in the motion's own units the run is the same bits
_ORBIT_MODELS = {
    "gravity_gradient": (lambda m, s: dict(torques=[dz.GravityGradient(0.8 * s)]),
                         ("rk4", "dop853", "splitting_exact")),
    "body_torque": (lambda m, s: dict(torques=[dz.ConstantTorque(
        np.array([0.1, -0.2, 0.05]) * (m * s * s))]), ("rk4", "dop853", "splitting_exact")),
    "world_torque": (lambda m, s: dict(torques=[dz.ConstantTorque(
        np.array([0.0, 0.3, -0.1]) * (m * s * s), frame="world")]),
                     ("rk4", "dop853", "splitting_exact")),
    "wheels_in_orbit": (lambda m, s: dict(parts=[dz.Wheel((0, 1, 0), 0.7 * m * s)],
                                          torques=[dz.GravityGradient(0.8 * s)]),
                        ("rk4", "dop853")),
    "wheel": (lambda m, s: dict(parts=[dz.Wheel((1, 1, 0), -0.4 * m * s)]),
              ("rk4_projected", "dopri5")),
}
_SCALES = [(900, 0), (-900, 0), (0, 900), (0, -900), (900, -450), (-900, 450), (600, -900)]


@pytest.mark.parametrize("a, k", _SCALES, ids=[f"I2^{a},w2^{k}" for a, k in _SCALES])
@pytest.mark.parametrize("model", list(_ORBIT_MODELS))
def test_a_run_in_orbit_at_any_scale_is_the_unit_run_scaled(model, a, k):
    make, methods = _ORBIT_MODELS[model]
    if model.endswith("_torque") and abs(a + 2 * k) > 1000:
        pytest.skip("the torque itself, 2^(a + 2k) of order one, is beyond float64")
    inertia = np.array([2.0, 3.0, 1.5])
    omega, q0 = np.array([0.3, -0.7, 1.1]), np.array([0.6, -0.2, 0.7, 0.3])
    m, s = 2.0**a, 2.0**k
    for method in methods:
        dt = None if METHODS[method].adaptive else 0.01
        unit = dz.simulate(dz.System(dz.Body(inertia), **make(1.0, 1.0)), omega, q0,
                           t_end=10.0, frames=11, dt=dt, method=method)
        scaled = dz.simulate(dz.System(dz.Body(inertia * m), **make(m, s)), omega * s, q0,
                             t_end=10.0 / s, frames=11, dt=None if dt is None else dt / s,
                             method=method)
        np.testing.assert_array_equal(scaled.q, unit.q, err_msg=method)
        np.testing.assert_array_equal(scaled.omega / s, unit.omega, err_msg=method)
        assert tuple(scaled.drift) == tuple(unit.drift), method
        assert scaled.n_steps == unit.n_steps, method


def test_a_span_beyond_float64_in_the_motions_units_is_named():
    with pytest.warns(dz.StepSizeWarning), \
            pytest.raises(ValueError, match=r"t_end · max\|omega0\|"):
        dz.simulate(BODY, (1e300, 1e299, 1e300), t_end=1e10, frames=3, dt=1e-5,
                    max_steps=2**63 - 1)
    with pytest.raises(ValueError, match=r"t_end · Ω"):
        dz.simulate(BODY, (1e300, 1e299, 1e300), t_end=1e10, frames=3, dt=None)


# -- the step guard for moments no body has ------------------------------------------------------------

def test_the_step_guard_knows_that_impossible_moments_precess_faster():
    # (1, 1, 1000) breaks the triangle inequality: its rates turn 999 times faster than the
    # bound Ω of |ω|, so a step of Ω·dt = 0.01 is far beyond RK4's stability for them
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.InertiaWarning)
        rod = dz.Body((1.0, 1.0, 1000.0))
    with pytest.warns(dz.StepSizeWarning, match="stability limit"):
        try:
            dz.simulate(rod, (1.0, 0.0, 0.1), t_end=1.0, frames=2, dt=1e-3)
        except ValueError as err:
            assert "diverged" in str(err)
    # a real body keeps the bound Ω, and no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        dz.simulate((1.0, 1.0, 1.9), (1.0, 0.0, 0.1), t_end=1.0, frames=2, dt=1e-4)


# -- figures of scenes at rest or far from the origin --------------------------------------------------

def test_figures_of_a_body_at_rest_draw_without_warnings():
    scene = dz.Scene(name="rest", title="at rest", inertia=(1.0, 2.0, 3.0),
                     omega0=(0.0, 0.0, 0.0), t_end=1.0, frames=3, signal_point=(0.0, 0.0, 0.0),
                     draw=Draw(path=True, momentum=True,
                               figures=("path", "omega", "invariants", "polhode", "phases")))
    # the orbit's figures draw a run in orbit, or with a wheel (the pointing figure: with
    # wheels under feedback): the same body at rest there
    needs = {"lvlh": dict(orbit=dz.GravityGradient(1.0)),
             "wheel_off": dict(wheel=dz.Wheel((0.0, 0.0, 1.0), 0.5)),
             "pointing": dict(parts=(dz.QuaternionFeedback(1.0, 2.0, 0.25),))}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for name, figure in plotting.FIGURE_FUNCTIONS.items():
            if name in ("energy_balance", "part_motion", "capture"):
                continue  # a run with an energy sink: at rest below
            figure(scene.replace(**needs[name]) if name in needs else scene).canvas.draw()
        # a body and a slosh tank at rest: no energy, no work, no flips
        body = dz.Body.from_tensor(np.diag([1.0, 2.0, 3.0]), mass=1.0)
        tank = dz.Slosh(0.1, (0.0, 0.0, 0.5), 0.3, 0.01, (1.0, 0.0, 0.0))
        traj = dz.simulate(dz.System(body, parts=[tank]), (0.0, 0.0, 0.0), t_end=1.0, frames=3,
                           dt=0.01)
        for figure in (dz.plotting.energy_balance_figure, dz.plotting.part_motion_figure,
                       dz.plotting.capture_figure):
            figure(traj).canvas.draw()


def test_phases_need_at_least_one_column():
    with pytest.raises(ValueError, match="`columns` must be at least 1"):
        plotting.phases_figure(dz.SCENES["example"], columns=0)


# -- batches, sweeps, grids and maps (the second part of the table) -----------------------------

def test_batches_and_sweeps_of_rates_far_from_one_are_their_single_runs():
    # rows of rates 2^±200 run in their own units, alone, as simulate runs them: every row
    # is the single run bit for bit, and (powers of two scale exactly) the run at unit rate
    unit = np.array([[0.01, 0.01, 1.0], [0.02, 0.1, 1.0]])
    at_one = dz.simulate(BODY, unit, t_end=100.0, frames=5, dt=1e-2)
    for s in (2.0**200, 2.0**-200):
        rows = unit * s
        run = dict(t_end=100.0 / s, frames=5, dt=1e-2 / s)
        batch = dz.simulate(BODY, rows, **run)
        swept = dz.sweep(BODY, rows, progress=False, **run)
        assert np.array_equal(batch.q, at_one.q) and np.array_equal(batch.omega, at_one.omega * s)
        for k in range(2):
            alone = dz.simulate(BODY, rows[k], **run)
            assert np.array_equal(batch[k].q, alone.q) and np.array_equal(batch[k].omega, alone.omega)
            assert np.array_equal(batch[k].flip_times, alone.flip_times)
            assert np.array_equal(alone.flip_times, at_one[k].flip_times / s)
            assert swept.flips[k] == len(alone.flip_times) > 0
            assert tuple(float(d[k]) for d in swept.drift) == tuple(alone.drift)


def test_a_scaled_run_starts_at_the_rates_given():
    # a component 2^-1080 below the largest underflows in the run's own units; frame 0 is
    # still the start as given
    omega0 = (1e150, 0.0, 1e150 * 2.0**-1060)
    traj = dz.simulate(BODY, omega0, t_end=1e-149, frames=3, dt=1e-151)
    assert tuple(traj.omega[0]) == omega0


def test_a_batch_checks_flips_and_a_grid_names_its_axes():
    with pytest.raises(TypeError, match="`flips` must be True or False"):
        dz.simulate(BODY, np.ones((2, 3)), t_end=1.0, flips=2)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="`axes` of `grid`"):
        dz.grid()
    with pytest.raises(ValueError, match=r"`axes\[1\]` must be finite"):
        dz.grid([0.1, 0.2], [1.0, math.nan])


def test_the_separatrix_gap_refuses_bad_input_and_keeps_near_symmetric_digits():
    from dzhanibekov.plotting.maps import separatrix_gap
    with pytest.raises(TypeError, match="`inertia`"):
        separatrix_gap(None, (1.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="`inertia` must hold positive"):
        separatrix_gap((1.0, -1.0, 2.0), (1.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="`omega` must be finite"):
        separatrix_gap((1.0, 2.0, 3.0), (math.inf, 0.0, 0.0))
    # moments 1e-8 apart at 1e-150: the difference keeps its digits, nothing underflows
    inertia = np.array([1.0, 1.0 + 1e-8, 1.02]) * 1e-150
    omega = np.array([1.0, 0.0, 1e-8]) * 1e-151
    gap = float(separatrix_gap(inertia, omega))
    i, w = inertia * 1e150, omega * 1e151
    mid = i[1]
    assert gap == pytest.approx(np.sum(i * (i - mid) * w**2) / np.sum((i * w) ** 2), rel=1e-6)


def test_a_flip_period_below_float64_is_an_error_not_zero():
    # found by the fuzz target: rates near the largest float64 on moments 1e89 apart flip
    # every 1e-349 time units, which float64 rounds to 0 (a period no motion has)
    with pytest.warns(dz.InertiaWarning):  # moments no body has, but a motion all the same
        body = dz.Body((4.330480332540362e262, 6.183675162794051e173, 4.4207826926609875e262))
    with pytest.raises(ValueError, match=r"`omega0` must give a flip period that float64 holds"):
        dz.flip_period(body, (-1.8518347881150608e304, 2.781342323133997e-309, -4.091738259870177e149))


@pytest.mark.parametrize("method", _FREE_METHODS)
def test_moments_of_any_size_are_the_run_at_unit_moments(method):
    # found by the hostile search: moments of 1e-306 and rates of 1e-15 made angular momenta
    # of 1e-321 (subnormal, a few bits) in the splitting, which moved |L| by 1 %. Moments
    # beyond 2^±64 now run over a power of two near the largest (exact): the same bits.
    inertia = np.array([1.0, 1.0, 0.01626])
    omega0 = (1e-300, 5e-324, 1e-15)
    run = dict(t_end=5e15, frames=3, dt=None if method in ("dopri5", "dop853") else 1e13,
               method=method)
    unit = dz.simulate(dz.Body(inertia), omega0, **run)
    for k in (-1015, -600, 600, 1000):
        tiny = dz.simulate(dz.Body(inertia * 2.0**k), omega0, **run)
        assert np.array_equal(tiny.q, unit.q) and np.array_equal(tiny.omega, unit.omega)
        assert tuple(tiny.drift) == tuple(unit.drift) and tiny.drift.momentum < 1e-13
