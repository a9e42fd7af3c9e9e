"""Pictures of a run with matplotlib: :func:`snapshot` draws one snapshot's
floes as polygons coloured by a field, the walls and land in grey."""

from __future__ import annotations

import os
from typing import Any, Optional, Tuple, Union

import numpy as np

from ._runfile import Run, open_run

PathLike = Union[str, "os.PathLike[str]"]

COLOURS = ("speed", "theta", "stress", "thickness")


def floe_pressure(run: Run, k: int) -> np.ndarray:
    """Each floe's pressure ``-(sigma_xx + sigma_yy) / 2``, Pa, compression
    positive: from the run's filtered floe stress where it has one, else
    from the snapshot's contacts (the Love-Weber mean stress
    ``sum f (x) (x_c - x) / (A h)`` of each floe's contact forces; bonds,
    which a run file does not list, are left out)."""
    ds = run.snapshot(k)
    if "stress" in ds:
        s = ds["stress"].values
        return -(s[:, 0] + s[:, 2]) / 2
    c = run.contacts(k)
    n = ds.sizes["floe"]
    normal = c["normal"].values
    perp = np.column_stack([-normal[:, 1], normal[:, 0]])
    force_b = c["normal_force"].values[:, None] * normal + c["tangential_force"].values[:, None] * perp
    size = np.asarray(run.parameters.attrs["domain_size_m"])
    periodic = np.asarray(run.parameters.attrs["periodic"], dtype=bool)
    position = ds["position"].values
    trace = np.zeros(n)
    for idx, force in ((c["a"].values, -force_b), (c["b"].values, force_b)):
        arm = c["point"].values - position[idx]
        # Across a periodic seam, the arm to the nearest image.
        arm = np.where(periodic, arm - size * np.round(arm / size), arm)
        np.add.at(trace, idx, (force * arm).sum(axis=1))
    volume = ds["area"].values * ds["thickness"].values
    # Love-Weber with arm from the floe to the contact: f . (x_c - x) is
    # tension positive; pressure is minus half the trace.
    return -trace / (2 * volume)


def floe_theta(run: Run, k: int) -> np.ndarray:
    """Each floe's mean rate-and-state state ``theta`` over its contacts
    (NaN for a floe without contacts)."""
    c = run.contacts(k)
    n = run.snapshot(k).sizes["floe"]
    total, count = np.zeros(n), np.zeros(n)
    for idx in (c["a"].values, c["b"].values):
        np.add.at(total, idx, c["theta"].values)
        np.add.at(count, idx, 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return total / count


def snapshot(
    run: Union[Run, PathLike],
    k: int = -1,
    color: str = "speed",
    ax: Optional[Any] = None,
    cmap: Optional[str] = None,
    colorbar: bool = True,
) -> Any:
    """Draw snapshot ``k`` of ``run`` (a :class:`floe.Run` or a path) on
    ``ax`` (a new figure's if None): the free floes as polygons coloured by
    ``color`` (``speed`` m/s, ``theta`` the mean state of their contacts,
    ``stress`` their pressure in Pa, ``thickness`` m), walls and land in
    grey, with a colour bar. Returns the axes."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    if color not in COLOURS:
        raise ValueError(f"color={color!r}: one of {', '.join(COLOURS)}")
    if not isinstance(run, Run):
        run = open_run(run)
    ds = run.snapshot(k)
    polygons = run.polygons(k)
    fixed = ds["prescribed"].values
    land = ds["land"].values
    values, label, default_cmap = _field(run, k, color, ds)
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 8 * _aspect(run)))
    free = [p for p, f in zip(polygons, fixed) if not f]
    coll = PolyCollection(free, array=values[~fixed], cmap=cmap or default_cmap,
                          edgecolors="k", linewidths=0.2)
    ax.add_collection(coll)
    walls = [p for p, f, l in zip(polygons, fixed, land) if f and not l]
    shore = [p for p, l in zip(polygons, land) if l]
    ax.add_collection(PolyCollection(walls, facecolors="0.6", edgecolors="0.4", linewidths=0.2))
    ax.add_collection(PolyCollection(shore, facecolors="tan", edgecolors="0.4", linewidths=0.2))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x, m")
    ax.set_ylabel("y, m")
    t = float(ds["time"])
    ax.set_title(f"{os.path.basename(run.path)}: snapshot {ds.attrs['snapshot']}, t = {t:.0f} s")
    if colorbar:
        ax.figure.colorbar(coll, ax=ax, label=label, shrink=0.8)
    return ax


def _field(run: Run, k: int, color: str, ds: Any) -> Tuple[np.ndarray, str, str]:
    if color == "speed":
        return ds["speed"].values, "speed, m/s", "viridis"
    if color == "theta":
        return floe_theta(run, k), "mean contact state theta", "coolwarm"
    if color == "stress":
        return floe_pressure(run, k), "pressure, Pa (compression positive)", "magma"
    return ds["thickness"].values, "thickness, m", "Blues"


def _aspect(run: Run) -> float:
    w, h = np.asarray(run.parameters.attrs["domain_size_m"], dtype=float)
    return float(np.clip(h / w, 0.3, 1.5))
