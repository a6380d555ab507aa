"""The exceptions of deckspin (pure Python: the native module raises them by name)."""

from __future__ import annotations

from typing import Any, Optional


class DeckspinError(Exception):
    """Base class of deckspin's exceptions."""


class ModelError(DeckspinError, ValueError):
    """A model that cannot be read, overridden or compiled.

    ``str(e)`` is the message the CLI prints (``FILE:LINE: FIELD: reason``). Attributes, each
    None when it does not apply:

    - ``file``: the model file (``<text>`` for a model given as text, under ``base`` if given);
    - ``line``: the line in it, 1-based (``column`` too for a TOML syntax error);
    - ``field``: the dotted field (``contacts.mu``, ``bent.1.height``);
    - ``argument``: the ``set=`` override that gave the value, when one did;
    - ``reason``: the message without the place.
    """

    file: Optional[str] = None
    line: Optional[int] = None
    column: Optional[int] = None
    field: Optional[str] = None
    argument: Optional[str] = None
    reason: Optional[str] = None


class LimitError(DeckspinError):
    """A job refused before it starts: its output or its number of runs above a limit."""


class RunFailed(DeckspinError):
    """A run the solver could not finish (or that finished outside its accuracy bounds).

    Attributes: ``time`` (s, the instant it stopped at), ``kind`` (``"TooManySteps"``,
    ``"Inaccurate"``, …: the ``failure.kind`` of summary.json), ``reason`` (the error's text)
    and ``result``: the :class:`deckspin.Result` with everything computed up to ``time``.
    """

    def __init__(self, reason: str, time: float, kind: str, result: Any) -> None:
        super().__init__(reason)
        self.reason = reason
        self.time = time
        self.kind = kind
        self.result = result
