"""The command line: ``dzhanibekov paper`` runs the paper's scenarios and reports on them."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence

from .scenarios import SCENARIOS

__all__ = ["main"]


def _paper(args: argparse.Namespace) -> int:
    print(f"{'scenario':<9} {'steps':>9} {'seconds':>8} {'flips':>5}  {'first flip times':<28}"
          f" {'dE/E':>8} {'d|L|/|L|':>8} {'dL_world':>8} {'d|q|':>8}")
    for s in SCENARIOS.values():
        start = time.perf_counter()
        traj = s.run(dt=args.dt)
        seconds = time.perf_counter() - start
        times = [] if traj.flip_times is None else list(traj.flip_times)
        flips = ", ".join(f"{t:.3f}" for t in times[:4]) + (", …" if len(times) > 4 else "")
        d = traj.drift
        print(f"{s.name:<9} {traj.n_steps:>9} {seconds:>8.3f} {len(times):>5}  {flips:<28}"
              f" {d.energy:>8.1e} {d.momentum:>8.1e} {d.momentum_world:>8.1e} {d.q_norm:>8.1e}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Runs the command line with `argv` (default ``sys.argv[1:]``); returns the exit code."""
    parser = argparse.ArgumentParser(
        prog="dzhanibekov",
        description="Free rotation of rigid bodies: the Dzhanibekov effect.",
    )
    commands = parser.add_subparsers(dest="command", required=True)
    paper = commands.add_parser(
        "paper",
        help="run the paper's scenarios; print flip times and invariant drift",
        description="Simulate the paper's scenarios (Fig. 2 and 3a-c) with RK4 and print, for "
        "each, the flip times and the largest drift of the invariants.",
    )
    paper.add_argument("--dt", type=float, default=1e-3, help="RK4 step (default 1e-3)")
    paper.set_defaults(run=_paper)
    args = parser.parse_args(argv)
    try:
        return int(args.run(args))
    except (ValueError, TypeError) as exc:
        print(f"dzhanibekov: error: {exc}", file=sys.stderr)
        return 2
