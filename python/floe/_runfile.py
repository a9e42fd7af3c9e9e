"""Reading a run file as xarray Datasets, one snapshot at a time.

Nothing is read until asked for: :func:`open_run` checks the file and
returns a :class:`Run`; ``run.snapshot(k)`` reads snapshot ``k``'s floes
(about 150 bytes per floe), ``run.contacts(k)`` its contacts. Each read
opens the file anew, so a file that a run is still writing shows its new
snapshots (a read caught mid-flush is retried, docs/output.md). A run with
fracture or ridging changes its floes between snapshots: each snapshot's
Dataset has that snapshot's floes, with ``id`` and ``parent_id``.
"""

from __future__ import annotations

import os
from typing import Any, Dict, Iterator, List, Union

import numpy as np
import xarray as xr

from . import _floe
from ._floe import Scenario

PathLike = Union[str, "os.PathLike[str]"]

_FLOE_UNITS = {
    "position": "m",
    "velocity": "m s-1",
    "angle": "rad",
    "angular_velocity": "rad s-1",
    "thickness": "m",
    "mass": "kg",
    "area": "m2",
    "inertia": "kg m2",
    "stress": "Pa",
    "vertices": "m",
}

_CONTACT_UNITS = {
    "theta": "1",
    "mu": "1",
    "normal_force": "N",
    "tangential_force": "N",
    "slip_rate": "m s-1",
    "overlap_area": "m2",
    "point": "m",
    "normal": "1",
}


def _with_units(ds: xr.Dataset, units: Dict[str, str]) -> xr.Dataset:
    for name, unit in units.items():
        if name in ds:
            ds[name].attrs["units"] = unit
    return ds


