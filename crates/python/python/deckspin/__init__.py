"""deckspin from Python: nonsmooth seismic analysis of bridges whose decks pound their
abutments and rotate in plan (reference: "Nonsmooth seismic response analysis of a straight
bridge with deck rotation induced by abutment impact").

>>> import deckspin
>>> m = deckspin.Model("models/four-span.toml", set={"contacts.mu": 0.3})
>>> r = m.run()
>>> r.status, r.summary["peaks"][0]["max_abs"]
>>> r.history[["t", "deck.theta"]]

Tables are pandas DataFrames when pandas can be imported, else dicts of numpy arrays (column
name -> array). Runs release the GIL: runs in threads go on in parallel. Ctrl-C cancels a run
within a fraction of a second and raises KeyboardInterrupt with the partial result attached
(``e.result``). See docs/python.md.
"""

from __future__ import annotations

import csv
import io
import json
import math
import numbers
import os
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._errors import DeckspinError, LimitError, ModelError, RunFailed

__all__ = [
    "Model",
    "Result",
    "run",
    "sweep",
    "suite",
    "modes",
    "methods",
    "fig8_mus",
    "DeckspinError",
    "ModelError",
    "LimitError",
    "RunFailed",
]

__version__: str = _native.version()

PathLike = Union[str, "os.PathLike[str]"]
#: ``set=`` overrides: a mapping of dotted keys to Python values, or ``key=value`` strings
#: exactly as the CLI's ``--set``.
Overrides = Union[Mapping[str, Any], Iterable[str], None]
#: A table: a pandas DataFrame, or without pandas a dict of numpy arrays.
Table = Any


def _toml(value: Any) -> str:
    """A Python value as the TOML text of a ``--set`` value."""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        x = float(value)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        # the shortest text that reads back as the same float (TOML accepts 1e-05, 1e+20)
        return repr(x)
    if isinstance(value, str):
        # a TOML basic string (JSON's escapes are TOML's)
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    raise TypeError(
        f"a set= value must be a bool, number, string or list of them, not {type(value).__name__}"
    )


def _overrides(overrides: Overrides) -> List[str]:
    """``set=`` as the CLI's ``--set key=value`` arguments."""
    if overrides is None:
        return []
    if isinstance(overrides, str):
        return [overrides]
    if isinstance(overrides, Mapping):
        return [f"{k}={_toml(v)}" for k, v in overrides.items()]
    out = []
    for o in overrides:
        if not isinstance(o, str):
            raise TypeError(f"a set= item must be a 'key=value' string, not {type(o).__name__}")
        out.append(o)
    return out


def _axes(axes: Union[Mapping[str, Any], Iterable[str], None]) -> List[str]:
    """Swept keys as the CLI's ``--set key=a:b:step`` or ``key=v1,v2`` arguments: a mapping
    key -> list of values (each a Python value) or a range text ``"a:b:step"``, or the
    arguments themselves."""
    if axes is None:
        return []
    if isinstance(axes, str):
        return [axes]
    if isinstance(axes, Mapping):
        out = []
        for k, v in axes.items():
            if isinstance(v, str):
                out.append(f"{k}={v}")
            elif isinstance(v, (list, tuple, np.ndarray, range)):
                out.append(f"{k}=" + ",".join(_toml(x) for x in v))
            else:
                out.append(f"{k}={_toml(v)}")
        return out
    return _overrides(axes)


def _pandas() -> Any:
    """pandas, or None where it cannot be imported."""
    try:
        import pandas
    except ImportError:
        return None
    return pandas


def _frame(columns: Dict[str, Any]) -> Table:
    pd = _pandas()
    if pd is None:
        return {k: (v if isinstance(v, np.ndarray) else np.asarray(v, dtype=str)) for k, v in columns.items()}
    return pd.DataFrame(columns)


def _table(cols: Sequence[Tuple[str, str, Any]], keys: int = 0) -> Table:
    """A table of the native columns: (name, "f8" | "i8", bytes) or (name, "str", list); the
    first ``keys`` columns (a sweep's settings) as numbers where every value is one."""
    out: Dict[str, Any] = {}
    for i, (name, kind, data) in enumerate(cols):
        if i < keys and kind == "str":
            out[name] = _number_column(list(data))
            continue
        if kind == "f8":
            out[name] = np.frombuffer(data, dtype="<f8").astype(np.float64)
        elif kind == "i8":
            out[name] = np.frombuffer(data, dtype="<i8").astype(np.int64)
        else:
            out[name] = list(data)
    return _frame(out)


