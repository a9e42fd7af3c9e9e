"""Running a scenario in this process: floe's run loop in a thread of its
own, the GIL released, with a progress bar and Ctrl-C as in ``floe run``."""

from __future__ import annotations

import os
import sys
from typing import Any, Dict, Optional, Union

from . import _floe
from ._floe import Scenario

PathLike = Union[str, "os.PathLike[str]"]

class _Bar:
    """A tqdm bar over the run's steps (plain lines every 10 % without
    tqdm)."""

    def __init__(self, show: bool) -> None:
        self.show = show
        self.bar: Any = None
        self.next_fraction = 0.1

    def line(self, text: str) -> None:
        if self.show:
            print(text, file=sys.stderr, flush=True)

    def update(self, first: int, step: int, total: int, time_s: float, end_s: float) -> None:
        if not self.show:
            return
        if self.bar is None:
            try:
                from tqdm.auto import tqdm
            except ImportError:
                tqdm = None
            if tqdm is not None:
                self.bar = tqdm(total=total, initial=first, unit="step", dynamic_ncols=True)
            else:
                self.bar = False
        if self.bar:
            self.bar.update(step - self.bar.n)
            self.bar.set_postfix_str(f"t = {time_s:.0f} / {end_s:.0f} s", refresh=False)
        else:
            fraction = step / max(total, 1)
            if fraction >= self.next_fraction:
                print(f"step {step}/{total} ({100 * fraction:.0f} %), t = {time_s:.0f} s",
                      file=sys.stderr, flush=True)
                while self.next_fraction <= fraction:
                    self.next_fraction += 0.1

    def new_run_aware_update(
        self, first: int, step: int, total: int, time_s: float, end_s: float
    ) -> None:
        """As :meth:`update`, with a fresh bar when a new run begins (a
        comparison runs one scenario after another)."""
        if self.bar and (total != self.bar.total or step < self.bar.n):
            # The run before has ended: its bar shows it whole.
            self.bar.update(self.bar.total - self.bar.n)
            self.bar.close()
            self.bar = None
        self.update(first, step, total, time_s, end_s)

    def close(self) -> None:
        if self.bar:
            self.bar.close()

def _command_line(call: str) -> list:
    return [sys.executable, *sys.argv, call]


def _with_progress(progress: bool, call: Any, *args: Any, **kwargs: Any) -> Any:
    """``call(*args, **kwargs)`` with a progress bar's callbacks, the bar
    closed however the call ends."""
    bar = _Bar(progress)
    try:
        return call(*args, on_line=bar.line, on_progress=bar.new_run_aware_update, **kwargs)
    finally:
        bar.close()

def run(
    scenario: Union[Scenario, PathLike],
    out: PathLike,
    *,
    threads: Optional[int] = None,
    progress: bool = True,
    force: bool = False,
    max_steps: Optional[int] = None,
    xdmf: bool = False,
) -> Dict[str, Any]:
    """Run ``scenario`` (a :class:`floe.Scenario` or a scenario file) into
    the run file ``out`` (HDF5, docs/output.md), in this process, as
    ``floe run SCENARIO -o OUT`` does: the same file, bitwise, for the same
    scenario (only the provenance differs).

    ``threads``: worker threads (default: the scenario's ``threads``, else
    every core; results are bitwise the same for any count). ``progress``:
    a progress bar (tqdm where installed) and the set-up lines on standard
    error. ``force``: replace an existing ``out``. ``max_steps``: stop after
    this many steps with a checkpoint (continue with :func:`floe.resume`).
    ``xdmf``: when the run stops (completed or paused), describe the file
    for ParaView beside it, as ``floe run --xdmf`` (:func:`floe.export_xdmf`).

    The GIL is released while the run steps. Ctrl-C stops the run after
    the current step, writes a final snapshot and checkpoint (status
    ``interrupted at step N``) and raises ``KeyboardInterrupt``; resume it
    with :func:`floe.resume`. Returns a dict: ``status`` (``completed`` or
    ``paused``), ``final_step``, ``total_steps``, ``final_time_s``,
    ``steps_taken``, ``wall_s``, ``threads``, ``output``, ``summary``.
    """
    if not isinstance(scenario, Scenario):
        scenario = Scenario.from_file(os.fspath(scenario))
    summary = _with_progress(
        progress,
        _floe.run,
        scenario,
        os.fspath(out),
        threads=threads,
        force=force,
        max_steps=max_steps,
        command_line=_command_line(f"floe.run({scenario.path}, {os.fspath(out)})"),
    )
    return _with_xdmf(summary, out, xdmf)


def _with_xdmf(summary: Dict[str, Any], out: PathLike, xdmf: bool) -> Dict[str, Any]:
    """The summary, with ``xdmf`` (the ParaView description written beside
    ``out``) when asked for."""
    if xdmf:
        target = os.path.splitext(os.fspath(out))[0] + ".xdmf"
        summary["xdmf"] = str(_floe.export_xdmf(os.fspath(out), target, force=True)[0])
    return summary


def resume(
    out: PathLike,
    *,
    threads: Optional[int] = None,
    progress: bool = True,
    max_steps: Optional[int] = None,
    xdmf: bool = False,
) -> Dict[str, Any]:
    """Continue the run in ``out`` from its last checkpoint, as
    ``floe run --resume OUT``: the finished file is bitwise the one an
    uninterrupted run writes. Arguments and result as :func:`floe.run`."""
    summary = _with_progress(
        progress,
        _floe.resume,
        os.fspath(out),
        threads=threads,
        max_steps=max_steps,
        command_line=_command_line(f"floe.resume({os.fspath(out)})"),
    )
    return _with_xdmf(summary, out, xdmf)
