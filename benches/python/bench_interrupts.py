"""How fast Ctrl-C stops a long call: the latency from SIGINT to KeyboardInterrupt.

    python benches/python/bench_interrupts.py [REPEATS]

Runs `tests/python/interrupt_child.py` (a process per measurement, which sends itself
SIGINT half a second into a call that would take tens of seconds) REPEATS times (default 5)
for each long call, and prints the median and largest latency. The package must be installed
(`maturin develop --release` or the wheel).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
from pathlib import Path

CHILD = Path(__file__).resolve().parents[2] / "tests" / "python" / "interrupt_child.py"
CALLS = ["simulate-rk4", "simulate-dop853", "simulate-splitting", "summarize-rk4",
         "summarize-exact", "batch-rk4", "batch-splitting", "sweep-rk4", "rotate"]


def main() -> None:
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    print(f"{'call':<20} {'median (ms)':>12} {'max (ms)':>10}  (n = {2 * repeats}: two "
          "interrupts a process)")
    for call in CALLS:
        latencies = []
        for _ in range(repeats):
            out = subprocess.run([sys.executable, str(CHILD), call, "0.5"], capture_output=True,
                                 text=True, timeout=300, check=True).stdout
            report = json.loads(out.strip().splitlines()[-1])
            assert report["interrupted"] and report["inside"] and report["usable"], report
            latencies += [report["latency"], report["latency_second"]]
        print(f"{call:<20} {1e3 * statistics.median(latencies):>12.1f} "
              f"{1e3 * max(latencies):>10.1f}")


if __name__ == "__main__":
    main()
