"""The long-run notes' estimates against the runs they announce: for `eval` with random walks,
`albedo`, `export --to radiance` of a pane, `export --to mitsuba3` of an all-orders fit and
`report --fits` of that fit with its walks edited up, the time the pilot run said on stderr and
the wall time the run then took (for the report, loading the data and drawing its one panel,
under 0.1 s, included).

Usage: python3 python/bench/long_run_estimates.py [SCALE]   (from the repository root, after
`cargo build --release`; SCALE multiplies every run's walks, default 1: each run is announced
as about 15 to 60 s on an idle 2-core machine; the all-orders fit of fits/example.csv that the
last two runs export and draw takes a few seconds more, unannounced)

The `eval` pairs are 200 incident directions (theta_i 0.2 to 89 degrees, phi_i 0) with 8
outgoing directions each, 1,600 pairs, written to a temporary file.
"""

import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time

scale = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0
stfit = "target/release/stfit"


def pairs_csv(path):
    """200 incident directions, 8 outgoing directions each (4 reflected, 4 transmitted)."""
    rows = ["wi_x,wi_y,wi_z,wo_x,wo_y,wo_z"]
    for i in range(200):
        ti = math.radians(0.2 + i * (89.0 - 0.2) / 199)
        wi = (math.sin(ti), 0.0, math.cos(ti))
        for j in range(8):
            to = math.radians(10.0 + 20.0 * (j % 4))
            po = j * math.pi / 4
            z = math.cos(to) if j < 4 else -math.cos(to)
            wo = (math.sin(to) * math.cos(po), math.sin(to) * math.sin(po), z)
            rows.append(",".join(f"{v:.12f}" for v in wi + wo))
    with open(path, "w") as f:
        f.write("\n".join(rows) + "\n")


def run(name, cmd, stdin=None):
    """Runs `cmd`, returns the announced estimate (the note's text) and the wall seconds."""
    start = time.perf_counter()
    child = subprocess.run(cmd, stdin=stdin, stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - start
    if child.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{child.stderr}")
    said = re.search(r"will take about (.+?)(?: on (\d+) threads| \()", child.stderr)
    events = re.search(r"about ([0-9.]+) scattering events per walk", child.stderr)
    said_text = f"said {said.group(1)}" if said else "no note (under 10 s)"
    events_text = f", {events.group(1)} events per walk" if events else ""
    print(f"{name}: {said_text}{events_text}; took {wall:.1f} s wall")
    print(f"  {' '.join(cmd)}")


with tempfile.TemporaryDirectory() as tmp:
    pairs = os.path.join(tmp, "pairs.csv")
    pairs_csv(pairs)
    with open(pairs) as stdin:
        run("eval, GGX, all orders, 1,600 pairs on 200 incident directions",
            [stfit, "eval", "--ndf", "ggx", "--alpha", "0.5", "--eta", "1.5", "--orders",
             "all", "--walks", str(int(200_000 * scale))], stdin)
    run("albedo, Student-T near gamma 3/2",
        [stfit, "albedo", "--ndf", "student-t", "--alpha", "1", "--gamma", "1.51", "--eta",
         "1.5", "--theta-i", "60", "--walks", str(int(4_000_000 * scale))])
    run("export --to radiance, a pane of the example Student-T fit",
        [stfit, "export", "fits/example-fits.json", "--to", "radiance", "--sample", "frosted", "--model", "student-t",
         "--walks", str(int(300_000 * scale)), "--out", os.path.join(tmp, "out") + "/"])
    fit = os.path.join(tmp, "all-orders.json")
    subprocess.run([stfit, "fits/example.csv", "--sample", "frosted", "--model", "ggx",
                    "--orders", "all", "--walks", str(int(100_000 * scale)), "--json", "--out",
                    fit], check=True, stdout=subprocess.DEVNULL)
    run("export --to mitsuba3, an all-orders GGX fit of the example's frosted sample",
        [stfit, "export", fit, "--to", "mitsuba3", "--out", os.path.join(tmp, "scene.xml")])
    # The same fit with its walks hand-edited up, as a user might: the report draws it with
    # them (the stored rmse is then not reproduced, which the report warns about).
    with open(fit) as f:
        fits = json.load(f)
    for entry in fits["fits"]:
        entry["walks"] = int(3_000_000 * scale)
    edited = os.path.join(tmp, "all-orders-edited.json")
    with open(edited, "w") as f:
        json.dump(fits, f)
    run("report --fits, the same fit with its walks edited to "
        f"{int(3_000_000 * scale):,}",
        [stfit, "report", "fits/example.csv", "--sample", "frosted", "--fits", edited,
         "--out", os.path.join(tmp, "report")])