def _number_column(values: List[str]) -> Any:
    """A CSV column as int64 (whole numbers, none missing), float64 (numbers, an empty field
    NaN) or strings. Numbers are read at full precision (Python's float is round-trip)."""
    if values and all(_is_int(v) for v in values):
        return np.array([int(v) for v in values], dtype=np.int64)
    try:
        return np.array([float(v) if v != "" else math.nan for v in values], dtype=np.float64)
    except ValueError:
        return values


def _is_int(v: str) -> bool:
    s = v[1:] if v[:1] in "+-" else v
    return s.isdigit()


def _csv_table(text: str) -> Table:
    """A table of CSV text as the library writes it."""
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        return _frame({})
    head, body = rows[0], rows[1:]
    cols = {h: _number_column([r[i] if i < len(r) else "" for r in body]) for i, h in enumerate(head)}
    return _frame(cols)


def _attach(exc: BaseException, result: Any) -> BaseException:
    try:
        exc.result = result  # type: ignore[attr-defined]
    except (AttributeError, TypeError):
        pass
    return exc


class Result:
    """What a run computed, however it ended (finished, cancelled or failed).

    ``history``, ``events`` and ``summary`` are those of the CLI's history.csv, events.csv and
    summary.json for the same run, at full precision: the history's numbers are the CLI's bit
    for bit, and ``history_csv()``, ``events_csv()``, ``summary_json()`` give the files' text.
    """

    def __init__(self, native: Any) -> None:
        self._native = native
        self._history: Any = None
        self._events: Any = None
        self._summary: Optional[Dict[str, Any]] = None

    @property
    def status(self) -> str:
        """``"finished"``, ``"cancelled"`` or ``"failed"`` (summary.json's ``status``)."""
        return self._native.status

    @property
    def history(self) -> Table:
        """history.csv's table: ``t``, ``row`` (grid / pre-event / post-event), each DOF, its
        rate ``d/dt DOF``, per contact ``gap``, ``gap_rate``, ``slip_rate``, ``normal_force``,
        ``tangential_force``, ``state``, per element ``deformation`` and ``force``, the energy
        ledger ``energy.*`` and the seat margins."""
        if self._history is None:
            self._history = _table(self._native.history_columns())
        return self._history

    @property
    def events(self) -> Table:
        """events.csv's table: ``t``, ``contact``, ``kind``, the impulses and rates, ``sticks``
        and ``accumulation_time`` (NaN where the CSV's field is empty)."""
        if self._events is None:
            self._events = _table(self._native.event_columns())
        return self._events

    @property
    def summary(self) -> Dict[str, Any]:
        """summary.json as a dict: ``status``, ``failure`` or ``cancelled_at`` when they
        apply, then the run's summary (peaks, contacts, energy, stats, …)."""
        if self._summary is None:
            self._summary = json.loads(self._native.summary_json())
        return self._summary

    @property
    def failure(self) -> Optional[Dict[str, Any]]:
        """``{"t", "kind", "reason"}`` of a failed run, else None."""
        f = self._native.failure
        return None if f is None else {"t": f[0], "kind": f[1], "reason": f[2]}

    @property
    def cancelled_at(self) -> Optional[float]:
        """The instant a cancelled run stopped at, else None."""
        return self._native.cancelled_at

    @property
    def method(self) -> str:
        """The integration method the run used."""
        return self._native.method

    @property
    def cpu_time(self) -> float:
        """CPU seconds the library spent integrating (the thread that ran it)."""
        return self._native.cpu_time

    @property
    def warnings(self) -> List[str]:
        """What the model was compiled with that its file does not say (as the CLI warns)."""
        return list(self._native.warnings)

    @property
    def notes(self) -> List[str]:
        """Why a fixed-step method chose its step, per attempt (as the CLI reports)."""
        return list(self._native.notes)

    def history_csv(self) -> str:
        """history.csv's text, byte for byte as ``deckspin run`` writes it."""
        return self._native.history_csv()

    def events_csv(self) -> str:
        """events.csv's text, byte for byte as ``deckspin run`` writes it."""
        return self._native.events_csv()

    def summary_json(self) -> str:
        """summary.json's text, as ``deckspin run`` writes it (``stats.wall_time`` differs)."""
        return self._native.summary_json()

    def write(self, out: PathLike) -> None:
        """Write history.csv, events.csv and summary.json into the folder ``out`` (created),
        as ``deckspin run --out``."""
        self._native.write(os.fspath(out))

    def __repr__(self) -> str:
        s = self.summary
        return f"<deckspin.Result {self.status}: {s.get('title', '')!r}, t_end = {s.get('t_end')} s>"


