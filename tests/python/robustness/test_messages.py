"""Messages that must read as sentences and blame the argument at fault, with the user's own
values (hardening round 4)."""

import re

import pytest

import dzhanibekov as dz

BODY = dz.Body((1.0, 2.0, 3.0))


def test_a_run_beyond_every_step_count_reads_as_a_sentence():
    # was "…, more than the limit the most steps a run can count (2^64 - 1)"
    with pytest.raises(dz.TooLargeError) as caught:
        dz.simulate(BODY, (0.01, 0.01, 1.0), t_end=1e300, method="rk4")
    text = str(caught.value)
    assert "the limit the" not in text, text
    assert re.search(r"^the run needs .*, more than the most steps a run can count "
                     r"\(2\^64 - 1\); take a shorter t_end", text), text
    # a step below float64's smallest: a count of steps, not "steps of … more than the
    # smallest step"
    with pytest.raises(dz.TooLargeError) as caught:
        dz.simulate(BODY, (1e300, 1e299, 1e298), t_end=100.0, method="rk4")
    text = str(caught.value)
    assert "smallest step" not in text, text
    assert re.search(r"^the run needs (more steps than float64 counts|[\d.e+]+ steps)", text), text


def test_a_step_count_over_max_steps_names_the_limit_once():
    with pytest.raises(dz.TooLargeError, match=r"needs 1\.000e6 steps \(t_end / dt\), more "
                                               r"than the limit max_steps = 1000; raise"):
        dz.simulate(BODY, (0.01, 0.01, 1.0), t_end=1e3, dt=1e-3, max_steps=1000)


@pytest.mark.parametrize("method", ["rk4", "dop853"])
def test_a_part_too_large_for_float64_is_named_with_the_users_value(method):
    """A wheel's momentum of 1e308 and an orbit rate of 1e200 were reported as `omega0`, with
    the momenta the run computes (`got [0.01, 1e308, 3.0]`), not anything the user gave."""
    w0 = (0.01, 0.01, 1.0)
    wheel = dz.System(BODY, parts=[dz.Wheel((0, 1, 0), 1e308)])
    with pytest.raises(ValueError, match=r"^`momentum` must give.*, got 1e\+?308$"):
        dz.simulate(wheel, w0, t_end=10.0, method=method)
    orbit = dz.System(BODY, torques=[dz.GravityGradient(1e200)])
    with pytest.raises(ValueError, match=r"^`orbit_rate` must give.*, got 1e\+?200$"):
        dz.simulate(orbit, w0, t_end=10.0, method=method)
