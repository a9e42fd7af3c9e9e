"""floe.open_run: snapshots, contacts and observables as xarray Datasets,
checked against the file read with h5py (an independent reader) and
against geometry (each polygon's area and centroid are its floe's)."""

from __future__ import annotations

import subprocess
import time

import h5py
import numpy as np
import pytest

import floe
from conftest import ROOT, run_cli

FRACTURE = ROOT / "tests" / "data" / "run_fracture.toml"
WELDING = ROOT / "tests" / "data" / "run_welding.toml"


@pytest.fixture(scope="module")
def fracture_run(tmp_path_factory, floe_binary):
    out = tmp_path_factory.mktemp("read") / "fracture.h5"
    run_cli(floe_binary, "run", str(FRACTURE), "-o", str(out), "--quiet")
    return out


def segments(path):
    """(first snapshot, group) of each floe segment, read with h5py."""
    with h5py.File(path, "r") as f:
        names = sorted((g for g in f["particles"] if g.startswith("floes")),
                       key=lambda g: int(g[6:] or 0))
        return [(int(f["particles"][g].attrs.get("first_snapshot", 0)), g) for g in names]


def shoelace(p):
    x, y = p[:, 0], p[:, 1]
    xs, ys = np.roll(x, -1), np.roll(y, -1)
    cross = x * ys - xs * y
    area = cross.sum() / 2
    return area, np.array([((x + xs) * cross).sum(), ((y + ys) * cross).sum()]) / (6 * area)


def test_snapshots_are_the_file_s_and_follow_the_floes_as_they_break(fracture_run):
    run = floe.open_run(fracture_run)
    segs = segments(fracture_run)
    assert len(segs) > 1, "the fracture run changes its floes"
    with h5py.File(fracture_run, "r") as f:
        n = f["particles/floes/position/step"].shape[0] + sum(
            f["particles"][g]["position/step"].shape[0] for _, g in segs[1:])
        assert len(run) == n
        for k in range(len(run)):
            first, g = max(s for s in segs if s[0] <= k)
            grp = f["particles"][g]
            ds = run.snapshot(k)
            row = k - first
            np.testing.assert_array_equal(ds["id"].values, grp["id"][()])
            np.testing.assert_array_equal(ds["position"].values, grp["position/value"][row])
            np.testing.assert_array_equal(ds["velocity"].values, grp["velocity/value"][row])
            np.testing.assert_array_equal(ds["angle"].values, grp["angle/value"][row])
            np.testing.assert_array_equal(ds["thickness"].values, grp["thickness"][()])
            np.testing.assert_array_equal(ds["stress"].values, grp["stress/value"][row])
            assert float(ds["time"]) == grp["position/time"][row]
            # Contacts: rows start[k] .. start[k] + count[k].
            c = run.contacts(k)
            start, count = f["contacts/start"][k], f["contacts/count"][k]
            np.testing.assert_array_equal(
                np.column_stack([c["a"], c["b"]]), f["contacts/pair"][start:start + count])
            np.testing.assert_array_equal(c["mu"].values, f["contacts/mu"][start:start + count])
            assert (c["b"].values < ds.sizes["floe"]).all()
    last = run.snapshot(-1)
    assert (last["parent_id"] >= 0).any() and (last["parent_id"] == -1).any()
    assert last.sizes["floe"] > run.snapshot(0).sizes["floe"]


def test_polygons_have_their_floes_area_and_centroid(fracture_run):
    run = floe.open_run(fracture_run)
    ds = run.snapshot(-1)
    polys = run.polygons(-1)
    assert len(polys) == ds.sizes["floe"]
    for p, area, pos in zip(polys, ds["area"].values, ds["position"].values):
        a, c = shoelace(p)
        assert a == pytest.approx(area, rel=1e-9)  # counter-clockwise: positive
        np.testing.assert_allclose(c, pos, atol=1e-6 * np.sqrt(area))