class Model:
    """A model: a file, or TOML text, with ``set=`` overrides; compiled when made, so that a bad
    model raises :class:`ModelError` here.

    - ``Model("models/four-span.toml")``: a model file; its record files are relative to it.
    - ``Model(text=toml_text, base="models")``: model text (named ``<text>`` in errors); its
      record files are relative to ``base``, else to the current directory.
    - ``set``: a mapping of dotted keys to Python values (``{"contacts.mu": 0.3,
      "solver.method": "moreau"}``; a str is a TOML string, a list a TOML array), or
      ``key=value`` strings exactly as the CLI's ``--set`` (``["contacts.mu=0.3"]``).
    """

    def __init__(
        self,
        path: Optional[PathLike] = None,
        *,
        text: Optional[str] = None,
        set: Overrides = None,
        base: Optional[PathLike] = None,
    ) -> None:
        if (path is None) == (text is None):
            raise TypeError("Model() takes a path or text=, not both")
        if path is not None and base is not None:
            raise TypeError("base= applies to a model given as text=")
        self._source = (
            None if path is None else os.fspath(path),
            text,
            None if base is None else os.fspath(base),
        )
        self._native = _native.load(*self._source, _overrides(set))

    def _with(self, extra: Overrides) -> "Model":
        """This model with more overrides after its own."""
        more = _overrides(extra)
        if not more:
            return self
        m = Model.__new__(Model)
        m._source = self._source
        m._native = _native.load(*self._source, list(self._native.set) + more)
        return m

    @property
    def title(self) -> str:
        """The model's title (a bridge's with its test run added)."""
        return self._native.title

    @property
    def path(self) -> str:
        """The file, or ``<text>`` (under ``base``) for a model given as text."""
        return self._native.path

    @property
    def text(self) -> str:
        """The model's TOML text (before its overrides)."""
        return self._native.text

    @property
    def set(self) -> List[str]:
        """The overrides as ``--set`` arguments."""
        return list(self._native.set)

    @property
    def warnings(self) -> List[str]:
        """What the model was compiled with that its file does not say (defaults taken, …)."""
        return list(self._native.warnings)

    @property
    def dof_names(self) -> List[str]:
        """The degrees of freedom (``deck.x``, ``deck.theta``, …): the history's columns."""
        return list(self._native.dof_names)

    @property
    def contact_names(self) -> List[str]:
        """The contacts (the deck's corners against the abutments, …)."""
        return list(self._native.contact_names)

    @property
    def t_end(self) -> float:
        """The run's end time, s (``solver.t_end``)."""
        return self._native.t_end

    @property
    def method(self) -> str:
        """The integration method of the model's settings."""
        return self._native.method

    def run(
        self,
        method: Optional[str] = None,
        *,
        progress: Optional[Callable[[float, float], Any]] = None,
        interval: float = 0.1,
        check: bool = True,
    ) -> Result:
        """Run the model as ``deckspin run`` does, the GIL released.

        - ``method``: ``"event"``, ``"moreau"``, ``"penalty"``, ``"penalty-explicit"`` (see
          :func:`methods`); default: the model's.
        - ``progress(t, t_end)``: called every ``interval`` seconds at most (default 0.1), on
          the calling thread; returning False cancels the run (status ``"cancelled"``,
          returned); an exception it raises cancels the run and is raised, the partial result
          as its ``result``.
        - Ctrl-C (SIGINT, on the main thread) cancels the run and raises KeyboardInterrupt,
          the partial result (status ``"cancelled"``) as its ``result``.
        - A solver failure raises :class:`RunFailed` (its ``result`` the partial run) unless
          ``check=False``, which returns it (status ``"failed"``).
        - Raises :class:`LimitError` when the run's history would be too large to keep.
        """
        native, raised = self._native.run(method, progress, float(interval))
        result = Result(native)
        if raised is not None:
            raise _attach(raised, result)
        f = native.failure
        if check and f is not None:
            raise RunFailed(f[2], f[0], f[1], result)
        return result

    def modes(self) -> Table:
        """The eigen-analysis of the initial system (``deckspin modes``): ``mode``,
        ``period`` (s), ``frequency`` (Hz), ``omega`` (rad/s) and one column per DOF, each
        shape scaled to its largest component."""
        return _table(_native.modes(self._native))

    def __repr__(self) -> str:
        return f"<deckspin.Model {self.title!r} ({self.path})>"


ModelLike = Union[Model, PathLike]


