"""The README's example runs as written and says what it does; its commands exist."""

import re
from pathlib import Path

import numpy as np
import pytest

import dzhanibekov as dz
from dzhanibekov.cli import main

ROOT = Path(__file__).resolve().parents[3]
README = ROOT / "README.md"
pytestmark = pytest.mark.skipif(not README.exists(), reason="no README beside the tests")


def test_the_ten_lines_run_and_mean_what_they_say(tmp_path, monkeypatch):
    block = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)[0]
    assert len(block.strip().splitlines()) <= 12
    monkeypatch.chdir(tmp_path)
    space: dict = {}
    exec(compile(block, "README.md", "exec"), space)
    traj = space["traj"]
    assert len(traj.flip_times) == 3 and (tmp_path / "path.png").exists()
    # the box's moments from the textbook formula I = m(b² + c²)/12, mass 1
    assert np.allclose(space["body"].inertia, ((100 + 225) / 12, (400 + 225) / 12,
                                               (400 + 100) / 12))
    assert space["path"].shape == (201, 3)
    assert f"{dz.flip_period(space['body'], (0.01, 0.01, 1.0)):.4f}" == "38.1569"


def test_the_readmes_commands_exist():
    text = README.read_text(encoding="utf-8")
    commands = set(re.findall(r"dzhanibekov (\w+) (?:\w+ )?--", text))
    assert {"paper", "view", "map"} <= commands
    for command in commands:
        with pytest.raises(SystemExit) as exit_:
            main([command, "--help"])
        assert exit_.value.code == 0, command
    for link in re.findall(r"\]\((docs/[^)#]+)", text):
        assert (ROOT / link).exists(), link
