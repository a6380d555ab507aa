"""A slice of a record suite from Python, run in threads: a few far-field record pairs of
excitations/far-field at two of the four-span bridge's test-run levels, each run on a thread
of a ThreadPoolExecutor. A run releases the GIL, so the runs go on in parallel on the cores.

    python examples/python/suite_slice.py [PAIRS] [THREADS]

Each run takes the pair as the bridge's longitudinal and transverse records, scaled by the
model's [[run]] table (`excitation.run`: target PGAs), for the record's length plus 2 s of free
vibration. `deckspin.suite(...)` runs a whole suite (levels of an intensity measure) in
parallel inside the library instead. Prints a table (pandas when importable).
"""

import concurrent.futures
import os
import re
import sys
import time
from pathlib import Path

import deckspin

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "models" / "four-span.toml"
RECORDS = ROOT / "excitations" / "far-field"
PAIRS = int(sys.argv[1]) if len(sys.argv) > 1 else 3
THREADS = int(sys.argv[2]) if len(sys.argv) > 2 else 2
LEVELS = [4, 6]  # the model's test runs 4 (0.60 g / 0.50 g) and 6 (1.20 g / 1.00 g)
TIME_SCALE = 0.5  # the model's excitation.time_scale (quarter-scale similitude)


def duration(at2: Path) -> float:
    """NPTS × DT of a PEER .AT2 record, s."""
    head = at2.read_text(errors="replace").splitlines()[3]
    npts = int(re.search(r"NPTS\s*=\s*(\d+)", head).group(1))
    dt = float(re.search(r"DT\s*=\s*([0-9.eE+-]+)", head).group(1))
    return npts * dt


# the first PAIRS stations: two files each, sorted, the first longitudinal
files = sorted(RECORDS.glob("*.AT2"))
pairs = [(files[i], files[i + 1]) for i in range(0, 2 * PAIRS, 2)]


def one(job):
    (x, y), level = job
    t_end = TIME_SCALE * max(duration(x), duration(y)) + 2.0
    model = deckspin.Model(
        MODEL,
        set={
            "excitation.longitudinal": str(x),
            "excitation.transverse": str(y),
            "excitation.run": level,
            "solver.t_end": round(t_end, 3),
        },
    )
    r = model.run(check=False)
    peak = {p["name"]: p["max_abs"] for p in r.summary["peaks"]}
    return {
        "pair": os.path.commonprefix([x.stem, y.stem]).rstrip("_-"),
        "run": level,
        "status": r.status,
        "t_end": r.summary["t_end"],
        "peak_rotation": peak.get("deck.theta"),
        "impacts": r.summary["stats"]["impacts"],
        "cpu_s": r.cpu_time,
    }


jobs = [(p, level) for p in pairs for level in LEVELS]
t0 = time.perf_counter()
with concurrent.futures.ThreadPoolExecutor(max_workers=THREADS) as pool:
    rows = list(pool.map(one, jobs))
wall = time.perf_counter() - t0

try:
    import pandas as pd

    print(pd.DataFrame(rows).to_string(index=False))
except ImportError:
    for r in rows:
        print(r)
cpu = sum(r["cpu_s"] for r in rows)
print(f"{len(rows)} runs on {THREADS} threads: {wall:.2f} s wall, {cpu:.2f} s CPU in the library")