class Run:
    """A floe run file opened for reading (see :func:`open_run`)."""

    def __init__(self, path: PathLike) -> None:
        self.path = os.fspath(path)
        self._reader = _floe.RunReader(self.path)

    def __repr__(self) -> str:
        return f"Run({self.path!r}: {len(self)} snapshots, {self.status})"

    def __len__(self) -> int:
        return self._reader.snapshot_count()

    # --- what the run is --------------------------------------------------

    @property
    def status(self) -> str:
        """``running (pid N on HOST)``, ``completed``, ``paused at step N``,
        ``interrupted at step N`` or ``stopped: <reason>``."""
        return self._reader.metadata()["status"]

    @property
    def parameters(self) -> xr.Dataset:
        """The run's parameters as a Dataset of attributes: the scenario's
        text (``scenario_toml``), where it was read from, the domain, and
        the last checkpoint's step and time."""
        m = self._reader.metadata()
        attrs = {
            "scenario_toml": m["scenario_toml"],
            "scenario_path": m["scenario_path"],
            "domain_min_m": np.asarray(m["domain_min"]),
            "domain_size_m": np.asarray(m["domain_size"]),
            "periodic": np.asarray(m["periodic"], dtype=np.uint8),
            "status": m["status"],
        }
        if m["checkpoint"] is not None:
            attrs["checkpoint_step"], attrs["checkpoint_time_s"] = m["checkpoint"]
        return xr.Dataset(attrs=attrs)

    @property
    def provenance(self) -> xr.Dataset:
        """Who made the file: floe's version and commit, the command line,
        threads, processes and author, as a Dataset of attributes."""
        m = self._reader.metadata()
        keys = ["floe_version", "git_commit", "threads", "processes", "author"]
        attrs: Dict[str, Any] = {k: m[k] for k in keys}
        attrs["command_line"] = " ".join(m["command_line"])
        return xr.Dataset(attrs=attrs)

    @property
    def scenario(self) -> Scenario:
        """The scenario the run was made from (its stored text), for reading
        or for a variant: ``run.scenario.with_values({"friction.mu": 0.5})``."""
        m = self._reader.metadata()
        return Scenario.from_text(m["scenario_toml"], m["scenario_path"])

    @property
    def times(self) -> np.ndarray:
        """Every complete snapshot's time, s (without reading the
        snapshots)."""
        return self._reader.snapshot_times()

    # --- snapshots ---------------------------------------------------------

    def _index(self, k: int) -> int:
        n = len(self)
        if k < 0:
            k += n
        if not 0 <= k < n:
            raise IndexError(f"snapshot {k}: the file has {n}")
        return k

    def snapshot(self, k: int) -> xr.Dataset:
        """Snapshot ``k``'s floes (``-1``: the last) as a Dataset on the
        dimension ``floe``: ``id``, ``parent_id`` (-1 for a floe of the
        start), ``position`` and ``velocity`` (``floe, xy``), ``angle``,
        ``angular_velocity``, ``thickness``, ``mass``, ``area``,
        ``inertia``, ``prescribed``, ``land``, ``stress`` (``floe,
        component``: xx, xy, yy; runs with floe stress only), and the
        polygons as a ragged array: ``vertex_count`` per floe and
        ``vertices`` (``vertex, xy``: each floe's in turn, counter-clockwise,
        in world coordinates; ``local_vertices`` about the centroid in the
        floe's frame). ``speed`` is ``|velocity|``."""
        k = self._index(k)
        f = self._reader.floes(k)
        offsets = f["vertex_offsets"].astype(np.int64)
        counts = np.diff(offsets)
        local = f["vertices"]
        # World vertices: each floe's turned by its angle, moved to its position.
        owner = np.repeat(np.arange(len(counts)), counts)
        c, s = np.cos(f["angle"])[owner], np.sin(f["angle"])[owner]
        px, py = f["position"][owner, 0], f["position"][owner, 1]
        world = np.column_stack(
            [px + (c * local[:, 0] - s * local[:, 1]), py + (s * local[:, 0] + c * local[:, 1])]
        )
        data: Dict[str, Any] = {
            "id": ("floe", f["id"]),
            "parent_id": ("floe", f["parent_id"]),
            "position": (("floe", "xy"), f["position"]),
            "velocity": (("floe", "xy"), f["velocity"]),
            "speed": ("floe", np.hypot(f["velocity"][:, 0], f["velocity"][:, 1])),
            "angle": ("floe", f["angle"]),
            "angular_velocity": ("floe", f["angular_velocity"]),
            "thickness": ("floe", f["thickness"]),
            "mass": ("floe", f["mass"]),
            "area": ("floe", f["area"]),
            "inertia": ("floe", f["inertia"]),
            "prescribed": ("floe", f["prescribed"]),
            "land": ("floe", f["land"]),
            "vertex_count": ("floe", counts),
            "vertices": (("vertex", "xy"), world),
            "local_vertices": (("vertex", "xy"), local),
        }
        if f["stress"] is not None:
            data["stress"] = (("floe", "component"), f["stress"])
        coords: Dict[str, Any] = {"xy": ["x", "y"], "time": f["time"]}
        if f["stress"] is not None:
            coords["component"] = ["xx", "xy", "yy"]
        ds = xr.Dataset(data, coords=coords, attrs={"step": f["step"], "snapshot": k})
        ds["speed"].attrs["units"] = "m s-1"
        ds["time"].attrs["units"] = "s"
        return _with_units(ds, _FLOE_UNITS)

    def polygons(self, k: int) -> List[np.ndarray]:
        """Snapshot ``k``'s floes as a list of ``(n_i, 2)`` arrays of world
        vertices."""
        ds = self.snapshot(k)
        ends = np.cumsum(ds["vertex_count"].values)
        return np.split(ds["vertices"].values, ends[:-1])

    def snapshots(self) -> Iterator[xr.Dataset]:
        """Each snapshot in turn (one read at a time)."""
        for k in range(len(self)):
            yield self.snapshot(k)

    def contacts(self, k: int) -> xr.Dataset:
        """Snapshot ``k``'s contacts on the dimension ``contact``: ``a``,
        ``b`` (indices into that snapshot's floes, ``a < b``), ``theta``,
        ``mu``, ``normal_force``, ``tangential_force``, ``slip_rate``,
        ``overlap_area``, ``point`` and ``normal`` (``contact, xy``)."""
        k = self._index(k)
        c = self._reader.contacts(k)
        pair = c["pair"].astype(np.int64)
        data: Dict[str, Any] = {
            "a": ("contact", pair[:, 0]),
            "b": ("contact", pair[:, 1]),
            "point": (("contact", "xy"), c["point"]),
            "normal": (("contact", "xy"), c["normal"]),
        }
        for name in ["theta", "mu", "normal_force", "tangential_force", "slip_rate", "overlap_area"]:
            data[name] = ("contact", c[name])
        ds = xr.Dataset(
            data,
            coords={"xy": ["x", "y"], "time": c["time"]},
            attrs={"step": c["step"], "snapshot": k},
        )
        ds["time"].attrs["units"] = "s"
        return _with_units(ds, _CONTACT_UNITS)

    # --- time series and logs ------------------------------------------------

    @property
    def observables(self) -> xr.Dataset:
        """Every observable on the dimension ``time`` (s; ``step`` as a
        coordinate); ``mean_stress`` and the others with several components
        on a dimension of their own. Observables sampled at other times than
        the first (none today) get a time dimension of their own."""
        names = self._reader.observable_names()
        series = {n: self._reader.observable(n) for n in names}
        data: Dict[str, Any] = {}
        coords: Dict[str, Any] = {}
        reference = series[names[0]]["step"] if names else np.zeros(0, dtype=np.int64)
        for name, s in series.items():
            same = np.array_equal(s["step"], reference)
            tdim = "time" if same else f"time_{name}"
            if not same:
                coords[tdim] = s["time"]
            dims = (tdim, f"{name}_component")[: s["value"].ndim]
            data[name] = (dims, s["value"], {"units": s["unit"]})
        if names:
            coords["time"] = ("time", series[names[0]]["time"], {"units": "s"})
            coords["step"] = ("time", reference)
        ds = xr.Dataset(data, coords=coords)
        if "mean_stress" in ds:
            ds = ds.assign_coords(mean_stress_component=["xx", "xy", "yx", "yy"])
        return ds

    def fractures(self) -> xr.Dataset:
        """The fracture log on the dimension ``event`` (empty without
        fracture): ``step``, ``time``, ``parent``, ``first_piece``,
        ``pieces``, ``sigma_1``, ``sigma_2`` (Pa), ``area`` (m2)."""
        return xr.Dataset({k: ("event", v) for k, v in self._reader.fractures().items()})

    def ridges(self) -> xr.Dataset:
        """The ridging log on the dimension ``event`` (runs with ``[output]
        ridging_log = true``): columns as in docs/output.md."""
        return xr.Dataset({k: ("event", v) for k, v in self._reader.ridges().items()})

    def welds(self) -> xr.Dataset:
        """The welding log on the dimension ``event`` (runs with
        ``[welding]``): ``step``, ``time``, ``first``, ``second``,
        ``welded`` (ids), areas, ``mass``, ``thickness``, ``centre_shift``
        and the energies, as in docs/output.md."""
        return xr.Dataset({k: ("event", v) for k, v in self._reader.welds().items()})


def export_xdmf(run: Union[Run, PathLike], out: PathLike = None, *, force: bool = False) -> str:
    """Describe the run file for ParaView, as ``floe export RUN.h5 --xdmf``:
    ``out`` (default: the run file with ``.xdmf``) points into the run file
    for every field, and ``out + ".h5"`` holds the floes' polygons in world
    coordinates and the contacts' lines (docs/output.md, "ParaView").
    Returns the XDMF file's path; open it in ParaView."""
    path = run.path if isinstance(run, Run) else os.fspath(run)
    if out is None:
        out = os.path.splitext(path)[0] + ".xdmf"
    xdmf, _ = _floe.export_xdmf(path, os.fspath(out), force=force)
    return str(xdmf)


def open_run(path: PathLike) -> Run:
    """Open the floe run file ``path`` for reading (nothing is read until
    asked for). Raises ``FileNotFoundError``, or :class:`floe.RunFileError`
    for a file that is not a floe run file."""
    return Run(path)
