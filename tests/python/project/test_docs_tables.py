"""The per-step costs the docs quote come from one measurement (issue 33: the methods guide
and the atlas said 2.2 and 2.8 for rk4_projected, 4.1 and 5.5 for the splitting, 17 and 21
for splitting4): the atlas's speed table (``python benches/atlas.py speed``), rounded, in the
atlas's method table and in the methods guide's."""

from __future__ import annotations

import re
from pathlib import Path

DOCS = Path(__file__).resolve().parents[3] / "docs"


def _measured() -> dict[str, float]:
    """The × RK4 column of the atlas's speed table."""
    text = (DOCS / "atlas.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| `([a-z0-9_]+)` \| \d+ \| ([0-9.]+) \|", text, re.MULTILINE)
    assert len(rows) >= 10, rows
    return {name: float(ratio) for name, ratio in rows}


def _quoted(page: Path) -> dict[str, str]:
    """The last column of a page's table of methods (rows starting with | `"name"` |)."""
    text = page.read_text(encoding="utf-8")
    rows = re.findall(r'^\| `"([a-z0-9_]+)"`.*\| ([^|]+) \|$', text, re.MULTILINE)
    return {name: cell.strip() for name, cell in rows}


def test_every_per_step_cost_is_the_atlas_measurement_rounded():
    measured = _measured()
    for page in (DOCS / "atlas.md", DOCS / "guide" / "methods.md"):
        quoted = _quoted(page)
        for name, ratio in measured.items():
            if name == "rk4":
                continue
            expected = f"{ratio:.1f}" if ratio < 10 else f"{ratio:.0f}"
            assert quoted.get(name) == expected, (page.name, name, quoted.get(name), ratio)