def _model(model: ModelLike, fix: Overrides = None) -> Model:
    if isinstance(model, Model):
        return model._with(fix)
    return Model(model, set=fix)


def run(
    model: ModelLike,
    *,
    set: Overrides = None,
    method: Optional[str] = None,
    progress: Optional[Callable[[float, float], Any]] = None,
    check: bool = True,
) -> Result:
    """``Model(model, set=set).run(method, ...)``: one run of a model file."""
    return _model(model, set).run(method, progress=progress, check=check)


def sweep(
    model: ModelLike,
    set: Union[Mapping[str, Any], Iterable[str]],
    *,
    fix: Overrides = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    interval: float = 0.1,
) -> Table:
    """Every combination of swept keys (``deckspin sweep``), run in parallel in the library.

    - ``set``: the swept keys, each a list of values (``{"contacts.mu": [0.1, 0.3]}``) or a
      range text ``"a:b:step"`` (inclusive; ``{"contacts.mu": "0:0.7:0.1"}``), or the CLI's
      ``key=a:b:step`` / ``key=v1,v2`` strings. The first key varies slowest.
    - ``fix``: overrides applied to every run (as :class:`Model`'s ``set``).
    - ``progress(done, planned)``: called every ``interval`` seconds; False or an exception
      cancels the runs not started yet (their rows' ``error`` says so). Ctrl-C too, then
      KeyboardInterrupt is raised with the table as its ``result``.

    One row per combination: the swept keys (numbers where every value is one),
    ``peak_rotation``, ``residual_rotation``, ``peak_x``, ``peak_y``, ``impacts``,
    ``stick_time``, ``energy_closure_rel``, ``wall_time`` (s) and ``error`` (empty when the
    run finished): the CLI's sweep CSV at full precision, plus the wall time.
    """
    m = _model(model, fix)
    axes = _axes(set)
    cols, _, raised = _native.sweep(m._native, axes, progress, float(interval))
    table = _table(cols, len(axes))
    if raised is not None:
        raise _attach(raised, table)
    return table


def suite(
    model: ModelLike,
    records: PathLike,
    *,
    measure: str,
    levels: Union[str, Sequence[float]],
    damping: Optional[float] = None,
    set: Union[Mapping[str, Any], Iterable[str], None] = None,
    fix: Overrides = None,
    tail: float = 2.0,
    stats: bool = False,
    progress: Optional[Callable[[int, int], Any]] = None,
    interval: float = 0.1,
) -> Union[Table, Tuple[Table, Table]]:
    """A record suite (``deckspin suite``): the bridge under every record pair of ``records``
    scaled to each intensity level, crossed with swept keys, run in parallel in the library.

    - ``records``: a folder of .AT2 records (paired by station) or a list file.
    - ``measure``: ``"pga"``, ``"sa:T"`` (T in s) or ``"sa:T1"``; ``damping``: ζ of Sa.
    - ``levels``: g, a list of numbers or ``"a:b:step"``.
    - ``set``: swept keys (as :func:`sweep`), ``fix``: overrides of every run, ``tail``: free
      vibration after the longer record, s.
    - ``progress``, ``interval``, Ctrl-C: as :func:`sweep`.

    The table of the runs (the CLI's suite CSV: ``pair``, ``longitudinal``, ``transverse``,
    ``measure``, ``level``, ``scale``, the swept keys, ``status``, then the metrics); with
    ``stats=True`` also the per-level statistics (the CLI's ``STEM-stats.csv``).
    """
    m = _model(model, fix)
    if not isinstance(levels, str):
        levels = ",".join(_toml(float(x)) for x in levels)
    runs_csv, stats_csv, _single, raised = _native.suite(
        m._native,
        os.fspath(records),
        measure,
        levels,
        None if damping is None else float(damping),
        _axes(set),
        float(tail),
        progress,
        float(interval),
    )
    runs = _csv_table(runs_csv)
    out: Any = (runs, _csv_table(stats_csv)) if stats else runs
    if raised is not None:
        raise _attach(raised, out)
    return out


def modes(model: ModelLike, *, set: Overrides = None) -> Table:
    """The eigen-analysis of a model's initial system (``deckspin modes``): see
    :meth:`Model.modes`."""
    return _model(model, set).modes()


def methods() -> List[str]:
    """The integration methods a run may use."""
    return list(_native.methods())


def fig8_mus() -> List[float]:
    """The friction coefficients of the paper's Fig. 8: 0, 0.1, …, 0.7."""
    return list(_native.fig8_mus())
