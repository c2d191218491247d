"""Times and measures the memory of reading a large CCSDS AEM, and of `dz.save`/`dz.load`.

    python benches/python/bench_files.py            # a ~100 MB AEM (about a minute)
    python benches/python/bench_files.py --quick    # a ~10 MB AEM

Each measurement runs in a child process of its own (Linux: the peak resident set, VmHWM,
reset before the call, above the resident set then):
`read_aem` of the file, and for comparison the previous reader (the whole text read, split
into lines and fields, then converted: `legacy_read`, written out below as it was), plus
`dz.save` and `dz.load` of a 10⁶-frame trajectory. Printed: the median seconds of three
runs and the peak RSS above the interpreter's baseline. The machine's load average is
printed before and after: the figures are only as good as the machine was quiet.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import textwrap

CHILD = textwrap.dedent("""
    import sys, time
    import numpy as np
    import dzhanibekov as dz
    what, path = sys.argv[1], sys.argv[2]

    def legacy_read(path):
        # the reader before streaming (issue 25: 11 s and 932 MB for 100 MB)
        lines = open(path, encoding="ascii").read().splitlines()
        rows, section = [], "header"
        for raw in lines:
            line = raw.strip()
            if line in ("META_START", "META_STOP", "DATA_START", "DATA_STOP"):
                section = {"DATA_START": "data"}.get(line, "other")
                continue
            if section == "data" and line:
                rows.append(line.split())
        values = np.array([[float(x) for x in row[1:]] for row in rows])
        epochs = [row[0] for row in rows]
        return values, epochs

    def status(field):
        with open("/proc/self/status") as f:
            return next(int(l.split()[1]) * 1024 for l in f if l.startswith(field + ":"))

    def reset_peak():
        with open("/proc/self/clear_refs", "w") as f:  # VmHWM := VmRSS (Linux)
            f.write("5")

    reset_peak()
    base = status("VmRSS")
    start = time.perf_counter()
    if what == "read_aem":
        rows = len(dz.io.read_aem(path).t)
    elif what == "legacy":
        rows = len(legacy_read(path)[1])
    elif what == "load":
        rows = len(dz.load(path).t)
    else:
        traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=1000.0, frames=10**6)
        reset_peak()
        base = status("VmRSS")
        start = time.perf_counter()
        dz.save(traj, path)
        rows = len(traj.t)
    seconds = time.perf_counter() - start
    peak = status("VmHWM") - base
    print(rows, seconds, peak)
""")


def measure(what: str, path: str, repeat: int = 3) -> tuple[int, float, float]:
    runs = []
    for _ in range(repeat):
        out = subprocess.run([sys.executable, "-c", CHILD, what, path], capture_output=True,
                             text=True, check=True).stdout.split()
        runs.append((int(out[0]), float(out[1]), float(out[2])))
    return runs[0][0], statistics.median(r[1] for r in runs), max(r[2] for r in runs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a ~10 MB AEM")
    args = parser.parse_args()
    import dzhanibekov as dz

    print(f"load average before: {os.getloadavg()}")
    frames = 100_001 if args.quick else 1_000_001
    with tempfile.TemporaryDirectory() as folder:
        traj = dz.simulate(dz.PAPER_INERTIA, (0.01, 0.01, 1.0), t_end=frames / 100,
                           frames=frames, dt=1e-2)
        aem = dz.io.write_aem(traj, os.path.join(folder, "big.aem"), "BOX", "2026-001A",
                              "2026-01-01T00:00:00", ref_frame_a="EME2000", rates=True)
        size = os.path.getsize(aem)
        del traj
        print(f"AEM of {frames} rows, {size / 1e6:.0f} MB:")
        for what in ("read_aem", "legacy"):
            rows, seconds, peak = measure(what, str(aem))
            print(f"  {what:<9} {seconds:6.2f} s  peak +{peak / 1e6:6.0f} MB  "
                  f"({peak / rows:.0f} B a row)")
        nc = os.path.join(folder, "big.nc")
        _, seconds, peak = measure("save", nc)
        print(f"save of 10^6 frames: {seconds:.2f} s, peak +{peak / 1e6:.0f} MB "
              f"(the file: {os.path.getsize(nc) / 1e6:.0f} MB)")
        _, seconds, peak = measure("load", nc)
        print(f"load of it:          {seconds:.2f} s, peak +{peak / 1e6:.0f} MB")
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
