"""The paper's Fig. 8 analog from Python: the percent increase of the peak deck rotation over
the run without contact, against the friction coefficient μ, for each test run of the
four-span bridge ("Nonsmooth seismic response analysis of a straight bridge with deck rotation
induced by abutment impact", Fig. 8). The same numbers as `deckspin study mu
models/four-span.toml` (its increase_vs_mu.csv rounds them to 3 decimals).

    python examples/python/fig8.py [MODEL.toml] [--csv OUT.csv]

Needs pandas. Both sweeps run in parallel inside the library.
"""

import argparse
import re
import sys
from pathlib import Path

import pandas as pd

import deckspin

ROOT = Path(__file__).resolve().parents[2]
args = argparse.ArgumentParser(description="The Fig. 8 analog: peak rotation increase vs μ")
args.add_argument("model", nargs="?", default=ROOT / "models" / "four-span.toml")
args.add_argument("--csv", help="also write the table (full precision) to this CSV")
args = args.parse_args()
model = deckspin.Model(args.model)

# the [[run]] tables of the bridge file: the test runs and their target PGAs
pga_x = [float(x) for x in re.findall(r"(?m)^pga_x\s*=\s*([0-9.eE+-]+)", model.text)]
runs = list(range(1, len(pga_x) + 1))
mus = deckspin.fig8_mus()

# each run without contact, then each run with contact at each μ (as `deckspin study mu`)
baseline = deckspin.sweep(model, {"excitation.run": runs, "contacts.enabled": [False]})
varied = deckspin.sweep(model, {"excitation.run": runs, "contacts.mu": mus})
for table in (baseline, varied):
    failed = table[table["error"] != ""]
    if len(failed):
        print(failed[["excitation.run", "error"]].to_string(), file=sys.stderr)

peak0 = baseline.set_index("excitation.run")["peak_rotation"]
varied["increase_pct"] = 100.0 * (varied["peak_rotation"] / varied["excitation.run"].map(peak0) - 1.0)
fig8 = varied.pivot(index="excitation.run", columns="contacts.mu", values="increase_pct")
fig8.index = [f"{k} ({pga_x[k - 1]:.2f} g)" for k in fig8.index]
fig8.index.name = "run (PGA x)"
fig8.columns = [f"μ={mu:g}" for mu in fig8.columns]
fig8.loc["mean"] = fig8.mean()

if args.csv:
    fig8.to_csv(args.csv)

pd.set_option("display.width", 120)
print("Percent increase of peak rotation over no contact vs μ (Fig. 8 analog)")
print(fig8.round(1).to_string())
