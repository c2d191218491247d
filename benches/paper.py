"""The main command's cost: `dzhanibekov paper` end to end, its wall time, CPU time, peak
memory and the sizes of its animations, against another version in the same session.

    python benches/paper.py                                   # this version, 3 runs
    python benches/paper.py --baseline-rev 42177e0 --repeat 3 # and a git revision's Python

Each run is a fresh process (`python -m dzhanibekov paper --out TMP --no-progress`), as a
user runs it, after the build. Runs of the two versions alternate, so that both see the same
load; the machine's load average is printed before and after, and the medians are reported
(the issue's target: the whole render within 45 s on 2 cores; each GIF under 3 MB).

`--baseline-rev REV` runs the Python package of git revision REV (extracted with `git
archive`) with this build's compiled core: valid while the two share the core's interface
(the branch that sped up the render changed no Rust). `--baseline DIR` takes such a folder
(holding `dzhanibekov/`) directly.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from io import BytesIO
from pathlib import Path

from PIL import Image

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "python" / "dzhanibekov"


def baseline_from(rev: str, into: Path) -> Path:
    """The Python package of git revision `rev`, with this build's compiled core, in `into`."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "python/dzhanibekov"],
                             check=True, capture_output=True).stdout
    with tarfile.open(fileobj=BytesIO(archive)) as tar:
        tar.extractall(into, filter="data")
    for core in PACKAGE.glob("_core*.so"):
        shutil.copy2(core, into / "python" / "dzhanibekov" / core.name)
    return into / "python"


MEASURE = """
import json, resource, subprocess, sys, time
start = time.perf_counter()
subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
wall = time.perf_counter() - start
used = resource.getrusage(resource.RUSAGE_CHILDREN)
print(json.dumps({"wall": wall, "cpu": used.ru_utime + used.ru_stime,
                  "rss_mb": used.ru_maxrss / 1024}))
"""
"""Runs a command and reports its wall time, the CPU time of it and every process it waited
for, and the peak memory of the largest of them: from a process of its own, so that the
figures are this run's alone."""


def run_once(python_path: Path | None, out: Path, jobs: int | None) -> dict[str, float]:
    """One `paper` render into `out`: wall and CPU seconds (the command and its drawing
    processes), the peak memory of the largest of them, and the load average around it."""
    env = dict(os.environ, MPLBACKEND="Agg")
    if python_path is not None:
        env["PYTHONPATH"] = str(python_path)
    argv = [sys.executable, "-m", "dzhanibekov", "paper", "--out", str(out), "--no-progress"]
    if jobs is not None:
        argv += ["--jobs", str(jobs)]
    load = os.getloadavg()[0]
    done = subprocess.run([sys.executable, "-c", MEASURE, *argv], check=True, env=env,
                          capture_output=True, text=True)
    measured: dict[str, float] = json.loads(done.stdout)
    return {**measured, "load_before": load, "load_after": os.getloadavg()[0]}


def animations(out: Path) -> dict[str, tuple[float, int, float]]:
    """Each GIF's size (MB) and frame count, and its MP4's size (MB, 0 if none)."""
    found = {}
    for gif in sorted(out.glob("*.gif")):
        with Image.open(gif) as image:
            frames = image.n_frames
        mp4 = gif.with_suffix(".mp4")
        found[gif.stem] = (gif.stat().st_size / 1e6, frames,
                           mp4.stat().st_size / 1e6 if mp4.exists() else 0.0)
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--baseline", type=Path, default=None,
                        help="a folder holding the baseline's dzhanibekov/ package")
    parser.add_argument("--baseline-rev", default=None,
                        help="a git revision whose Python package is the baseline")
    parser.add_argument("--jobs", type=int, default=None,
                        help="--jobs for this version (the baseline has none)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        versions: dict[str, Path | None] = {"this version": None}
        if args.baseline_rev is not None:
            versions = {f"baseline {args.baseline_rev}":
                        baseline_from(args.baseline_rev, Path(tmp) / "base"), **versions}
        elif args.baseline is not None:
            versions = {"baseline": args.baseline, **versions}
        print(f"{os.cpu_count()} CPUs; load average {os.getloadavg()[0]:.2f} at the start; "
              f"{args.repeat} runs of each, alternating", flush=True)
        results: dict[str, list[dict[str, float]]] = {name: [] for name in versions}
        files: dict[str, dict[str, tuple[float, int, float]]] = {}
        for k in range(args.repeat):
            for name, path in versions.items():
                out = Path(tmp) / f"out-{len(results[name])}-{name.split()[0]}"
                jobs = args.jobs if path is None else None
                results[name].append(run_once(path, out, jobs))
                files[name] = animations(out)
                r = results[name][-1]
                print(f"  run {k + 1} {name}: {r['wall']:.1f} s wall, {r['cpu']:.1f} s CPU, "
                      f"load {r['load_before']:.2f} → {r['load_after']:.2f}", flush=True)
                shutil.rmtree(out)
        print()
        print(f"| version | wall s (median) | CPU s (median) | peak RSS MB | load average |")
        print("|---|---|---|---|---|")
        for name, rs in results.items():
            loads = [r["load_before"] for r in rs] + [r["load_after"] for r in rs]
            print(f"| {name} | {statistics.median(r['wall'] for r in rs):.1f} | "
                  f"{statistics.median(r['cpu'] for r in rs):.1f} | "
                  f"{max(r['rss_mb'] for r in rs):.0f} | {min(loads):.1f}–{max(loads):.1f} |")
        print()
        print("| version | animation | GIF MB | GIF frames | MP4 MB |")
        print("|---|---|---|---|---|")
        for name, found in files.items():
            for scene, (gif, frames, mp4) in found.items():
                print(f"| {name} | {scene} | {gif:.2f} | {frames} | {mp4:.2f} |")
        if len(results) == 2:
            (a, ra), (b, rb) = results.items()
            wall = statistics.median(r["wall"] for r in ra) / statistics.median(
                r["wall"] for r in rb)
            cpu = statistics.median(r["cpu"] for r in ra) / statistics.median(
                r["cpu"] for r in rb)
            print(f"\n{b} against {a}: {wall:.1f}× less wall time, {cpu:.1f}× less CPU time")


if __name__ == "__main__":
    main()
