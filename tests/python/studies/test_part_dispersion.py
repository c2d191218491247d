"""Studies over the parts' parameters (issues 29, 31): ``dz.PartDispersion`` draws any number
parameter of any part by name, and ``dz.monte_carlo`` asks of such systems whether a spin goes
flat — with no damping in the antennas none does (the energy is kept), with ample damping
every one does."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz

BODY = dz.Body((1.0, 2.0, 3.0))
DAMPED = dz.System(BODY, parts=[dz.Damper(0.05, 0.02), dz.Wheel((0.0, 0.0, 1.0), 0.1)],
                   torques=[dz.ConstantTorque((0.0, 0.0, 1e-3))])


def test_a_relative_spread_is_the_truncated_normal_law_it_says():
    disperse = dz.PartDispersion(DAMPED, 0, damping=0.1)
    rng = np.random.default_rng(0)
    c = np.array([disperse(rng).parts[0].damping for _ in range(4000)])
    # mean c and standard deviation 0.1 c (a truncation at 10 spreads removes nothing)
    assert abs(c.mean() - 0.02) < 4 * 0.002 / np.sqrt(len(c))
    assert abs(c.std() / 0.02 - 0.1) < 0.01


def test_the_rest_of_the_system_is_the_nominal_one():
    drawn = dz.PartDispersion(DAMPED, "damper", inertia=0.2)(np.random.default_rng(3))
    assert drawn.body == BODY and drawn.parts[1:] == DAMPED.parts[1:]
    assert drawn.torques == DAMPED.torques
    assert drawn.parts[0].damping == 0.02 and drawn.parts[0].inertia != 0.05
    # a damper's law is DamperDispersion's: the same numbers in the same order
    both = dz.PartDispersion(DAMPED, 0, inertia=0.1, damping=0.3)(np.random.default_rng(5))
    alone = dz.DamperDispersion(DAMPED.parts[0], inertia=0.1,
                                damping=0.3)(np.random.default_rng(5))
    assert both.parts[0] == alone


def whip(k: int, damping: float = 0.05) -> dz.Hinge:
    """One of two whip antennas on opposite sides of a spinning cylinder's waist, radial,
    flapping out of the spin plane (hinge axis tangential), with no spring."""
    a = k * np.pi
    radial = np.array([np.cos(a), np.sin(a), 0.0])
    tangent = np.array([-np.sin(a), np.cos(a), 0.0])
    return dz.Hinge(0.05, (1e-6, 0.05 * 0.25 / 3, 0.05 * 0.25 / 3), 0.3 * radial, tangent,
                    radial, 0.5, 0.0, damping)


SATELLITE = dz.System(dz.Body.cylinder(0.3, 1.5, mass=10.0), parts=[whip(0), whip(1)])
SPIN = (0.1, 0.0, 2.0)   # about z, the cylinder's axis of least inertia, slightly off


def test_each_part_of_a_model_is_drawn_on_its_own():
    drawn = dz.PartDispersion(SATELLITE, "hinge",
                              damping=lambda rng: rng.uniform(0, 1))(np.random.default_rng(1))
    a, b = (p.damping for p in drawn.parts)
    assert a != b and 0 < a < 1 and 0 < b < 1
    assert drawn.parts[0].length == 0.5 and drawn.body == SATELLITE.body


def test_shared_draws_one_value_for_every_part_of_the_model():
    disperse = dz.PartDispersion(SATELLITE, "hinge", shared=True, damping=0.5)
    drawn = disperse(np.random.default_rng(4))
    a, b = (p.damping for p in drawn.parts)
    assert a == b != 0.05
    assert "shared=True" in repr(disperse)


def _study(damping, n=4):
    return dz.monte_carlo(dz.PartDispersion(SATELLITE, "hinge", damping=damping), SPIN, n,
                          seed=1, t_end=300.0, ask="flat_spin", dt=1e-2, frames=101)


def test_without_damping_no_spin_goes_flat_and_the_energy_is_kept():
    study = _study(lambda rng: 0.0)
    assert study.kind == "system" and study.runs == 4
    assert study.p == 0.0
    run = study.rerun(2)
    assert all(p.damping == 0.0 for p in run.system.parts)
    assert run.drift.energy < 1e-9           # nothing dissipates: the energy is kept
    assert np.isnan(dz.flat_spin_time(run))


def test_with_ample_damping_every_spin_goes_flat():
    study = _study(lambda rng: rng.uniform(0.02, 0.1))
    assert study.p == 1.0
    run = study.rerun(0)
    # the run balanced its energy with the work its hinges dissipated
    assert run.drift.energy_balance < 1e-8
    assert 0 < dz.flat_spin_time(run) < 300.0


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(part="slosh", damping=0.1), ValueError, r"`part` 'slosh' names no part.*damper"),
    (dict(part=5, damping=0.1), ValueError, r"index of the system's 3 parts"),
    (dict(part=0, sigma0=0.1), ValueError, r"`sigma0` is no number parameter of a damper"),
    (dict(part=0, damping=-0.1), ValueError, r"`damping` must be a non-negative"),
    (dict(part=0), ValueError, r"at least one parameter"),
    (dict(part=True, damping=0.1), TypeError, r"`part` must be an index"),
])
def test_bad_input_is_refused_by_name(kwargs, error, match):
    with pytest.raises(error, match=match):
        dz.PartDispersion(DAMPED, **kwargs)


def test_a_system_without_a_dissipating_part_cannot_be_asked_for_a_flat_spin():
    wheel = dz.System(BODY, parts=[dz.Wheel((0.0, 0.0, 1.0), 0.1)])
    with pytest.raises(ValueError, match=r"`ask='flat_spin'` needs a part that dissipates"):
        dz.monte_carlo(wheel, SPIN, 4, seed=1, t_end=1.0, ask="flat_spin")


def final_spin(traj: dz.Trajectory) -> float:
    """A continuous outcome: the body's rate about z at the end."""
    return float(traj.omega[-1, 2])


