"""The cost of a run from Python against the CLI: median CPU times of the default model's run
(`deckspin run models/four-span.toml`), and whether the outputs are the same.

    python examples/python/run_cost.py [N] [--cli PATH]

- CLI: the CPU time (user + system) of the `deckspin run` process: start, model, run, files;
- Python, the run: `Model.run()` on a model compiled before (process CPU time);
- Python, the whole: `Model(...)`, `run()`, the history as a table and `write()` of the files;
- the library's: the CPU time of the thread that integrated (`Result.cpu_time`);
- the binding's overhead: Python's run minus the library's; the history's table apart.
"""

import argparse
import os
import resource
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import deckspin

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "models" / "four-span.toml"

args = argparse.ArgumentParser()
args.add_argument("n", nargs="?", type=int, default=9)
args.add_argument("--cli", default=os.environ.get("DECKSPIN_BIN", ROOT / "target" / "release" / "deckspin"))
args = args.parse_args()


def children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def cli_run(out: Path) -> float:
    c0 = children_cpu()
    subprocess.run([str(args.cli), "run", str(MODEL), "--out", str(out)], check=True, capture_output=True)
    return children_cpu() - c0


def cpu(f):
    c0 = time.process_time()
    out = f()
    return out, time.process_time() - c0


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    model = deckspin.Model(MODEL)
    model.run()  # warm up: pages of the library, the records read once by the OS
    cli_s, run_s, lib_s, whole_s, table_s = [], [], [], [], []
    for i in range(args.n):
        cli_s.append(cli_run(tmp / "cli"))
        r, s = cpu(model.run)
        run_s.append(s)
        lib_s.append(r.cpu_time)
        _, s = cpu(lambda: r.history)
        table_s.append(s)

        def whole():
            m = deckspin.Model(MODEL)
            res = m.run()
            _ = res.history
            res.write(tmp / "py")
            return res

        _, s = cpu(whole)
        whole_s.append(s)
    same = (
        r.history_csv() == (tmp / "cli" / "history.csv").read_text()
        and r.events_csv() == (tmp / "cli" / "events.csv").read_text()
        and (tmp / "py" / "history.csv").read_bytes() == (tmp / "cli" / "history.csv").read_bytes()
    )

med = statistics.median


def line(label: str, seconds: list) -> None:
    print(f"  {label:<56} {1e3 * med(seconds):8.2f}")


kind = "pandas" if deckspin._pandas() else "numpy"
print(f"default model ({MODEL.name}), median of {args.n} runs, CPU ms")
line("CLI `deckspin run` (process: start, model, run, files)", cli_s)
line("Python Model.run()", run_s)
line("Python Model() + run() + history table + write()", whole_s)
line(f"the history as a table (r.history, {kind})", table_s)
line("the library's integration (Result.cpu_time)", lib_s)
line("binding overhead: Model.run() minus the integration", [a - b for a, b in zip(run_s, lib_s)])
print(f"outputs identical to the CLI's (history.csv, events.csv, written files): {same}")
