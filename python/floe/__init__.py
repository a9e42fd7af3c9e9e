"""floe, a discrete-element sea-ice floe simulator, from Python.

Build and vary scenarios (:class:`Scenario`), run them in this process on
floe's own engine (:func:`run`, :func:`resume`), read run files as xarray
Datasets (:func:`open_run`), grid them (:func:`grid`), compare friction
laws (:func:`compare`) and plot them (:mod:`floe.plot`). docs/python.md has the guide.

>>> import floe
>>> s = floe.Scenario.from_file("scenarios/demo.toml")
>>> s["friction.law"]
'rate-state'
>>> floe.run(s.with_values({"duration_s": 600.0}), "out.h5")   # doctest: +SKIP
"""

from __future__ import annotations

from ._floe import GIT_COMMIT, Scenario, __version__
from ._compare import compare
from ._grid import grid
from ._runfile import Run, export_xdmf, open_run
from ._running import resume, run
from .errors import FloeError, RunError, RunFileError, ScenarioError

__all__ = [
    "Scenario",
    "run",
    "resume",
    "open_run",
    "Run",
    "grid",
    "compare",
    "export_xdmf",
    "FloeError",
    "ScenarioError",
    "RunError",
    "RunFileError",
    "GIT_COMMIT",
    "__version__",
]
