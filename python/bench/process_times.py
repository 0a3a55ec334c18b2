"""Whole-process medians (wall and CPU, user + sys of the child) of the all-orders and
single-scattering fits of the Walter data.

Usage: python3 python/bench/process_times.py DATA [RUNS]   (from the repository root, after
`cargo build --release`)
"""

import os
import statistics
import subprocess
import sys
import time

data = sys.argv[1]
runs = int(sys.argv[2]) if len(sys.argv) > 2 else 11
stfit = "target/release/stfit"
commands = {
    "one sample (frosted), Student-T free gamma, all orders":
        [stfit, data, "--sample", "frosted", "--orders", "all"],
    "three samples, Student-T free gamma, all orders": [stfit, data, "--orders", "all"],
    "12 single-scattering fits (--model all)": [stfit, data, "--model", "all"],
    "12 single-scattering fits, RAYON_NUM_THREADS=1":
        ["env", "RAYON_NUM_THREADS=1", stfit, data, "--model", "all"],
}
for name, cmd in commands.items():
    wall, cpu = [], []
    for _ in range(runs):
        start = time.perf_counter()
        child = subprocess.Popen(cmd, stdout=subprocess.DEVNULL)
        _, status, usage = os.wait4(child.pid, 0)
        wall.append(time.perf_counter() - start)
        cpu.append(usage.ru_utime + usage.ru_stime)
        if status != 0:
            sys.exit(f"{cmd} failed")
    print(f"{name}: wall median {statistics.median(wall) * 1e3:.1f} ms, "
          f"cpu median {statistics.median(cpu) * 1e3:.1f} ms over {runs} runs")
