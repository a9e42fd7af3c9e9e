"""floe.grid: the fields `floe grid` writes, computed without a file, equal
to the NetCDF file's (read with h5py) and conserving the floes' volume."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

import floe
from conftest import ROOT, run_cli


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory, floe_binary):
    d = tmp_path_factory.mktemp("grid")
    floe.Scenario.from_file(ROOT / "scenarios" / "demo.toml").with_values(
        duration_s=600.0).write(d / "demo.toml")
    run_cli(floe_binary, "run", str(d / "demo.toml"), "-o", str(d / "demo.h5"), "--quiet")
    return d / "demo.h5"


def test_grid_is_floe_grid_s_file(demo_run, floe_binary, tmp_path):
    nc = tmp_path / "grid.nc"
    run_cli(floe_binary, "grid", str(demo_run), "-o", str(nc), "--cell-m", "2500", "--every", "2")
    g = floe.grid(demo_run, 2500.0, every=2)
    with h5py.File(nc, "r") as f:
        np.testing.assert_array_equal(g["x"].values, f["x"][()])
        np.testing.assert_array_equal(g["y"].values, f["y"][()])
        np.testing.assert_array_equal(g["time"].values, f["time"][()])
        for name in g.data_vars:
            stored = f[name][()]
            stored = np.where(stored == f[name].attrs["_FillValue"], np.nan, stored)
            np.testing.assert_array_equal(g[name].values, stored, err_msg=name)
            assert g[name].attrs["units"] == f[name].attrs["units"].decode()
    assert g.sizes["time"] == 3


def clip_below(poly, y):
    """The part of a convex polygon below the line at height y
    (Sutherland-Hodgman against one half-plane)."""
    out = []
    for p, q in zip(poly, np.roll(poly, -1, axis=0)):
        if p[1] <= y:
            out.append(p)
        if (p[1] - y) * (q[1] - y) < 0:
            t = (y - p[1]) / (q[1] - p[1])
            out.append(p + t * (q - p))
    return np.array(out)


def area(poly):
    if len(poly) < 3:
        return 0.0
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float((x * np.roll(y, -1) - np.roll(x, -1) * y).sum())


def test_grid_holds_the_floes_volume(demo_run):
    # The channel is periodic in x; along y the floes pressed into the walls
    # reach past the domain, and only their part inside it is gridded.
    run = floe.open_run(demo_run)
    top = float(run.parameters.attrs["domain_size_m"][1])
    g = floe.grid(run, 1000.0)
    cell_area = float(np.diff(g["x"][:2])[0] * np.diff(g["y"][:2])[0])
    outside_seen = 0.0
    for k in range(len(run)):
        ds = run.snapshot(k)
        volume = 0.0
        for p, h, fixed in zip(run.polygons(k), ds["thickness"].values, ds["prescribed"].values):
            if not fixed:
                inside = area(clip_below(clip_below(p, top) * [1, -1], 0.0) * [1, -1])
                volume += h * abs(inside)
                outside_seen += h * (area(p) - abs(inside))
        gridded = float(np.nansum(g["concentration"][k] * g["thickness"][k]) * cell_area)
        assert gridded == pytest.approx(volume, rel=1e-9)
    assert outside_seen > 0, "some floes reached past the walls' edge"


def test_bad_grids():
    with pytest.raises(FileNotFoundError):
        floe.grid("no-such-run.h5", 100.0)


def test_bad_cell_sizes(demo_run):
    for cell in [0.0, -1.0, float("nan"), 1e-3]:
        with pytest.raises(ValueError, match="cell_m"):
            floe.grid(demo_run, cell)
    with pytest.raises(ValueError):
        floe.grid(demo_run, 1000.0, every=0)
    with pytest.raises(ValueError):
        floe.grid(demo_run, 1000.0, every=2, interval_s=60.0)
