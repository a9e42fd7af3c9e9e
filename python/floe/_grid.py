"""Gridded fields of a run as an xarray Dataset: the fields ``floe grid``
writes to NetCDF (docs/output.md, "Gridded fields"), computed by the same
code, without a file."""

from __future__ import annotations

import os
from typing import Optional, Union

import numpy as np
import xarray as xr

from . import _floe
from ._runfile import Run

PathLike = Union[str, "os.PathLike[str]"]


def grid(
    run: Union[Run, PathLike],
    cell_m: float,
    *,
    every: Optional[int] = None,
    interval_s: Optional[float] = None,
) -> xr.Dataset:
    """The run's snapshots on a regular grid of cells of at most ``cell_m``
    metres: a Dataset on ``(time, y, x)`` with ``concentration``,
    ``thickness``, ``u``, ``v``, the four ``stress_*`` components,
    ``divergence``, ``shear`` and ``total_deformation`` (CF names and units
    in each variable's attributes; NaN in cells without ice, where the
    NetCDF file has its fill value). ``every=K`` takes every K-th snapshot,
    ``interval_s=T`` one per T seconds (as ``floe grid --every/--interval-s``).
    With the scenario's ``start_time``, ``time`` is decoded to dates."""
    path = run.path if isinstance(run, Run) else os.fspath(run)
    g = _floe.grid(path, float(cell_m), every=every, interval_s=interval_s)
    data = {}
    for name, values in g["fields"].items():
        standard, units, long_name = g["attributes"][name]
        attrs = {"units": units, "long_name": long_name}
        if standard:
            attrs["standard_name"] = standard
        data[name] = (("time", "y", "x"), values, attrs)
    time_attrs = {"units": "s", "long_name": "time since the start of the run"}
    ds = xr.Dataset(
        data,
        coords={
            "time": ("time", g["time"], time_attrs),
            "snapshot": ("time", g["snapshot"]),
            "y": ("y", g["y"], {"units": "m", "axis": "Y"}),
            "x": ("x", g["x"], {"units": "m", "axis": "X"}),
        },
        attrs={"Conventions": "CF-1.8", "title": f"floe run {path} on a grid"},
    )
    if g["start_time"]:
        start = np.datetime64(g["start_time"].replace(" ", "T").rstrip("Z"), "ns")
        ds = ds.assign_coords(time=start + (g["time"] * 1e9).astype("timedelta64[ns]"))
    return ds
