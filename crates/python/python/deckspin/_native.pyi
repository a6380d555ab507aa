"""Type stubs of deckspin._native, the compiled part of the package (PyO3). Use the wrappers of
the package itself (deckspin.Model, deckspin.sweep, …): these calls return raw columns."""

from os import PathLike
from typing import Any, Callable, List, Optional, Tuple, Union

#: (name, "f8" | "i8", little-endian bytes) or (name, "str", list of str)
Column = Tuple[str, str, Any]

class NativeModel:
    """A compiled model: its text, the path naming it, its overrides."""

    @property
    def title(self) -> str: ...
    @property
    def path(self) -> str: ...
    @property
    def text(self) -> str: ...
    @property
    def set(self) -> List[str]: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def dof_names(self) -> List[str]: ...
    @property
    def contact_names(self) -> List[str]: ...
    @property
    def t_end(self) -> float: ...
    @property
    def method(self) -> str: ...
    def run(
        self,
        method: Optional[str],
        progress: Optional[Callable[[float, float], Any]],
        interval: float,
    ) -> Tuple["NativeRun", Optional[BaseException]]:
        """Run as `deckspin run` does, the GIL released: the run, and the exception to raise
        (Ctrl-C's KeyboardInterrupt, or the callback's) or None."""
        ...

class NativeRun:
    """What a run computed, however it ended."""

    @property
    def status(self) -> str: ...
    @property
    def cpu_time(self) -> float: ...
    @property
    def notes(self) -> List[str]: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def method(self) -> str: ...
    @property
    def failure(self) -> Optional[Tuple[float, str, str]]:
        """(t, kind, reason) of a failed run."""
        ...
    @property
    def cancelled_at(self) -> Optional[float]: ...
    def summary_json(self) -> str: ...
    def history_csv(self) -> str: ...
    def events_csv(self) -> str: ...
    def history_columns(self) -> List[Column]: ...
    def event_columns(self) -> List[Column]: ...
    def write(self, dir: Union[str, "PathLike[str]"]) -> None: ...

def load(
    path: Optional[str], text: Optional[str], base: Optional[str], set: List[str]
) -> NativeModel:
    """Compile a model file or text with `--set` overrides; raises deckspin.ModelError."""
    ...

def sweep(
    model: NativeModel,
    axes: List[str],
    progress: Optional[Callable[[int, int], Any]],
    interval: float,
) -> Tuple[List[Column], int, Optional[BaseException]]:
    """`deckspin sweep`: (columns, runs of the integrator, exception to raise or None)."""
    ...

def suite(
    model: NativeModel,
    records: str,
    measure: str,
    levels: str,
    damping: Optional[float],
    axes: List[str],
    tail: float,
    progress: Optional[Callable[[int, int], Any]],
    interval: float,
) -> Tuple[str, str, List[str], Optional[BaseException]]:
    """`deckspin suite`: (runs CSV, statistics CSV, unpaired record files, exception or None)."""
    ...

def modes(model: NativeModel) -> List[Column]:
    """`deckspin modes`: mode, period, frequency, omega, one shape column per DOF."""
    ...

def methods() -> List[str]: ...
def fig8_mus() -> List[float]: ...
def version() -> str: ...
