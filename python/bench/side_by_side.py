"""Whole-process medians of the 12 single-scattering fits: `stfit DATA --model all` against
`python3 python/bench/scipy_fits.py DATA`, run alternately.

Usage: python3 python/bench/side_by_side.py DATA [RUNS]   (from the repository root, after
`cargo build --release`)
"""

import statistics
import subprocess
import sys
import time

data = sys.argv[1]
runs = int(sys.argv[2]) if len(sys.argv) > 2 else 11
commands = {
    "stfit": ["target/release/stfit", data, "--model", "all"],
    "numpy/scipy": [sys.executable, "python/bench/scipy_fits.py", data],
}
times = {k: [] for k in commands}
for _ in range(runs):
    for name, cmd in commands.items():
        t = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        times[name].append(time.perf_counter() - t)
med = {k: statistics.median(v) for k, v in times.items()}
for k, v in med.items():
    print(f"{k:12} median {v * 1e3:9.2f} ms over {runs} runs")
print(f"ratio {med['numpy/scipy'] / med['stfit']:.0f}x")