def test_a_study_records_each_part_parameter_each_sample_ran_with(tmp_path):
    disperse = dz.PartDispersion(SATELLITE, "hinge", damping=0.5,
                                 stiffness=lambda rng: rng.uniform(0.0, 0.05))
    settings = dict(t_end=20.0, dt=1e-2, frames=5)
    study = dz.monte_carlo(disperse, SPIN, 4, seed=3, ask=final_spin, **settings)
    names = {f"hinge_{j}.{p}" for j in (0, 1) for p in ("damping", "stiffness")}
    # the dispersed parameters vary: columns and telling name them; the others do not
    assert names <= set(study.columns()) and "hinge_0.length" not in study.columns()
    assert study.inputs["hinge_0.length"].tolist() == [0.5] * 4
    assert set(study.telling(count=10)) >= names
    # sample k's values are those its generator draws, each hinge its own
    for k in range(4):
        drawn = disperse(dz.montecarlo.sample_rng(3, k))
        for j in (0, 1):
            assert study.inputs[f"hinge_{j}.damping"][k] == drawn.parts[j].damping
            assert study.inputs[f"hinge_{j}.stiffness"][k] == drawn.parts[j].stiffness
    # a system rebuilt from the recorded inputs alone runs to the study's outcome, bit for bit
    k = 2
    rebuilt = dz.System(SATELLITE.body, parts=[
        dz.Hinge.from_fields("hinge", {**whip(j).fields(),
                                       **{p: float(study.inputs[f"hinge_{j}.{p}"][k])
                                          for p in ("damping", "stiffness")}})
        for j in (0, 1)])
    run = dz.simulate(rebuilt, study.inputs["omega0"][k], study.inputs["q0"][k],
                      method=study.method, **settings)
    assert final_spin(run) == study.outcomes[k]
    # and files keep them
    pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    dz.save(study, tmp_path / "study.nc")
    again = dz.load(tmp_path / "study.nc")
    for name in names:
        assert np.array_equal(again.inputs[name], study.inputs[name])
    assert again.columns().keys() == study.columns().keys()
