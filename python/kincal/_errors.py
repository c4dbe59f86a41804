"""kincal's exceptions in Python, and the check that decides who handles Ctrl-C."""

from __future__ import annotations

import threading
from typing import Any


class KincalError(ValueError):
    """Bad input to kincal: one line naming what is wrong and where."""


class KincalInterrupt(KeyboardInterrupt):
    """Ctrl-C during a kincal call. ``result`` holds what was done: the report of a solve
    stopped at its best point so far, the best design so far, or the partial study."""

    def __init__(self, message: str, result: Any) -> None:
        super().__init__(message)
        self.result = result


def _on_main_thread() -> bool:
    """Ctrl-C is caught only on the main thread (where Python's own handler is)."""
    return threading.current_thread() is threading.main_thread()
