"""The Python package against the CLI's own output (`deckspin run`, `sweep`, `suite`, `modes`).

The CLI binary is DECKSPIN_BIN, else target/release/deckspin of this repository (built by
`cargo build --release`); the tests fail, not skip, without it.
"""

from __future__ import annotations

import concurrent.futures
import csv
import io
import json
import math
import os
import signal
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import deckspin

ROOT = Path(__file__).resolve().parents[3]
MODEL = ROOT / "models" / "four-span.toml"
FAR_FIELD = ROOT / "excitations" / "far-field"


def cli() -> str:
    exe = os.environ.get("DECKSPIN_BIN") or str(ROOT / "target" / "release" / "deckspin")
    assert Path(exe).is_file(), f"{exe}: no deckspin binary (cargo build --release, or set DECKSPIN_BIN)"
    return exe


def run_cli(*args: str, ok: bool = True) -> subprocess.CompletedProcess:
    p = subprocess.run([cli(), *args], cwd=ROOT, capture_output=True, text=True)
    if ok:
        assert p.returncode == 0, p.stderr
    return p


def read_csv(path: Path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def same_float(a: float, b: float) -> bool:
    """Equal bit for bit (NaN equal to NaN)."""
    return (math.isnan(a) and math.isnan(b)) or (a == b and math.copysign(1, a) == math.copysign(1, b))


def rust_exp(x: float, digits: int) -> str:
    """Rust's `{:.DIGITSe}` of x (exponent without sign or padding: 2.5e0, 1.0e-7)."""
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    mantissa, exp = format(x, f".{digits}e").split("e")
    return f"{mantissa}e{int(exp)}"


def without_wall_time(summary: dict) -> dict:
    s = json.loads(json.dumps(summary))
    s["stats"].pop("wall_time")
    return s


def cli_run(tmp_path: Path, name: str, *sets: str, ok: bool = True) -> Path:
    out = tmp_path / name
    args = ["run", str(MODEL), "--out", str(out)]
    for s in sets:
        args += ["--set", s]
    run_cli(*args, ok=ok)
    return out


def assert_same_as_cli(r: deckspin.Result, out: Path) -> None:
    # the files' text, byte for byte
    assert r.history_csv() == (out / "history.csv").read_text()
    assert r.events_csv() == (out / "events.csv").read_text()
    # summary.json: the same fields and numbers, but for the wall time
    cli_summary = json.loads((out / "summary.json").read_text())
    assert without_wall_time(r.summary) == without_wall_time(cli_summary)
    # the history's columns: the CLI's numbers read at full precision, bit for bit
    head, rows = read_csv(out / "history.csv")
    h = r.history
    assert list(h.columns) == head
    assert len(h) == len(rows) > 0
    for j, name in enumerate(head):
        col = h[name].to_numpy()
        if col.dtype.kind == "f":
            cli_col = [float(row[j]) for row in rows]
            bad = [i for i, (a, b) in enumerate(zip(col, cli_col)) if not same_float(float(a), b)]
            assert not bad, f"{name}: rows {bad[:5]} differ"
        else:
            assert [str(x) for x in col] == [row[j] for row in rows], name
    # the events: the CLI's rounding of the full-precision values
    head, rows = read_csv(out / "events.csv")
    e = r.events
    assert list(e.columns) == head
    assert len(e) == len(rows)
    digits = {"t": 15, "accumulation_time": 15}
    for j, name in enumerate(head):
        col = list(e[name])
        if isinstance(col[0] if col else "", str):
            assert col == [row[j] for row in rows], name
        else:
            d = digits.get(name, 12)
            empty = name == "accumulation_time"
            text = ["" if empty and math.isnan(x) else rust_exp(x, d) for x in col]
            assert text == [row[j] for row in rows], name


def test_default_run_is_the_clis(tmp_path):
    r = deckspin.Model(MODEL).run()
    assert r.status == "finished"
    assert_same_as_cli(r, cli_run(tmp_path, "default"))


def test_overrides_are_the_clis(tmp_path):
    r = deckspin.Model(MODEL, set={"contacts.mu": 0.3, "excitation.run": 2}).run()
    assert r.summary["title"].endswith(")") and r.status == "finished"
    assert_same_as_cli(r, cli_run(tmp_path, "mu", "contacts.mu=0.3", "excitation.run=2"))


def test_method_is_the_clis(tmp_path):
    r = deckspin.Model(MODEL).run("moreau")
    assert r.method == "moreau"
    out = tmp_path / "moreau"
    run_cli("run", str(MODEL), "--out", str(out), "--method", "moreau")
    assert_same_as_cli(r, out)


def test_text_model_resolves_records_from_base():
    text = MODEL.read_text()
    r = deckspin.Model(text=text, base=MODEL.parent).run()
    assert r.history_csv() == deckspin.Model(MODEL).run().history_csv()


def test_model_error_names_file_line_and_field():
    text = MODEL.read_text().replace("mu = 0.5 ", "mu = -0.5")
    line = next(i for i, l in enumerate(text.splitlines(), 1) if l.startswith("mu = -0.5"))
    with pytest.raises(deckspin.ModelError) as e:
        deckspin.Model(text=text, base=MODEL.parent)
    err = e.value
    assert err.file == str(MODEL.parent / "<text>")
    assert err.line == line
    assert err.field == "contacts.mu"
    assert str(err).startswith(f"{err.file}:{line}: contacts.mu: ")


def test_model_error_of_an_override_names_the_argument():
    with pytest.raises(deckspin.ModelError) as e:
        deckspin.Model(MODEL, set={"bent.1.height": -2.0})
    err = e.value
    assert (err.file, err.field, err.argument) == (str(MODEL), "bent.1.height", "bent.1.height=-2.0")
    assert isinstance(err, ValueError)
    # the CLI says the same
    p = run_cli("modes", str(MODEL), "--set", "bent.1.height=-2.0", ok=False)
    assert p.returncode != 0 and str(err) in p.stderr


def test_model_error_of_a_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('title = "x"\n[[body]]\nname = "b"\nmass = "heavy"\n')
    with pytest.raises(deckspin.ModelError) as e:
        deckspin.Model(bad)
    assert e.value.file == str(bad)
    assert e.value.line == 4
    with pytest.raises(deckspin.ModelError) as e:
        deckspin.Model(tmp_path / "missing.toml")
    assert e.value.file == str(tmp_path / "missing.toml") and e.value.line is None


def test_failed_run_raises_with_its_partial_history(tmp_path):
    m = deckspin.Model(MODEL, set={"solver.max_steps": 2000})
    with pytest.raises(deckspin.RunFailed) as e:
        m.run()
    err = e.value
    assert err.kind == "TooManySteps"
    assert 0 < err.time < m.t_end
    r = err.result
    assert r.status == "failed" and r.failure["kind"] == "TooManySteps"
    t = r.history["t"].to_numpy()
    assert len(t) > 10 and t[-1] <= err.time
    # the partial run is the CLI's (which exits 1 and writes it too)
    out = cli_run(tmp_path, "failed", "solver.max_steps=2000", ok=False)
    assert json.loads((out / "summary.json").read_text())["failure"]["kind"] == "TooManySteps"
    assert_same_as_cli(r, out)
    # check=False returns it
    assert m.run(check=False).history_csv() == r.history_csv()


@pytest.fixture
def ctrl_c():
    """Python's Ctrl-C handler for the test, whatever the process inherited: a process started
    with SIGINT ignored (a background job of a non-interactive shell, as some CI runners start
    their steps) gets no KeyboardInterrupt from the signal, and Python installs no handler then."""
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


def test_ctrl_c_cancels_a_long_run_and_keeps_what_it_computed(ctrl_c):
    # a long run: Moreau–Jean at a step far below the one it would choose
    m = deckspin.Model(MODEL, set={"solver.step": 1e-5, "solver.method": "moreau"})
    seen = []
    sent = []
    timer = []

    def interrupt():
        sent.append(seen[-1])
        os.kill(os.getpid(), signal.SIGINT)

    def progress(t, t_end):
        seen.append(t)
        if not timer:
            timer.append(threading.Timer(0.2, interrupt))
            timer[0].start()

    with pytest.raises(KeyboardInterrupt) as e:
        m.run(progress=progress)
    r = e.value.result
    assert r.status == "cancelled"
    assert sent, "the signal was sent during the run"
    t_end = m.t_end
    stopped = r.cancelled_at
    last = r.history["t"].to_numpy()[-1]
    # stopped early, not long after the signal: far from t_end (the whole run is ~15x longer
    # than the 0.2 s before the signal), the history up to where it stopped
    assert stopped < t_end / 2
    assert last <= stopped
    assert stopped - sent[0] < t_end / 4
    assert r.summary["status"] == "cancelled" and r.summary["cancelled_at"] == stopped


def test_ctrl_c_stops_a_sweep_and_keeps_its_finished_rows(ctrl_c):
    # 12 long runs (Moreau-Jean at a step far below its own, seconds each): the signal comes
    # while the first ones run
    sent = []

    def interrupt():
        sent.append(True)
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(0.5, interrupt)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as e:
            deckspin.sweep(MODEL, {"contacts.mu": "0.05:0.6:0.05"},
                           fix={"solver.method": "moreau", "solver.step": 1e-5, "solver.t_end": 4})
    finally:
        timer.cancel()
    assert sent, "the signal was sent during the sweep"
    table = e.value.result
    assert len(table) == 12
    errors = list(table["error"])
    not_run = [x for x in errors if x == "cancelled before it ran"]
    finished = [i for i, x in enumerate(errors) if x == ""]
    # the runs not started are marked, those in progress finished and keep their numbers
    assert len(not_run) >= 6 and len(not_run) + len(finished) == 12, errors
    assert all(table["peak_rotation"][i] > 0 for i in finished)


def test_progress_returning_false_cancels():
    calls = []

    def progress(t, t_end):
        calls.append((t, t_end))
        return False

    m = deckspin.Model(MODEL, set={"solver.step": 1e-5, "solver.method": "moreau"})
    r = m.run(progress=progress, interval=0.01)
    assert r.status == "cancelled" and len(calls) == 1
    assert r.cancelled_at < m.t_end and calls[0][1] == m.t_end


def test_runs_in_threads_equal_sequential_runs():
    mus = [0.1, 0.3, 0.5, 0.7]
    models = [deckspin.Model(MODEL, set={"contacts.mu": mu}) for mu in mus]
    sequential = [m.run().history_csv() for m in models]
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        threaded = list(pool.map(lambda m: m.run().history_csv(), models))
    assert threaded == sequential
    # and they differ from one another (the test would see a mix-up)
    assert len(set(sequential)) == 4


def test_without_pandas_tables_are_dicts_of_arrays(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    r = deckspin.Model(MODEL).run()
    h = r.history
    assert isinstance(h, dict)
    head = r.history_csv().splitlines()[0].split(",")
    assert list(h) == head
    assert all(isinstance(v, np.ndarray) for v in h.values())
    assert h["t"].dtype == np.float64 and h["t"][-1] == r.summary["t_end"]
    assert isinstance(r.events, dict) and isinstance(r.events["kind"], np.ndarray)
    assert isinstance(deckspin.modes(MODEL), dict)


def test_sweep_is_the_clis(tmp_path):
    table = deckspin.sweep(MODEL, {"contacts.mu": [0.1, 0.5], "excitation.run": "3:4:1"})
    out = tmp_path / "sweep.csv"
    run_cli("sweep", str(MODEL), "--set", "contacts.mu=0.1,0.5", "--set", "excitation.run=3:4:1",
            "--out", str(out))
    head, rows = read_csv(out)
    assert list(table.columns) == head[:-1] + ["wall_time", "error"]
    assert len(table) == len(rows) == 4
    assert list(table["contacts.mu"]) == [0.1, 0.1, 0.5, 0.5]
    assert list(table["excitation.run"]) == [3, 4, 3, 4]
    # the CLI's rounding of the full-precision values
    digits = {"peak_rotation": 6, "residual_rotation": 6, "peak_x": 6, "peak_y": 6,
              "energy_closure_rel": 3}
    for j, name in enumerate(head):
        if name in digits:
            text = [rust_exp(x, digits[name]) for x in table[name]]
            assert text == [r[j] for r in rows], name
    j = head.index("stick_time")
    assert [format(x, ".4f") for x in table["stick_time"]] == [r[j] for r in rows]
    assert [str(x) for x in table["impacts"]] == [r[head.index("impacts")] for r in rows]
    assert list(table["error"]) == ["", "", "", ""]


def test_suite_is_the_clis(tmp_path):
    records = tmp_path / "records.txt"
    pairs = sorted(p.name for p in FAR_FIELD.glob("*.AT2"))[:4]
    lines = [f"{FAR_FIELD / pairs[i]} {FAR_FIELD / pairs[i + 1]}" for i in (0, 2)]
    records.write_text("\n".join(lines) + "\n")
    runs, stats = deckspin.suite(MODEL, records, measure="pga", levels=[0.3], stats=True)
    out = tmp_path / "suite.csv"
    run_cli("suite", str(MODEL), "--records", str(records), "--measure", "pga", "--levels", "0.3",
            "--out", str(out))
    head, rows = read_csv(out)
    assert list(runs.columns) == head and len(runs) == len(rows) == 2
    for j, name in enumerate(head):
        col = list(runs[name])
        for a, b in zip(col, (r[j] for r in rows)):
            if isinstance(a, str):
                assert a == b, name
            else:
                assert same_float(float(a), float(b) if b != "" else math.nan), name
    assert list(runs["status"]) == ["finished", "finished"]
    shead, srows = read_csv(tmp_path / "suite-stats.csv")
    assert list(stats.columns) == shead and len(stats) == len(srows) == 1


def test_modes_are_the_clis():
    table = deckspin.modes(MODEL)
    text = run_cli("modes", str(MODEL)).stdout.splitlines()
    rows = [l.split() for l in text[2:] if l.split() and l.split()[0].isdigit()]
    assert len(rows) == len(table)
    assert [format(x, ".5f") for x in table["period"]] == [r[1] for r in rows]
    assert [format(x, ".4f") for x in table["frequency"]] == [r[2] for r in rows]


def test_set_values_become_toml():
    m = deckspin.Model(MODEL, set={"contacts.enabled": False, "excitation.run": 3, "contacts.mu": 0.25,
                                   "solver.method": "penalty", "contacts.gaps": [0.01, 0.01, 0.02, 0.02]})
    assert m.set == ["contacts.enabled=false", "excitation.run=3", "contacts.mu=0.25",
                     'solver.method="penalty"', "contacts.gaps=[0.01, 0.01, 0.02, 0.02]"]
    assert m.method == "penalty"
    assert deckspin.Model(MODEL, set=["contacts.mu=0.25"]).set == ["contacts.mu=0.25"]


def test_bad_arguments_raise():
    with pytest.raises(ValueError):
        deckspin.Model(MODEL).run("no-such-method")
    with pytest.raises(TypeError):
        deckspin.Model(MODEL, text="x")
    with pytest.raises(deckspin.LimitError):
        deckspin.Model(MODEL, set={"solver.output_dt": 1e-6}).run()


def test_fig8_example_is_the_clis_mu_study(tmp_path):
    ours = tmp_path / "fig8.csv"
    subprocess.run([sys.executable, str(ROOT / "examples" / "python" / "fig8.py"), str(MODEL),
                    "--csv", str(ours)], check=True, capture_output=True)
    run_cli("study", "mu", str(MODEL), "--out", str(tmp_path / "study"))
    head, rows = read_csv(tmp_path / "study" / "increase_vs_mu.csv")
    ohead, orows = read_csv(ours)
    assert len(orows) == len(rows) > 1
    # the CLI rounds to 3 decimals: each of ours within half a unit of that
    mus = [c for c in head if c.startswith("mu_")]
    assert len(ohead) - 1 == len(mus)
    for ours_row, cli_row in zip(orows, rows):
        # the CLI's rows: run (or "mean"), pga_x, then one column per μ
        assert len(ours_row) - 1 == len(cli_row) - 2
        for a, b in zip(ours_row[1:], cli_row[2:]):
            assert abs(float(a) - float(b)) <= 0.0005 + 1e-9, (ours_row[0], a, b)
