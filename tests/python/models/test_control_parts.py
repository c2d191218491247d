"""The closed loop's parts as users meet them: a law of their own called once per sample, the
actuators' limits, momentum dumping, LVLH targets, bad input."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import dzhanibekov as dz
from dzhanibekov.methods import DEFAULT_MAX_STEPS


def state(traj: dz.Trajectory, kind: str) -> dict[str, np.ndarray]:
    out, at = {}, 0
    for name, width, _, _ in dz._core.model_info(kind).state:
        out[name] = traj.parts[kind][:, at:at + width]
        at += width
    return out


def feedback(q: np.ndarray, omega: np.ndarray, kp: float, kd: float) -> np.ndarray:
    """Quaternion feedback toward the identity, written here: τ = −K_p 2 sgn(q₀) q_v − K_d ω."""
    return -kp * 2 * math.copysign(1.0, q[0]) * q[1:] - kd * omega


def test_a_law_of_your_own_is_called_once_per_sample_and_matches_the_built_in_one() -> None:
    kp, kd, period = 0.3, 1.2, 0.25
    calls: list[float] = []

    def law(t: float, q: np.ndarray, omega: np.ndarray, field: np.ndarray,
            h: np.ndarray) -> np.ndarray:
        calls.append(t)
        assert q.shape == (4,) and omega.shape == field.shape == h.shape == (3,)
        assert not field.any()                    # no field: the magnetometer reads zeros
        return feedback(q, omega, kp, kd)

    body = dz.Body((2.0, 3.0, 4.0))
    q0 = Rotation.from_rotvec([0.4, -0.3, 0.9]).as_quat(scalar_first=True)
    mine = dz.simulate(dz.System(body, parts=[dz.Controller(law, period)]), (0.02, 0.0, -0.01),
                       q0, t_end=30.0, frames=61, method="dop853", rtol=1e-12)
    # every sample time once, in order, however many stages dop853 evaluated
    assert calls == pytest.approx(list(np.arange(len(calls)) * period), abs=1e-12)
    assert len(calls) in (120, 121)
    assert mine.nfev > 10 * len(calls)
    built = dz.simulate(dz.System(body, parts=[dz.QuaternionFeedback(kp, kd, period)]),
                        (0.02, 0.0, -0.01), q0, t_end=30.0, frames=61, method="dop853",
                        rtol=1e-12)
    assert np.abs(mine.q - built.q).max() < 1e-12
    assert np.abs(state(mine, "controller")["wheel_momentum"]
                  - state(built, "quaternion_feedback")["wheel_momentum"]).max() < 1e-12


def test_a_law_that_fails_stops_the_run_with_its_error() -> None:
    body = dz.Body((2.0, 3.0, 4.0))

    def broken(t: float, *args: object) -> np.ndarray:
        if t > 1.0:
            raise KeyError("no such mode")
        return np.zeros(3)

    with pytest.raises(KeyError, match="no such mode"):
        dz.simulate(dz.System(body, parts=[dz.Controller(broken, 0.5)]), (0, 0, 1.0),
                    t_end=5.0, method="rk4", dt=0.1)

    def short(*args: object) -> list[float]:
        return [0.0, 1.0]

    def lopsided(*args: object) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros(4), np.zeros(2)     # six numbers, but not a torque and a dipole

    for bad, got in [(short, r"got list of shape \(2,\) at t = 0"),
                     (lopsided, r"got a torque ndarray of shape \(4,\) at t = 0")]:
        with pytest.raises(ValueError, match=r"the `law` function must return a torque \(three "
                           r"real numbers\) or a pair \(torque, dipole\) of three each, " + got):
            dz.simulate(dz.System(body, parts=[dz.Controller(bad, 0.5)]), (0, 0, 1.0),
                        t_end=5.0, method="rk4", dt=0.1)


def test_a_law_may_command_the_magnetorquers_too() -> None:
    n = dz.circular_orbit_rate(500e3)
    field = dz.MagneticField(n, 1.0)
    seen: list[np.ndarray] = []

    def law(t: float, q: np.ndarray, omega: np.ndarray, b: np.ndarray,
            h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        seen.append(b.copy())
        return np.zeros(3), np.array([0.0, 0.0, 5.0])   # beyond the coil's limit of 1

    sat = dz.System(dz.Body((0.03, 0.04, 0.02)),
                    parts=[dz.Controller(law, 1.0, field=field, max_dipole=1.0)])
    traj = dz.simulate(sat, (0.0, 0.0, 0.0), t_end=10.0, frames=11, method="dop853")
    s = state(traj, "controller")
    assert np.all(s["dipole"][1:] == [0.0, 0.0, 1.0])
    assert np.all(s["saturated"][1:, 0] == 1 << 8)       # coil z (bit 6 + 2)
    assert 1e-5 < np.linalg.norm(seen[0]) < 5e-5        # tesla, in orbit at 500 km
    assert np.abs(traj.omega[-1]).max() > 0             # the field turned the body


def test_magnetorquers_saturate_per_coil() -> None:
    n = dz.circular_orbit_rate(500e3)
    bdot = dz.BDot(dz.MagneticField(n, 1.7), gain=1e-3, period=1.0, max_dipole=(0.1, 0.2, 0.05))
    sat = dz.System(dz.Body((0.0419, 0.0419, 0.00667)), torques=[bdot])
    traj = dz.simulate(sat, np.radians([6.0, -5.0, 6.0]), t_end=600.0, frames=601,
                       method="dop853")
    s = state(traj, "bdot")
    limit = np.array([0.1, 0.2, 0.05])
    assert np.all(np.abs(s["dipole"]) <= limit)
    at_limit = np.abs(s["dipole"]) == limit
    bits = s["saturated"][:, 0].astype(int)
    flagged = (bits[:, None] >> np.arange(3)) & 1
    assert np.array_equal(flagged.astype(bool), at_limit)
    assert at_limit.any()


def test_wheels_stay_within_their_limits_and_say_when_they_are_cut() -> None:
    qf = dz.QuaternionFeedback(kp=1.0, kd=3.0, period=0.5, torque_limit=0.01,
                               momentum_limit=0.05)
    sat = dz.System(dz.Body((10.0, 12.0, 8.0)), parts=[qf])
    q0 = Rotation.from_rotvec(np.radians(90) * np.array([1, 1, 1]) / math.sqrt(3))
    traj = dz.simulate(sat, (0.0, 0.0, 0.0), q0.as_quat(scalar_first=True), t_end=600.0,
                       frames=1201, method="dop853")
    s = state(traj, "quaternion_feedback")
    assert np.abs(s["wheel_torque"]).max() <= 0.01
    assert np.abs(s["wheel_momentum"]).max() <= 0.05 * (1 + 1e-9)
    assert np.abs(s["wheel_momentum"]).max() > 0.05 * (1 - 1e-6)   # it reached the limit
    bits = s["saturated"][:, 0].astype(int)
    assert (bits & 0b000111).any() and (bits & 0b111000).any()
    # and the slew still ends at the target
    angle = 2 * np.arctan2(np.linalg.norm(traj.q[:, 1:], axis=1), np.abs(traj.q[:, 0]))
    assert angle[0] == pytest.approx(math.pi / 2) and angle[-1] < 1e-3


def test_a_target_fixed_in_lvlh_keeps_a_body_at_rest_in_it() -> None:
    n = dz.circular_orbit_rate(500e3)
    qf = dz.QuaternionFeedback(kp=1e-3, kd=2e-2, period=1.0, frame="lvlh", orbit_rate=n)
    sat = dz.System(dz.Body((2.0, 3.0, 1.0)), parts=[qf], torques=[dz.GravityGradient(n)])
    omega0, q0 = dz.lvlh_start(n, pitch=0.05)
    traj = dz.simulate(sat, omega0, q0, t_end=2 * math.pi / n, frames=201, method="dop853")
    rel = dz.lvlh_attitude(traj, n)
    angle = 2 * np.arctan2(np.linalg.norm(rel[:, 1:], axis=1), np.abs(rel[:, 0]))
    assert angle[0] == pytest.approx(0.05) and angle[-1] < 1e-4


def test_dumping_drains_the_wheels_momentum_while_the_body_is_held() -> None:
    n = dz.circular_orbit_rate(500e3)
    field = dz.MagneticField(n, math.radians(97.4))
    hold = dz.QuaternionFeedback(kp=2e-3, kd=4e-2, period=1.0, momentum=(0.02, -0.01, 0.015),
                                 feedforward="gyroscopic")
    dump = dz.MomentumDumping(field, gain=5e-4, period=1.0, max_dipole=0.5)
    body = dz.Body((0.2, 0.25, 0.15))
    runs = {}
    for parts in ([hold], [hold, dump]):
        sat = dz.System(body, parts=parts)
        traj = dz.simulate(sat, (0.0, 0.0, 0.0), t_end=3 * 2 * math.pi / n, frames=301,
                           method="dop853")
        runs[len(parts)] = np.linalg.norm(state(traj, "quaternion_feedback")["wheel_momentum"],
                                          axis=1)
    assert runs[1][-1] == pytest.approx(runs[1][0], rel=1e-6)   # held: nothing to take it
    assert runs[2][-1] < 0.05 * runs[2][0]


def true_field(t: np.ndarray, q: np.ndarray, n: float, inclination: float) -> np.ndarray:
    """The untilted dipole's field in body axes (Wertz App. H.2), written here:
    B = B_eq (d − 3 (d·r) r), B_eq = moment n² / μ, d = (0, sin i, cos i)."""
    d = np.array([0.0, math.sin(inclination), math.cos(inclination)])
    r = np.stack([np.cos(n * t), np.sin(n * t), np.zeros_like(t)], axis=-1)
    world = 7.708e15 * n * n / 3.986004418e14 * (d - 3.0 * (r @ d)[:, None] * r)
    return np.einsum("fji,fj->fi", Rotation.from_quat(q, scalar_first=True).as_matrix(), world)


def noisy_bdot_run(t_end: float, noise: float, bias: tuple[float, float, float]
                   ) -> tuple[dz.Trajectory, float, float]:
    n, inclination = dz.circular_orbit_rate(500e3), 1.2
    bdot = dz.BDot(dz.MagneticField(n, inclination), gain=3e-5, period=1.0,
                   magnetometer=dz.Magnetometer(noise, bias))
    sat = dz.System(dz.Body((0.042, 0.042, 0.0067)), torques=[bdot])
    # frames at each sample (the state before its update) and halfway through each hold
    traj = dz.simulate(sat, np.radians([3.0, -2.0, 4.0]), t_end=t_end,
                       frames=int(2 * t_end) + 1, method="rk4", dt=0.25)
    return traj, n, inclination


def test_the_magnetometers_noise_has_its_bias_and_deviation() -> None:
    sigma, bias = 2e-7, (3e-7, 0.0, -1e-7)
    traj, n, inclination = noisy_bdot_run(400.0, sigma, bias)
    # the field measured at sample k (held in the state through hold k) less the truth at k
    measured = state(traj, "bdot")["field"][1::2]
    truth = true_field(traj.t[0:-1:2], traj.q[0:-1:2], n, inclination)
    error = measured - truth
    assert np.abs(truth).max() > 50 * sigma
    samples = len(error)                                         # 400 samples, 3 axes each
    assert np.abs(error.mean(axis=0) - bias).max() < 4 * sigma / math.sqrt(samples)
    assert error.std(axis=0) == pytest.approx([sigma] * 3, rel=0.12)
    # the axes' noises and successive samples are uncorrelated
    z = (error - bias) / sigma
    assert np.abs(np.corrcoef(z.T)[np.triu_indices(3, 1)]).max() < 4 / math.sqrt(samples)
    lag = np.mean(z[1:] * z[:-1], axis=0)
    assert np.abs(lag).max() < 4 / math.sqrt(samples)


def test_sensor_noise_is_reproducible_and_sample_k_draws_the_same_whatever_the_length() -> None:
    sigma = 2e-7
    short, n, inclination = noisy_bdot_run(100.0, sigma, (0.0, 0.0, 0.0))
    again, _, _ = noisy_bdot_run(100.0, sigma, (0.0, 0.0, 0.0))
    long, _, _ = noisy_bdot_run(300.0, sigma, (0.0, 0.0, 0.0))
    assert np.array_equal(short.parts["bdot"], again.parts["bdot"])

    def noise(traj: dz.Trajectory, samples: int) -> np.ndarray:
        measured = state(traj, "bdot")["field"][1:2 * samples:2]
        return measured - true_field(traj.t[0:2 * samples:2], traj.q[0:2 * samples:2], n,
                                     inclination)

    # the runs' times differ in their last bits (so do the B-dot dipoles, a difference of
    # nearly equal fields); the draws of samples 0..99 do not
    first, same = noise(short, 100), noise(long, 100)
    assert np.abs(first).max() > sigma
    assert np.abs(first - same).max() < 1e-9 * sigma
    assert np.abs(noise(long, 300)[100:]).max() > sigma       # later samples draw anew


def test_wheels_catch_the_papers_box_flipping_about_its_intermediate_axis() -> None:
    # Fig. 3a's box spun about its intermediate axis flips every ~50 s; wheels under feedback
    # toward its start attitude stop it and hold it: the body at rest, the wheels hold all of L
    inertia, omega0 = np.array([52.0833, 27.0833, 41.6666]), (0.01, 0.01, 1.0)
    box = dz.Body(tuple(inertia))
    free = dz.simulate(box, omega0, t_end=100.0, frames=501, method="dop853", flips=True)
    qf = dz.QuaternionFeedback(10.0, 30.0, period=0.1, torque_limit=5.0, momentum_limit=60.0,
                               feedforward="gyroscopic")
    held = dz.simulate(dz.System(box, parts=[qf]), omega0, t_end=100.0, frames=501,
                       method="dop853", flips=True)
    assert free.flips == 2 and held.flips == 0
    assert dz.pointing_angle(held)[-1] < 1e-9
    assert np.abs(held.omega[-1]).max() < 1e-9
    s = state(held, "quaternion_feedback")
    assert np.abs(s["wheel_torque"]).max() <= 5.0
    assert np.linalg.norm(s["wheel_momentum"][-1]) == pytest.approx(
        np.linalg.norm(inertia * omega0), rel=1e-9)


def test_the_parts_state_reaches_xarray_by_field_and_a_file_keeps_them(
        tmp_path: Path) -> None:
    n = dz.circular_orbit_rate(500e3)
    bdot = dz.BDot(dz.MagneticField(n, 1.7), gain=3e-5, period=1.0, max_dipole=(0.2, 0.2, 1e-4))
    sat = dz.System(dz.Body((0.042, 0.042, 0.0067)), torques=[bdot],
                    parts=[dz.QuaternionFeedback(1e-3, 1e-2, 1.0, torque_limit=1e-5)])
    traj = dz.simulate(sat, np.radians([6.0, -5.0, 6.0]), t_end=20.0, frames=21,
                       method="dop853")
    x = traj.to_xarray()
    assert list(x["part_kind"].values) == ["quaternion_feedback", "bdot"]
    for kind in ("bdot", "quaternion_feedback"):
        for name, values in state(traj, kind).items():
            var = x[f"{kind}_{name}"]
            assert var.dims == (("time", "axis") if values.shape[1] == 3 else ("time",))
            assert np.array_equal(var.values.reshape(values.shape), values)
    assert x["bdot_saturated"].values.any() and x["quaternion_feedback_saturated"].values.any()
    # saved by their models' declarations (issue 29's seam): the same system, the same state
    pytest.importorskip("h5netcdf")
    back = dz.load(dz.save(traj, tmp_path / "run.nc"))
    assert back.system == sat and back.system.parts[0].torque_limit == 1e-5
    for kind in ("bdot", "quaternion_feedback"):
        np.testing.assert_array_equal(back.parts[kind], traj.parts[kind])


@pytest.mark.parametrize("make, name", [
    (lambda f: dz.BDot(f, gain=-1.0, period=1.0), "gain"),
    (lambda f: dz.BDot(f, gain=1.0, period=0.0), "period"),
    (lambda f: dz.BDot(f, gain=1.0, period=1.0, max_dipole=(0.1, 0.0, 0.1)), "max_dipole"),
    (lambda f: dz.BDot(f, gain=1.0, period=1.0, rates="sun sensor"), "rates"),
    (lambda f: dz.BDot(f, gain=1.0, period=1.0, magnetometer=dz.Magnetometer(-1.0)),
     "noise"),
    (lambda f: dz.Gyro(angle_random_walk=-1e-6), "angle_random_walk"),
    (lambda f: dz.QuaternionFeedback(1.0, 1.0, 1.0, target=(0, 0, 0, 0)), "target"),
    (lambda f: dz.QuaternionFeedback(1.0, 1.0, 1.0, frame="lvlh"), "orbit_rate"),
    (lambda f: dz.QuaternionFeedback(1.0, 1.0, 1.0, axes=[(1, 0, 0), (0, 1, 0), (1, 1, 0)]),
     "axes"),
    (lambda f: dz.QuaternionFeedback(1.0, -1.0, 1.0), "kd"),
    (lambda f: dz.QuaternionFeedback(1.0, 1.0, 1.0, torque_limit=0.0), "torque_limit"),
    (lambda f: dz.ResidualDipole(dz.MagneticField(1e-3, 4.0), (0, 0, 1)), "inclination"),
    (lambda f: dz.ResidualDipole(dz.MagneticField(-1e-3, 1.0), (0, 0, 1)), "orbit_rate"),
])
def test_bad_parameters_are_refused_by_name(make: object, name: str) -> None:
    field = dz.MagneticField(1e-3, 1.0)
    with pytest.raises(ValueError, match=f"`{name}`"):
        make(field)  # type: ignore[operator]


def test_objects_of_the_wrong_kind_are_refused() -> None:
    with pytest.raises(TypeError, match="`field` must be a dz.MagneticField"):
        dz.BDot(1e-3, gain=1.0, period=1.0)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="`gyro` must be a dz.Gyro"):
        dz.QuaternionFeedback(1.0, 1.0, 1.0, gyro=dz.Magnetometer())  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="`law` must be callable"):
        dz.Controller(3.0, 1.0)


@pytest.mark.parametrize("period, t_end, max_steps", [
    (1e-3, 1e6, 10**8), (1e-9, 1e3, DEFAULT_MAX_STEPS), (5e-324, 1.0, DEFAULT_MAX_STEPS)])
def test_a_law_sampled_more_often_than_max_steps_allows_is_refused_naming_t_end(
        period: float, t_end: float, max_steps: int) -> None:
    # each sample time ends a step of its own: more of them than max_steps is refused before
    # the run starts (no sample time is ever listed, so a 1 kHz law over 10^6 s costs its
    # 10^9 steps, not 64 GB; else this test would take minutes)
    fast = dz.BDot(dz.MagneticField(dz.circular_orbit_rate(500e3), 1.2), gain=1e-5,
                   period=period)
    with pytest.raises(ValueError, match=f"`t_end`.*sample times.*max_steps = {max_steps}"):
        dz.simulate(dz.System(dz.Body((0.042, 0.042, 0.0067)), torques=[fast]),
                    (0.05, -0.03, 0.07), t_end=t_end, frames=2, method="dop853",
                    max_steps=max_steps)


def test_wheels_given_a_torque_follow_their_limits_line_and_report_each_cut() -> None:
    # open loop: a law that asks the wheels for a constant body torque of 0.12 about z, on
    # motors of 0.1 and wheels of 0.37, held for 0.5. As the actuators are documented: each
    # command is cut at its sample so that the wheel lands on its momentum limit at the
    # hold's end, then to the torque limit. So the z wheel's momentum (ḣ = −τ) runs down at
    # 0.1 (torque limit) to −0.35 at t = 3.5, at (−0.37 + 0.35)/0.5 = 0.04 (momentum limit)
    # to −0.37 at t = 4, and stays; the body, at rest at the start, holds I ω = −h
    period, tau_max, h_max, inertia = 0.5, 0.1, 0.37, (2.0, 3.0, 4.0)
    law = dz.Controller(lambda t, q, omega, field, h: (0.0, 0.0, 0.12), period=period,
                        torque_limit=tau_max, momentum_limit=h_max)
    traj = dz.simulate(dz.System(dz.Body(inertia), parts=[law]), (0.0, 0.0, 0.0),
                       t_end=6.0, frames=25, method="dop853", rtol=1e-12)
    t = traj.t
    line = np.where(t <= 3.5, -0.1 * t, np.maximum(-0.35 - 0.04 * (t - 3.5), -h_max))
    s = state(traj, "controller")
    h = s["wheel_momentum"]
    assert np.abs(h[:, 2] - line).max() < 1e-12
    assert np.all(h[:, :2] == 0.0)
    assert np.abs(inertia[2] * traj.omega[:, 2] + h[:, 2]).max() < 1e-12
    # each frame shows the command held since its last sample, and what cut it then
    last = np.floor(t / period - 1e-9) * period           # frame 0: before any sample
    held = np.where(last < 3.5, -0.1, np.where(last < 4.0, -0.04, 0.0))
    assert np.abs(s["wheel_torque"][1:, 2] - held[1:]).max() < 1e-12
    cut = dz.saturation(traj, "controller")
    assert np.array_equal(cut["torque"][1:, 2], last[1:] < 3.5)
    assert np.array_equal(cut["momentum"][1:, 2], last[1:] >= 3.5)
    assert not cut["torque"][:, :2].any() and not cut["momentum"][:, :2].any()
