"""Redraws docs/work_precision.png from the tables of docs/work_precision.md, without measuring
again: the picture then shows exactly the page's runs and says what the page says.

    python benches/replot_work_precision.py [--docs DIR]

The measurements themselves are made by `python benches/work_precision.py`, which writes both
files; use this when only the picture's drawing changed (or it went stale: its subtitle still
spoke of who shared the machine after the page had stopped saying so). The subtitle it is
drawn with is kept in the PNG's "Description" text, which the docs' test compares with the
page.
"""

from __future__ import annotations

import argparse
import importlib.util
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def bench_module():
    """benches/work_precision.py, imported (it is a script, not a package module)."""
    spec = importlib.util.spec_from_file_location("work_precision", ROOT / "benches" /
                                                  "work_precision.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["work_precision"] = module  # its dataclasses look themselves up there
    spec.loader.exec_module(module)
    return module


def number(text: str) -> float:
    return float(text.strip())


def runs_of(page: str, wp) -> list:
    """The runs of the page's "Every run" tables (what the plot draws of each)."""
    cases = {c.title: c for c in wp.CASES}
    runs = []
    case = None
    for line in page[page.index("## Every run"):].splitlines():
        if line.startswith("### "):
            case = cases[line[4:].strip()]
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if case is None or len(cells) < 6 or cells[0] in ("method", "---"):
            continue
        method, setting, steps, ms, err_w, err_q = cells[:6]
        if setting == "—":
            sweep, param = "exact", 0.0
        elif method == "scipy DOP853":
            sweep, param = "baseline", number(re.search(r"rtol = ([^,]+)", setting)[1])
        elif setting.startswith("dt=None"):
            sweep, param = "dt=None", number(setting.split("rtol =")[1])
        elif setting.startswith("hΩ ="):
            sweep, param = "dt", number(setting.split("=")[1])
        else:
            sweep, param = "rtol", number(setting.split("=")[1])
        nfev = int(steps.split()[0]) if steps.endswith("rhs") else 0
        n_steps = 0 if steps.endswith("rhs") else int(steps)
        runs.append(wp.Run(case.name, method, setting, sweep, param, number(ms) / 1e3,
                           n_steps, nfev, number(err_w), number(err_q)))
    return runs


def note_of(page: str) -> str:
    """The machine and its load, as the page's first paragraph says them."""
    made = re.search(r"^Made by .*? in [^;]+; (.*?)\. Times are", page, re.MULTILINE)
    if made is None:
        raise SystemExit("docs/work_precision.md does not say the machine it was made on")
    return made[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--docs", type=Path, default=ROOT / "docs")
    args = parser.parse_args()
    wp = bench_module()
    page = (args.docs / "work_precision.md").read_text(encoding="utf-8")
    runs = runs_of(page, wp)
    note = note_of(page)
    wp.plot(args.docs / "work_precision.png", runs, wp.CASES, note)
    print(f"redrew {args.docs / 'work_precision.png'} from {len(runs)} runs: {note}")


if __name__ == "__main__":
    main()
