"""Every model the core declares (`dz.MODELS`) through every result path (issue 29):
xarray, the figures, the viewer, a batch and a study, besides the files of
`test_round_trip_models.py`. What is checked cannot be faked: what each path shows is the
run's own numbers (bit for bit), a batch row and a study sample are their single runs, and the
run keeps what its model declares it keeps (|q| = 1; the angular momentum in space where no
external torque acts)."""

from __future__ import annotations

import numpy as np
import pytest

import dzhanibekov as dz
from every_model import START, system_of

RUN = dict(t_end=1.0, frames=5, method="rk4", dt=0.01)
MODELS = list(dz.MODELS)


@pytest.fixture(scope="module", params=MODELS)
def run(request):
    name = request.param
    return name, system_of(name), dz.simulate(system_of(name), *START, **RUN)


def test_the_run_keeps_what_its_model_declares(run):
    name, _, traj = run
    keeps = dz.MODELS[name].keeps
    assert "q_norm" in keeps
    # RK4 at dt = 0.01 keeps |q| to its truncation error (about 1e-12 a unit of time here)
    np.testing.assert_allclose(np.linalg.norm(traj.q, axis=1), 1.0, rtol=0, atol=1e-10)
    if "momentum_world" in keeps:
        L = traj.momentum_world
        assert np.abs(L - L[0]).max() <= 1e-9 * np.linalg.norm(L[0]), name


def test_xarray_shows_the_runs_numbers_and_each_parts_state(run):
    pytest.importorskip("xarray")
    name, _, traj = run
    ds = traj.to_xarray()
    np.testing.assert_array_equal(ds["omega"].values, traj.omega)
    np.testing.assert_array_equal(ds["q"].values, traj.q)
    for state, block in traj.parts.items():
        # its state, and the rates of its coordinates (`<state>_<field>_rate`) if it moves
        shown = [v for v in ds.data_vars if v == state or v.startswith(f"{state}_")]
        rates = [v for v in shown if v.endswith("_rate")]
        shown = [v for v in shown if v not in rates]
        assert shown, (name, state, list(ds.data_vars))
        values = np.concatenate([ds[v].values.reshape(len(traj.t), -1) for v in shown], axis=1)
        np.testing.assert_array_equal(np.sort(values, axis=1), np.sort(block, axis=1))
        assert len(rates) == (state in traj.part_rates), (name, state, rates)
        for v in rates:
            np.testing.assert_array_equal(ds[v].values.reshape(len(traj.t), -1),
                                          traj.part_rates[state])


def test_the_figures_draw_the_runs_own_rates(run):
    name, _, traj = run
    fig = dz.plotting.omega_figure(traj)
    drawn = [line.get_ydata() for ax in fig.axes for line in ax.get_lines()][:3]
    for k in range(3):
        np.testing.assert_array_equal(drawn[k], traj.omega[:, k], err_msg=name)
    assert dz.plotting.invariants_figure(traj).axes


def test_the_viewer_has_a_frame_for_each_frame_shown(run):
    pytest.importorskip("plotly")
    _, _, traj = run
    assert len(dz.viewer.figure(traj, frames=5).frames) == 5


def test_a_batch_row_is_its_single_run(run):
    name, system, traj = run
    other = np.array(START[0]) * 1.5
    batch = dz.simulate([system, system], [START[0], other], START[1], **RUN)
    np.testing.assert_array_equal(batch[0].q, traj.q, err_msg=name)
    np.testing.assert_array_equal(batch[0].omega, traj.omega, err_msg=name)
    alone = dz.simulate(system, other, START[1], **RUN)
    np.testing.assert_array_equal(batch[1].omega, alone.omega, err_msg=name)


def test_a_study_sample_is_its_single_run(run):
    name, system, traj = run
    study = dz.monte_carlo(system, START[0], 2, seed=4, q0=START[1],
                           ask=lambda tr: float(tr.omega[-1, 0]), **RUN)
    assert study.outcomes.tolist() == [traj.omega[-1, 0]] * 2, name
