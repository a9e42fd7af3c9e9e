"""floe.plot.snapshot: one polygon per free floe, coloured by the field
asked for (each colour checked against its own computation); the pressure
from contacts sums to the engine's `mean_stress` observable."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest
from matplotlib.collections import PolyCollection

import floe
import floe.plot
from conftest import ROOT, run_cli


@pytest.fixture(scope="module")
def run_file(tmp_path_factory, floe_binary):
    d = tmp_path_factory.mktemp("plot")
    out = d / "fracture.h5"
    run_cli(floe_binary, "run", str(ROOT / "tests/data/run_fracture.toml"), "-o", str(out), "--quiet")
    return out


@pytest.mark.parametrize("color", ["speed", "theta", "stress", "thickness"])
def test_one_polygon_per_free_floe(run_file, color, tmp_path):
    run = floe.open_run(run_file)
    ax = floe.plot.snapshot(run, -1, color=color)
    ds = run.snapshot(-1)
    colls = [c for c in ax.collections if isinstance(c, PolyCollection)]
    free, walls = colls[0], colls[1]
    assert len(free.get_paths()) == int((~ds["prescribed"]).sum())
    assert len(walls.get_paths()) == int(ds["prescribed"].sum())
    values = free.get_array()
    free = ~ds["prescribed"].values
    c = run.contacts(-1)
    if color == "speed":
        np.testing.assert_array_equal(values, ds["speed"].values[free])
    elif color == "thickness":
        np.testing.assert_array_equal(values, ds["thickness"].values[free])
    elif color == "stress":
        # The run has floe stress: the pressure is its -(xx + yy) / 2.
        s = ds["stress"].values
        np.testing.assert_array_equal(values, (-(s[:, 0] + s[:, 2]) / 2)[free])
    else:
        # Each floe's mean theta over the contacts that name it, counted here.
        expect = np.array([
            c["theta"].values[(c["a"].values == i) | (c["b"].values == i)].mean()
            if ((c["a"].values == i) | (c["b"].values == i)).any() else np.nan
            for i in range(ds.sizes["floe"])
        ])
        np.testing.assert_allclose(values, expect[free], rtol=1e-12)
    ax.figure.savefig(tmp_path / f"{color}.png")
    assert (tmp_path / f"{color}.png").stat().st_size > 10_000


def test_bad_colour(run_file):
    with pytest.raises(ValueError, match="speed"):
        floe.plot.snapshot(run_file, color="colour")


def test_contact_pressure_sums_to_the_mean_stress_observable(tmp_path, floe_binary):
    # Two ways to the pack's stress: each floe's Love-Weber sum from the
    # snapshot's contacts (numpy, here) and the engine's `mean_stress`
    # observable at the same step: sum over free floes of A h tr(sigma) / 2
    # is the observable's (xx + yy) / 2 times the domain's area.
    floe.Scenario.from_file(ROOT / "scenarios" / "demo.toml").with_values(
        duration_s=600.0).write(tmp_path / "demo.toml")
    run_cli(floe_binary, "run", str(tmp_path / "demo.toml"), "-o", str(tmp_path / "d.h5"), "-q")
    run = floe.open_run(tmp_path / "d.h5")
    ds = run.snapshot(-1)
    pressure = floe.plot.floe_pressure(run, -1)
    free = ~ds["prescribed"].values
    volume = (ds["area"] * ds["thickness"]).values
    total = -(2 * pressure * volume)[free].sum()
    obs = run.observables
    at = int(np.flatnonzero(obs["step"].values == ds.attrs["step"])[0])
    xx, _, _, yy = obs["mean_stress"].values[at]
    area = float(np.prod(run.parameters.attrs["domain_size_m"]))
    assert total / area == pytest.approx(xx + yy, rel=1e-9)
    assert xx + yy < 0, "the wind packs the ice: compression"
