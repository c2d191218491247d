"""Monte Carlo studies: a probability known by construction and the coverage of its intervals,
reproducibility (seeds, threads, chunks, rerun), the rare-event estimator against plain
sampling, bad input naming the sample, files and the figure.

The references are independent of the package: the textbook stability of spin about the
intermediate axis (a body with moments (1, 3, I_z) spun about z tumbles iff I_z < 3), the
normal law (scipy.stats.norm) for the probabilities built from it, numpy's own
``SeedSequence.spawn`` for the seeding, and single runs of ``dz.simulate`` for the reruns.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import stats

import dzhanibekov as dz
from dzhanibekov.montecarlo import binomial_interval, sample_rng, separatrix_distance

SPIN = (1e-3, 1e-3, 1.0)
"""About z, with a small wobble: z is the intermediate axis of (1, 3, I_z) iff I_z < 3."""

LONG = 1e6
"""t_end of the known-probability studies (the exact method's cost does not grow with it)."""


def uniform_iz(rng: np.random.Generator) -> tuple[float, float, float]:
    return (1.0, 3.0, rng.uniform(2.7, 3.7))


def margin_above() -> float:
    """How far above 3 an I_z still lets the wobble about z (now the major axis) swing wide
    enough that y, the intermediate axis, comes nearest to L — which counts as a flip. On the
    orbit of (u, v, w) = (a, a, 1), where L_x = 0: L_y² (1/I_y − 1/I_z) = 2E − L²/I_z, and y
    is nearest when L_y² > L²/2 (textbook energy and momentum; the definition of a flip in
    dz.simulate's docs). Returns the I_z − 3 below which that happens, with room (×10)."""
    a = SPIN[0]
    iz = 3.0
    excess = a * a * (1 + 3 - (1 + 9) / iz)            # 2E − L²/I_z at I_z ≈ 3
    # L_y² ≈ excess · 3 I_z / (I_z − 3) > L²/2 ≈ I_z²/2  ⇔  I_z − 3 < 6 excess / I_z
    return 10 * 6 * excess / iz


def margin_below() -> float:
    """How far below 3 an I_z may leave the first flip after LONG: the linearised growth rate
    λ² = (I_z − 1)(3 − I_z)/3 (Landau & Lifshitz §37) and a first flip near ln(4/ε)/λ, ε the
    wobble, ×10 for room."""
    first = math.log(4 / SPIN[0])
    lam = first / LONG
    return 10 * 3 * lam * lam / 2


@pytest.fixture(scope="module")
def known() -> dz.MonteCarlo:
    """80 000 samples of the known-probability case (p = 0.3): 200 studies of 400."""
    return dz.monte_carlo(uniform_iz, SPIN, 80_000, seed=20261125, t_end=LONG)


# -- a probability known by construction --------------------------------------------------------


def test_the_known_case_tumbles_exactly_when_z_is_the_intermediate_axis(known):
    iz = known.inputs["inertia"][:, 2]
    assert known.method == "exact" and known.outcomes.dtype == bool
    differ = known.outcomes != (iz < 3)
    # only where the textbook margins say the verdict within t_end may differ (none expected)
    near = (iz > 3 - margin_below()) & (iz < 3 + margin_above())
    assert not (differ & ~near).any(), iz[differ & ~near]
    assert differ.sum() <= 1


def test_the_interval_covers_the_known_probability_in_about_95_percent_of_studies(known):
    # 200 independent studies of 400 samples each: slices of one study, its samples
    # independent by construction (one SeedSequence child each)
    studies = [known[400 * i:400 * (i + 1)] for i in range(200)]
    assert all(s.runs == 400 for s in studies)
    assert np.array_equal(studies[3].samples, np.arange(1200, 1600))
    assert np.array_equal(studies[3].inputs["inertia"], known.inputs["inertia"][1200:1600])
    for method in ("wilson", "clopper-pearson"):
        cover = [lo <= 0.3 <= hi for lo, hi in
                 (s.confidence_interval(method=method) for s in studies)]
        # binomial(200, 0.95): below 180 has probability 2e-4 for an exact 95% interval
        assert sum(cover) >= 180, (method, sum(cover))
    # the level is settable: 99% intervals are wider and cover at least as often
    wide = [s.confidence_interval(level=0.99) for s in studies[:20]]
    narrow = [s.interval for s in studies[:20]]
    assert all(w[0] < n[0] and w[1] > n[1] for w, n in zip(wide, narrow))


def test_the_estimate_converges_like_one_over_root_n(known):
    # the spread of the estimate over disjoint groups of n samples, times √n, is √(p(1 − p))
    # for every n (a sample standard deviation of g groups has relative error ≈ 1/√(2g))
    target = math.sqrt(0.3 * 0.7)
    for n in (100, 400, 1600):
        groups = known.outcomes[: (80_000 // n) * n].reshape(-1, n).mean(axis=1)
        spread = groups.std(ddof=1) * math.sqrt(n)
        tolerance = 4 / math.sqrt(2 * len(groups))
        assert abs(spread / target - 1) < tolerance, (n, spread, target)
    # and the whole study's estimate is within 4 standard errors of 0.3
    assert abs(known.p - 0.3) < 4 * math.sqrt(0.21 / known.runs)


def test_binomial_intervals_against_their_definitions():
    # Wilson: the interval is where the score statistic |x/n − p| / √(p(1 − p)/n) is ≤ z
    z = stats.norm.ppf(0.975)
    x, n = 7, 50
    lo, hi = binomial_interval(x, n)
    for p in (lo, hi):
        assert abs(abs(x / n - p) / math.sqrt(p * (1 - p) / n) - z) < 1e-9
    # Clopper–Pearson: the binomial tails at the ends are α/2 each
    lo, hi = binomial_interval(x, n, method="clopper-pearson")
    assert abs(stats.binom.sf(x - 1, n, lo) - 0.025) < 1e-9
    assert abs(stats.binom.cdf(x, n, hi) - 0.025) < 1e-9
    assert binomial_interval(0, 20, method="clopper-pearson")[0] == 0.0
    assert binomial_interval(20, 20, method="clopper-pearson")[1] == 1.0


# -- reproducibility ----------------------------------------------------------------------------


def dispersed_spin(rng: np.random.Generator) -> np.ndarray:
    return np.array([rng.normal(0, 0.05), rng.normal(0, 0.05), 1.0])


DISPERSION = dz.InertiaDispersion((1.0, 2.0, 2.05), moments=0.03)


def test_sample_k_has_the_kth_child_of_the_seed_sequence():
    children = np.random.SeedSequence(99).spawn(40)
    for k in (0, 1, 17, 39):
        ours = sample_rng(99, k).random(3)
        numpy_s = np.random.Generator(np.random.PCG64(children[k])).random(3)
        assert np.array_equal(ours, numpy_s)
    study = dz.monte_carlo(DISPERSION, dispersed_spin, 40, seed=99, t_end=10.0)
    rng = np.random.Generator(np.random.PCG64(children[17]))
    body = DISPERSION(rng)  # the system first, then omega0
    assert np.array_equal(study.inputs["inertia"][17], body.inertia)
    assert np.array_equal(study.inputs["omega0"][17], dispersed_spin(rng))


def test_the_same_seed_gives_the_same_samples_whatever_n_threads_and_chunks():
    kwargs = dict(seed=5, t_end=60.0, method="rk4", dt=0.02, ask="flips")
    whole = dz.monte_carlo(DISPERSION, dispersed_spin, 70, threads=2, **kwargs)
    assert whole.outcomes.sum() > 10  # some flip, some do not
    for other in (dz.monte_carlo(DISPERSION, dispersed_spin, 70, threads=1, chunk=7, **kwargs),
                  dz.monte_carlo(DISPERSION, dispersed_spin, 45, chunk=16, **kwargs)):
        m = other.runs
        assert np.array_equal(other.outcomes, whole.outcomes[:m])
        for name, values in whole.inputs.items():
            assert np.array_equal(other.inputs[name], values[:m]), name


def test_the_planned_step_depends_on_the_seed_only():
    # dt=None: the pilot samples 0 … 15 plan it, drawn whatever n is
    kwargs = dict(seed=8, t_end=30.0, method="rk4")
    one = dz.monte_carlo(DISPERSION, dispersed_spin, 3, **kwargs)
    many = dz.monte_carlo(DISPERSION, dispersed_spin, 40, chunk=5, **kwargs)
    assert one.dt is not None and one.dt == many.dt
    assert np.array_equal(one.outcomes, many.outcomes[:3])


def test_rerun_is_the_single_run_of_the_sample_bit_for_bit():
    study = dz.monte_carlo(dz.InertiaDispersion((1.0, 2.0, 2.05), moments=0.03, axes_deg=3.0),
                           dispersed_spin, 40, seed=11, t_end=60.0, method="rk4", dt=0.02,
                           ask="flips", chunk=16)
    assert study.outcomes.max() > 0
    for k in (0, 5, 21, 39):
        traj = study.rerun(k)
        # the run made from the study's record of the sample's inputs, by dz.simulate alone
        tensor, omega0, q0 = (study.inputs[n][k] for n in ("tensor", "omega0", "q0"))
        body = dz.Body.from_tensor(tensor)
        assert np.array_equal(study.inputs["axes"][k], body.principal_axes)
        assert np.array_equal(study.inputs["inertia"][k], body.inertia)
        alone = dz.simulate(body, omega0, q0, t_end=60.0, frames=2, dt=0.02)
        assert np.array_equal(traj.q, alone.q) and np.array_equal(traj.omega, alone.omega)
        assert np.array_equal(traj.flip_times, alone.flip_times)
        assert len(traj.flip_times) == study.outcomes[k]


def test_memory_grows_with_the_outcomes_only():
    import tracemalloc

    def peak(n: int, keep: bool) -> int:
        tracemalloc.start()
        dz.monte_carlo(uniform_iz, SPIN, n, seed=1, t_end=10.0, chunk=250, keep_inputs=keep,
                       progress=False)
        top = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        return top

    peak(1000, False)  # once for what the first call allocates for good
    # a few bytes per sample (its outcome, twice while they are joined), not the ~300 that
    # keeping its inputs costs, nor its frames: the chunks come and go
    assert (peak(4000, False) - peak(1000, False)) / 3000 < 16
    assert (peak(4000, True) - peak(1000, True)) / 3000 > 150


def test_a_callable_ask_sees_the_trajectory_the_rerun_gives():
    def last_v(traj: dz.Trajectory) -> float:
        return float(traj.omega[-1, 1])

    study = dz.monte_carlo(DISPERSION, dispersed_spin, 20, seed=3, t_end=40.0, method="rk4",
                           dt=0.02, ask=last_v, frames=11, chunk=6)
    assert study.ask == "last_v" and study.outcomes.dtype == np.float64
    for k in (0, 7, 19):
        assert last_v(study.rerun(k)) == study.outcomes[k]


# -- bodies that change ---------------------------------------------------------------------------


def test_a_deployment_study_is_the_deployment_sweep_of_its_samples():
    nominal = dz.Deployment([10.0, 20.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.9)])
    disperse = dz.DeploymentDispersion(nominal, start=1.0, duration=0.2, moments=0.03)
    study = dz.monte_carlo(disperse, (0.01, 0.01, 1.0), 24, seed=2, t_end=30.0, dt=0.01,
                           chunk=10)
    assert study.kind == "deployment" and 0 < study.p < 1
    # independently: the deployments drawn again from numpy's children, swept in one call
    children = np.random.SeedSequence(2).spawn(24)
    drawn = [disperse(np.random.default_rng(c)) for c in children]
    assert np.array_equal(study.inputs["knot_times"], [d.times for d in drawn])
    swept = dz.sweep(drawn, (0.01, 0.01, 1.0), t_end=30.0, frames=2, dt=0.01)
    assert np.array_equal(study.outcomes, swept.tumbles)
    # the deployed body tumbles iff z, spun about, ends as its intermediate axis (the
    # textbook rule, the wobble small): its deployed I_z below its I_y
    tensors = study.inputs["knot_tensors"][:, -1]
    assert np.array_equal(study.outcomes, tensors[:, 2, 2] < tensors[:, 1, 1])


def test_a_damped_body_goes_flat_as_its_own_run_says():
    def damped(rng: np.random.Generator) -> dz.System:
        return dz.System((1.0, 10.0, 10.0),
                         parts=[dz.DamperDispersion(dz.Damper(0.05, 0.02), damping=0.5)(rng)])

    study = dz.monte_carlo(damped, (2.0, 0.01, 0.0), 6, seed=4, t_end=1500.0, dt=0.01,
                           ask="flat_spin", frames=151)
    assert study.kind == "damper" and study.frames == 151
    # the spheres co-rotate at the start (the dampers' sigma0 is None)
    assert np.array_equal(study.inputs["damper_sigma0"], study.inputs["omega0"])
    for k in range(6):
        traj = study.rerun(k)
        assert study.outcomes[k] == (not math.isnan(dz.flat_spin_time(traj)))
    # where the energy-sink estimate (Kaplan 1976) is clearly before or after t_end, it agrees
    for k in range(6):
        damper = dz.Damper(study.inputs["damper_inertia"][k], study.inputs["damping"][k])
        estimate = dz.flat_spin_estimate(study.inputs["inertia"][k], damper,
                                         study.inputs["omega0"][k])
        if estimate < 0.7 * 1500.0 or estimate > 1.5 * 1500.0:
            assert study.outcomes[k] == (estimate < 1500.0), (k, estimate)


def test_a_fixed_system_runs_its_damper_from_its_own_start(tmp_path):
    # σ0 belongs to the damper: every sample's sphere starts there, whatever omega0 is drawn
    system = dz.System((1.0, 10.0, 10.0), parts=[dz.Damper(0.05, 0.02, sigma0=(1.5, 0.0, 0.0))])

    def sphere_start(traj: dz.Trajectory) -> float:
        return float(traj.parts["damper"][0, 0])

    study = dz.monte_carlo(system, lambda rng: (2.0, rng.normal(0, 0.01), 0.0), 4, seed=5,
                           t_end=10.0, dt=0.01, ask=sphere_start, frames=3)
    assert study.kind == "damper" and study.method == dz.methods.DEFAULT_METHOD
    assert np.array_equal(study.inputs["damper_sigma0"], np.tile([1.5, 0.0, 0.0], (4, 1)))
    assert np.allclose(study.outcomes, 1.5, rtol=1e-15, atol=0)
    for k in (0, 3):
        traj = study.rerun(k)
        assert traj.system == system
        alone = dz.simulate(system, study.inputs["omega0"][k], t_end=10.0, frames=3, dt=0.01)
        assert np.array_equal(traj.omega, alone.omega) and np.array_equal(traj.q, alone.q)
        assert np.array_equal(traj.parts["damper"], alone.parts["damper"])
        assert sphere_start(traj) == study.outcomes[k]
    # the file keeps the damper's inputs, its start included
    back = dz.load(dz.save(study, tmp_path / "damped.nc"))
    assert back.kind == "damper" and np.array_equal(back.outcomes, study.outcomes)
    for name in ("damper_inertia", "damping", "damper_sigma0", "omega0", "inertia"):
        assert np.array_equal(back.inputs[name], study.inputs[name]), name


def test_a_body_and_damper_pair_is_refused_for_a_system():
    with pytest.raises(TypeError, match=r"dz.System\(body, parts=\[damper\]\)"):
        dz.monte_carlo(((1.0, 10.0, 10.0), dz.Damper(0.05, 0.02)), (2.0, 0.01, 0.0), 4,
                       seed=1, t_end=10.0, dt=0.01)


# -- rare events ----------------------------------------------------------------------------------


def normal_iz(rng: np.random.Generator) -> tuple[float, float, float]:
    return (1.0, 3.0, rng.normal(3.25, 0.1))


P_RARE = float(stats.norm.cdf((3.0 - 3.25) / 0.1))  # 6.2e-3: I_z < 3, z intermediate


def test_the_separatrix_distance_against_the_textbook_energy_and_momentum():
    inertia = np.array([1.0, 2.0, 4.0])
    # a start on the separatrix: L² = 2E I_mid, i.e. Σ I_k (I_k − I_mid) ω_k² = 0
    w = np.array([math.sqrt(4 * 2 / 1), 0.3, 1.0])      # 1·(−1)·8 + 4·2·1 = 0
    assert abs(separatrix_distance(inertia, w)) < 1e-15
    # spin about the major and the minor axis: D = L²/2E is that moment
    assert separatrix_distance(inertia, (0.0, 0.0, 2.0)) == (4 - 2) / (4 - 1)
    assert separatrix_distance(inertia, (3.0, 0.0, 0.0)) == (1 - 2) / (4 - 1)
    # D of a general start, from the textbook energy and momentum
    w = np.array([0.3, -0.2, 0.5])
    d = (inertia**2 * w**2).sum() / (inertia * w**2).sum()
    assert math.isclose(separatrix_distance(inertia, w), (d - 2) / 3, rel_tol=1e-14)
    assert np.isinf(separatrix_distance((2.0, 2.0, 2.0), (1.0, 2.0, 3.0)))


def test_the_rare_event_estimator_agrees_with_plain_sampling():
    plain = dz.monte_carlo(normal_iz, SPIN, 6000, seed=1, t_end=LONG)
    rare = dz.monte_carlo(normal_iz, SPIN, 6000, seed=2, t_end=LONG, runs=600)
    assert rare.runs == 600 and plain.runs == 6000
    # each estimate within the other's 95% interval, and both intervals cover the known p
    assert plain.interval[0] <= rare.p <= plain.interval[1]
    assert rare.interval[0] <= plain.p <= rare.interval[1]
    for study in (plain, rare):
        assert study.interval[0] <= P_RARE <= study.interval[1]
    # a tenth of the runs, the interval of about as many plain samples as draws
    assert rare.effective_runs > 0.5 * rare.n
    width = np.diff(rare.interval)[0]
    assert width < 1.5 * np.diff(plain.interval)[0]


def test_which_samples_run_depends_on_their_inputs_only():
    a = dz.monte_carlo(normal_iz, SPIN, 3000, seed=6, t_end=LONG, runs=200)
    b = dz.monte_carlo(normal_iz, SPIN, 3000, seed=6, t_end=LONG, runs=200, chunk=333,
                       threads=1)
    assert np.array_equal(a.samples, b.samples) and np.array_equal(a.outcomes, b.outcomes)
    # the nearest half by the closed-form distance all run
    children = np.random.SeedSequence(6).spawn(3000)
    moments = np.array([normal_iz(np.random.default_rng(c)) for c in children])
    distance = np.abs(separatrix_distance(moments, SPIN))
    nearest = np.sort(np.argsort(distance, kind="stable")[:100])
    assert np.array_equal(a.samples[a.stratum == 0], nearest)
    assert a.weights[a.stratum == 0][0] == 1 / 3000
    assert math.isclose(a.weights.sum(), 1.0)
    # its samples rerun like any other
    k = int(a.samples[a.outcomes][0])
    assert len(a.rerun(k).flip_times) > 0


@pytest.mark.slow
def test_the_rare_event_estimator_is_unbiased():
    estimates = [dz.monte_carlo(normal_iz, SPIN, 4000, seed=100 + i, t_end=LONG, runs=100).p
                 for i in range(60)]
    # the mean of 60 estimates, each of the variance of ~4000 plain samples
    se = math.sqrt(P_RARE * (1 - P_RARE) / 4000 / 60)
    assert abs(np.mean(estimates) - P_RARE) < 4 * se


# -- bad input --------------------------------------------------------------------------------------


def first_where(seed: int, n: int, draws) -> int:
    """The first sample whose generator (numpy's own children of the seed) makes `draws`
    true: an independent reference for which sample a study must name."""
    for k, child in enumerate(np.random.SeedSequence(seed).spawn(n)):
        if draws(np.random.default_rng(child)):
            return k
    raise AssertionError("no such sample")


def sometimes_flat(rng: np.random.Generator) -> tuple[float, float, float]:
    # a moment that breaks the triangle inequality in 2% of draws
    return (1.0, 2.0, 3.5 if rng.uniform() < 0.02 else 2.5)


def test_a_non_physical_body_names_its_sample_and_keeps_the_ones_before():
    bad = first_where(31, 500, lambda rng: rng.uniform() < 0.02)
    with pytest.raises(dz.StudyError, match=rf"sample {bad}: .*triangle") as info:
        dz.monte_carlo(sometimes_flat, SPIN, 500, seed=31, t_end=10.0, chunk=7)
    error = info.value
    assert isinstance(error, ValueError) and error.sample == bad
    assert np.array_equal(error.samples, np.arange(bad)) and len(error.outcomes) == bad
    assert error.study is not None and error.study.runs == bad
    # the samples before it are the study's own
    again = dz.monte_carlo(sometimes_flat, SPIN, bad, seed=31, t_end=10.0)
    assert np.array_equal(again.outcomes, error.outcomes)


def test_a_dispersion_that_raises_or_returns_junk_names_its_sample():
    def negative(rng: np.random.Generator) -> dz.Body:
        return dz.Body((1.0, 2.0, 3.0 if rng.uniform() > 0.05 else -3.0))

    bad = first_where(4, 300, lambda rng: rng.uniform() <= 0.05)
    with pytest.raises(dz.StudyError, match=rf"sample {bad}: `system` failed: .*positive") \
            as info:
        dz.monte_carlo(negative, SPIN, 300, seed=4, t_end=10.0)
    assert isinstance(info.value.__cause__, ValueError)
    with pytest.raises(dz.StudyError, match="sample 0: `system` failed: TypeError"):
        dz.monte_carlo(lambda rng: "box", SPIN, 3, seed=4, t_end=10.0)
    with pytest.raises(dz.StudyError, match="sample 0: .*3 × 3"):
        dz.monte_carlo(lambda rng: np.eye(3), SPIN, 3, seed=4, t_end=10.0)


def test_a_distribution_of_the_wrong_shape_names_its_sample():
    with pytest.raises(dz.StudyError, match=r"sample 0: `omega0` failed: .*shape \(3,\)"):
        dz.monte_carlo((1.0, 2.0, 3.0), stats.norm(0, 1), 10, seed=1, t_end=10.0)
    three = stats.multivariate_normal(np.zeros(3), np.eye(3))
    study = dz.monte_carlo((1.0, 2.0, 3.0), three, 10, seed=1, t_end=10.0)
    child = np.random.SeedSequence(1).spawn(10)[4]
    assert np.array_equal(study.inputs["omega0"][4],
                          three.rvs(random_state=np.random.default_rng(child)))
    with pytest.raises(dz.StudyError, match=r"sample 0: `q0` failed"):
        dz.monte_carlo((1.0, 2.0, 3.0), SPIN, 10, seed=1, t_end=10.0, q0=stats.norm(0, 1))


def test_an_ask_that_raises_names_its_sample_and_keeps_the_outcomes_before():
    def ask(traj: dz.Trajectory) -> bool:
        if traj.omega[0, 0] > 0.1:
            raise ZeroDivisionError("no")
        return bool(traj.flips)

    def spin(rng: np.random.Generator) -> np.ndarray:
        return np.array([rng.normal(0, 0.1), 0.01, 1.0])

    bad = first_where(12, 200, lambda rng: rng.normal(0, 0.1) > 0.1)
    with pytest.raises(dz.StudyError, match=rf"sample {bad}: `ask` raised ZeroDivisionError") \
            as info:
        dz.monte_carlo((1.0, 2.0, 3.0), spin, 200, seed=12, t_end=5.0, ask=ask, frames=3,
                       chunk=9)
    error = info.value
    assert isinstance(error.__cause__, ZeroDivisionError)
    assert np.array_equal(error.samples, np.arange(bad)) and error.outcomes.dtype == bool
    assert error.study is not None and 0 <= error.study.p <= 1


def test_a_run_that_does_not_finish_names_its_sample():
    # RK4 at a step beyond its stability limit for the fastest sample only
    def spin(rng: np.random.Generator) -> np.ndarray:
        return np.array([0.0, 0.01, 1.0 if rng.uniform() > 0.1 else 400.0])

    bad = first_where(3, 100, lambda rng: rng.uniform() <= 0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dz.StepSizeWarning)
        with pytest.raises(dz.StudyError, match=rf"sample {bad}: the run did not finish "
                                                 r"\(diverged\)") as info:
            dz.monte_carlo((1.0, 2.0, 3.0), spin, 100, seed=3, t_end=20.0, method="rk4",
                           dt=0.05, chunk=16)
    assert np.array_equal(info.value.samples, np.arange(bad))


@pytest.mark.parametrize("kwargs, match", [
    (dict(n=0), "`n` must be at least 1"),
    (dict(n=-3), "`n` must be at least 1"),
    (dict(ask="tumble"), "`ask` must be one of"),
    (dict(ask="flat_spin"), "needs a part that dissipates"),
    (dict(runs=10), "`runs` must be below `n`"),
    (dict(runs=3), "`runs` must be at least 4"),
    (dict(level=1.0), "`level` must lie in"),
    (dict(interval="exact"), "`interval` must be one of"),
    (dict(seed=-1), "`seed` must be non-negative"),
    (dict(method="RK4"), "`method` must be one of"),
    (dict(chunk=0), "`chunk` must be at least 1"),
])
def test_bad_arguments_are_refused_before_any_run(kwargs, match):
    args = dict(system=(1.0, 2.0, 3.0), omega0=SPIN, n=10, seed=1, t_end=10.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        dz.monte_carlo(**args)


@pytest.mark.parametrize("kwargs, match", [
    (dict(n=2.5), "`n` must be an integer"),
    (dict(seed="x"), "`seed` must be"),
    (dict(ask=3), "`ask` must be one of"),
    (dict(t_end="1"), "`t_end` must be a real number"),
    (dict(progress="yes"), "`progress` must be"),
])
def test_arguments_of_the_wrong_kind_are_refused(kwargs, match):
    args = dict(system=(1.0, 2.0, 3.0), omega0=SPIN, n=10, seed=1, t_end=10.0)
    args.update(kwargs)
    with pytest.raises(TypeError, match=match):
        dz.monte_carlo(**args)


def test_a_study_runs_one_kind_of_system():
    deployment = dz.Deployment([1.0, 2.0], [(1.0, 2.0, 3.0), (1.0, 3.0, 2.0)])

    def mixed(rng: np.random.Generator) -> object:
        return deployment if rng.uniform() < 0.3 else dz.Body((1.0, 2.0, 3.0))

    kind = "deployment" if np.random.default_rng(
        np.random.SeedSequence(9).spawn(1)[0]).uniform() < 0.3 else "body"
    with pytest.raises(dz.StudyError, match=f"where sample 0 gave a {kind}"):
        dz.monte_carlo(mixed, SPIN, 50, seed=9, t_end=10.0, dt=0.01)


def test_numbers_have_a_mean_not_a_probability():
    study = dz.monte_carlo((1.0, 2.0, 3.0), dispersed_spin, 30, seed=2, t_end=200.0,
                           ask="flips")
    assert study.outcomes.dtype == np.int64 and study.mean == study.outcomes.mean()
    with pytest.raises(TypeError, match="yes-or-no"):
        study.p
    with pytest.raises(TypeError, match="yes-or-no"):
        study.interval
    # the standard error of a mean of numbers: the sample deviation over √n
    assert math.isclose(study.standard_error, study.outcomes.std(ddof=1) / math.sqrt(30))


# -- files, tables, the figure ---------------------------------------------------------------------


def test_a_study_saves_and_loads_with_its_inputs_and_interval(tmp_path):
    pytest.importorskip("h5netcdf")
    study = dz.monte_carlo(DISPERSION, dispersed_spin, 50, seed=1, t_end=80.0)
    back = dz.load(dz.save(study, tmp_path / "study.nc"))
    assert isinstance(back, dz.MonteCarlo)
    assert np.array_equal(back.outcomes, study.outcomes) and back.outcomes.dtype == bool
    for name, values in study.inputs.items():
        assert np.array_equal(back.inputs[name], values), name
    assert back.interval == study.interval and back.seed.entropy == 1
    with pytest.raises(ValueError, match="loaded from a file"):
        back.rerun(0)
    ds = study.to_xarray()
    assert ds.outcome.dims == ("sample",) and ds.inertia.dims == ("sample", "axis")
    assert ds.attrs["estimate"] == study.p
    rare = dz.monte_carlo(normal_iz, SPIN, 400, seed=2, t_end=LONG, runs=40)
    back = dz.load(dz.save(rare, tmp_path / "rare.nc"))
    assert back.p == rare.p and back.interval == rare.interval
    assert np.array_equal(back.samples, rare.samples)


def test_inputs_not_kept_are_drawn_again():
    kept = dz.monte_carlo(DISPERSION, dispersed_spin, 30, seed=1, t_end=10.0)
    bare = dz.monte_carlo(DISPERSION, dispersed_spin, 30, seed=1, t_end=10.0,
                          keep_inputs=False)
    assert bare.inputs == {} and np.array_equal(bare.outcomes, kept.outcomes)
    for k in (0, 29):
        for name, value in bare.inputs_of(k).items():
            assert np.array_equal(value, kept.inputs[name][k]), name
    assert bare.columns().keys() == kept.columns().keys()


def test_the_telling_inputs_are_the_ones_the_outcome_depends_on(known):
    assert "Iz" in known[:4000].telling(2)
    # a spin whose tumbling depends on its rate about x, moments fixed
    study = dz.monte_carlo((1.0, 2.0, 3.0), lambda rng: (rng.uniform(-1, 1), 0.01, 1.0), 400,
                           seed=3, t_end=300.0)
    assert study.telling(1) == ["separatrix"] or study.telling(1) == ["u0"]
    assert set(study.telling(2)) == {"u0", "separatrix"}


def test_the_figure_draws_plain_rare_and_numeric_studies(known, tmp_path):
    from matplotlib.figure import Figure

    from dzhanibekov.plotting.study import study_figure

    fig = study_figure(known[:2000], save=tmp_path / "plain.png")
    assert isinstance(fig, Figure) and (tmp_path / "plain.png").stat().st_size > 0
    assert fig.axes[0].get_xlabel() == "I_z"
    rare = dz.monte_carlo(normal_iz, SPIN, 600, seed=2, t_end=LONG, runs=60)
    assert isinstance(study_figure(rare), Figure)
    counts = dz.monte_carlo((1.0, 2.0, 3.0), dispersed_spin, 30, seed=2, t_end=200.0,
                            ask="flips")
    assert isinstance(study_figure(counts, inputs=("u0", "v0")), Figure)
    with pytest.raises(ValueError, match="`inputs` must name two of"):
        study_figure(counts, inputs=("u0", "x"))
