"""floe's exceptions.

Every error floe raises on purpose is a :class:`FloeError`; the standard
ones are used where they fit (``FileNotFoundError`` for a missing file,
``FileExistsError`` for an output that exists without ``force=True``,
``TypeError`` for a value of the wrong type, ``KeyboardInterrupt`` for a run
stopped by Ctrl-C, after its final snapshot and checkpoint).
"""

from __future__ import annotations

from typing import Optional

__all__ = ["FloeError", "ScenarioError", "RunError", "RunFileError"]


class FloeError(Exception):
    """Base class of floe's own errors."""


class ScenarioError(FloeError, ValueError):
    """A scenario that floe refuses, located where the scenario reader
    locates it: ``file``, ``line``, ``column`` (1-based), ``key`` (the dotted
    key, when there is one) and ``reason`` (what is wrong); ``str(e)`` is the
    message ``floe run`` prints. A problem not located in a file (a
    ``--set``-style edit of a key whose table is an array element, say) has
    them all ``None``. ``key`` is the key as the reader names it: the dotted
    path, or for a value of the wrong type its last part (``size_m``)."""

    def __init__(
        self,
        message: str,
        *,
        file: Optional[str] = None,
        line: Optional[int] = None,
        column: Optional[int] = None,
        key: Optional[str] = None,
        reason: Optional[str] = None,
    ) -> None:
        super().__init__(message)
        self.file = file
        self.line = line
        self.column = column
        self.key = key
        self.reason = reason if reason is not None else message


class RunError(FloeError, RuntimeError):
    """A run that stopped: a numerical blow-up (the last good state is in
    the checkpoint), a forcing that ran out, or an error of floe itself."""


class RunFileError(FloeError, ValueError):
    """A file that is not a floe run file, or one that cannot be read."""
