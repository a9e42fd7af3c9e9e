"""The friction laws side by side, as ``floe compare`` does it, from
Python: the same ice, forcing and seed under each law (only ``[friction]``
differs), each run into ``OUT/<law>.h5``, the report ``OUT/report.md``,
and the report's table as a pandas DataFrame."""

from __future__ import annotations

import os
from typing import Optional, Sequence, Union

import pandas as pd

from . import _floe
from ._floe import Scenario
from ._running import _command_line, _with_progress

PathLike = Union[str, "os.PathLike[str]"]


def compare(
    scenario: Union[Scenario, PathLike],
    out: PathLike,
    laws: Sequence[str] = ("amontons", "rate", "rate-state"),
    *,
    threads: Optional[int] = None,
    force: bool = False,
    progress: bool = True,
    reference_slip_m_per_s: float = 1e-2,
    amontons_mu: Optional[float] = None,
) -> pd.DataFrame:
    """Run ``scenario`` under each of ``laws`` into the directory ``out``
    and return the metrics of ``floe compare``'s report, one row per law
    (index ``law``), in SI units: ``peak_to_steady``,
    ``steady_shear_stress_n_per_m``, ``final_normal_stress_n_per_m``,
    ``velocity_change_m_per_s``, ``band_equivalent_width_m``,
    ``band_10_90_width_m``, ``slip_events``, ``median_event_slip_m``,
    ``mean_sliding_fraction``, ``friction_dissipation_j``, ``plug_flow``
    (the pack moved as one block: the band widths measure noise), the
    ``friction`` table each ran with and its run ``file``. ``df.attrs
    ["report"]`` is the report's path.

    Amontons and the rate law are matched to the rate-and-state law's
    steady state at ``reference_slip_m_per_s`` (or Amontons' ``mu`` is
    ``amontons_mu``), as ``floe compare --reference-slip-speed`` /
    ``--amontons-mu``. An edited scenario is written to
    ``OUT/scenario.toml`` first (its relative input paths made absolute).
    Ctrl-C stops the run under way after its current step, as in
    :func:`floe.run`."""
    if not isinstance(scenario, Scenario):
        scenario = Scenario.from_file(os.fspath(scenario))
    if isinstance(laws, str):
        laws = [laws]
    report, rows = _with_progress(
        progress,
        _floe.compare,
        scenario,
        os.fspath(out),
        list(laws),
        threads=threads,
        force=force,
        reference_slip_m_per_s=reference_slip_m_per_s,
        amontons_mu=amontons_mu,
        command_line=_command_line(f"floe.compare({scenario.path}, {os.fspath(out)})"),
    )
    df = pd.DataFrame(rows).set_index("law")
    df.attrs["report"] = str(report)
    return df