def test_observables_parameters_and_logs(fracture_run):
    run = floe.open_run(fracture_run)
    obs = run.observables
    with h5py.File(fracture_run, "r") as f:
        np.testing.assert_array_equal(obs["kinetic_translational"].values,
                                      f["observables/kinetic_translational/value"][()])
        np.testing.assert_array_equal(obs["mean_stress"].values,
                                      f["observables/mean_stress/value"][()])
        np.testing.assert_array_equal(obs["time"].values,
                                      f["observables/contacts/time"][()])
        assert len(run.fractures()["parent"]) == f["fracture/parent"].shape[0]
    assert obs["kinetic_translational"].attrs["units"] == "J"
    assert run.status == "completed"
    assert run.parameters.attrs["scenario_toml"] == FRACTURE.read_text()
    assert run.scenario["fracture.criterion"] == "mohr_coulomb"
    assert "floe" in run.provenance.attrs["command_line"]
    assert len(run.ridges()["step"]) == 0
    assert len(run.welds()["step"]) == 0


def test_the_welding_log_is_h5py_s(tmp_path, floe_binary):
    out = tmp_path / "welding.h5"
    run_cli(floe_binary, "run", str(WELDING), "-o", str(out), "--quiet")
    welds = floe.open_run(out).welds()
    with h5py.File(out, "r") as f:
        for name in f["welding"]:
            np.testing.assert_array_equal(welds[name].values, f["welding"][name][()])
    assert len(welds["step"]) >= 10
    # The welded floe is the pair's hull: never smaller than the pair less
    # its overlap; ids counted on in order.
    pair = welds["area_first"] + welds["area_second"]
    assert bool((welds["area"] > 0.99 * pair).all())
    assert list(np.diff(welds["welded"].values)) == [1] * (len(welds["step"]) - 1)


def test_bad_files_and_indices(tmp_path, fracture_run):
    with pytest.raises(FileNotFoundError):
        floe.open_run(tmp_path / "missing.h5")
    (tmp_path / "text.h5").write_text("not hdf5")
    with pytest.raises(floe.RunFileError):
        floe.open_run(tmp_path / "text.h5")
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = [1, 2, 3]
    with pytest.raises(floe.RunFileError, match="floe"):
        floe.open_run(tmp_path / "other.h5")
    with pytest.raises(floe.RunFileError):
        floe.open_run(tmp_path)
    run = floe.open_run(fracture_run)
    with pytest.raises(IndexError):
        run.snapshot(len(run))
    with pytest.raises(IndexError):
        run.contacts(-len(run) - 1)


def test_a_file_being_written_can_be_read(tmp_path, floe_binary):
    scenario = tmp_path / "long.toml"
    floe.Scenario.from_file(ROOT / "scenarios" / "demo.toml").with_values(
        {"duration_s": 3000.0, "output.snapshot_every_s": 30.0}).write(scenario)
    child = subprocess.Popen([str(floe_binary), "run", str(scenario), "-o",
                              str(tmp_path / "live.h5"), "--quiet", "--threads", "1"])
    try:
        seen, reads, deadline = [], 0, time.monotonic() + 120
        while (child.poll() is None or reads == 0) and time.monotonic() < deadline:
            time.sleep(0.01)
            if (tmp_path / "live.h5").exists():
                try:
                    run = floe.open_run(tmp_path / "live.h5")
                except floe.RunFileError:
                    continue  # created but not yet a floe file
                n = len(run)
                if n:
                    assert run.snapshot(n - 1).sizes["floe"] == 399
                seen.append(n)
                reads += 1
    finally:
        child.wait(timeout=120)
    assert child.returncode == 0
    seen.append(len(floe.open_run(tmp_path / "live.h5")))
    assert seen == sorted(seen) and seen[-1] >= 99  # one per 40 steps of 3953
    assert len(set(seen)) > 2, f"the reads saw the file grow: {seen[:10]}..."
