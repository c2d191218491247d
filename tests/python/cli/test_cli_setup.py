"""The command line's setup items: `--version`, and `run`'s overrides of a scene."""

import json

import pytest

import dzhanibekov as dz
from dzhanibekov.cli import main


def test_version(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["--version"])
    assert exit_.value.code == 0
    assert capsys.readouterr().out.strip() == f"dzhanibekov {dz.__version__}"


def test_run_overrides_method_span_and_frames(tmp_path):
    assert main(["run", "fig3a", "--out", str(tmp_path), "--method", "exact", "--t-end", "50",
                 "--frames", "11", "--no-progress"]) == 0
    summary = json.loads((tmp_path / "fig3a.json").read_text())
    # the closed form takes no steps: no step to report (it said "dt": 0.0)
    assert summary["method"] == "exact" and summary["n_steps"] == 0 and summary["dt"] is None
    # fig. 3a flips every 2K(m)/λ ≈ 38.2: once by t = 50, twice by the scene's own t = 100
    period = dz.flip_period(dz.PAPER_INERTIA, (0.01, 0.01, 1.0))
    assert len(summary["flip_times"]) == 1 and summary["flip_times"][0] < 50.0
    assert main(["run", "fig3a", "--out", str(tmp_path), "--method", "exact",
                 "--no-progress"]) == 0
    times = json.loads((tmp_path / "fig3a.json").read_text())["flip_times"]
    assert len(times) == 2 and abs((times[1] - times[0]) - period) < 1e-9 * period


def test_a_bad_override_is_named_and_nothing_is_written(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["run", "fig3a", "--out", str(out), "--method", "rk5"]) == 2
    assert "`--method` must be one of" in capsys.readouterr().err and not out.exists()
    assert main(["run", "fig3a", "--out", str(out), "--frames", "1"]) == 2
    assert "`--frames` must be" in capsys.readouterr().err and not out.exists()
