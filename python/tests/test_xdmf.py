"""`floe export --xdmf`: the XDMF file ParaView opens, read back two ways.

meshio (the issue's suggestion) reads neither HDF5 hyperslabs nor polygon
cells, which a description pointing into the run file needs; so the file
is read here by a small reader of its own (ElementTree and h5py, resolving
every DataItem as XDMF defines it) and, where ParaView is installed
(`make paraview`), by ParaView's own XDMF reader under pvpython. Both must
give every time step's floes, walls and contacts, with the run file's
values."""

from __future__ import annotations

import json
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest

import floe
from conftest import ROOT, run_cli

DTYPES = {("Float", "8"): np.float64, ("UInt", "8"): np.uint64, ("UInt", "4"): np.uint32,
          ("UChar", "1"): np.uint8, ("Int", "8"): np.int64}


def read_item(item: ET.Element, base: Path) -> np.ndarray:
    """A DataItem's values, as XDMF defines them."""
    dims = [int(d) for d in item.get("Dimensions").split()]
    if item.get("ItemType") == "HyperSlab":
        select, source = list(item)
        start, stride, count = read_item(select, base).astype(int)
        data = read_item(source, base)
        index = tuple(slice(a, a + s * c, s) for a, s, c in zip(start, stride, count))
        picked = data[index]
        # The item's Dimensions: the count's, a leading single row dropped.
        shape = list(picked.shape)
        assert dims == shape or (shape[0] == 1 and dims == shape[1:]), (dims, shape)
        return picked.reshape(dims)
    if item.get("Format") == "XML":
        return np.array(item.text.split(), dtype=float).reshape(dims)
    assert item.get("Format") == "HDF"
    name, path = item.text.strip().split(":")
    with h5py.File(base / name, "r") as f:
        data = f[path][()]
    assert list(data.shape) == dims, (path, data.shape, dims)
    assert data.dtype == DTYPES[(item.get("NumberType"), item.get("Precision"))]
    return data


def polygons(grid: ET.Element, base: Path):
    mixed = read_item(grid.find("Topology/DataItem"), base)
    points = read_item(grid.find("Geometry/DataItem"), base)
    out, r = [], 0
    while r < len(mixed):
        assert mixed[r] == 3, "polygon cells"
        n = mixed[r + 1]
        out.append(points[mixed[r + 2:r + 2 + n]])
        r += 2 + n
    assert len(out) == int(grid.find("Topology").get("NumberOfElements"))
    return out


def field(grid: ET.Element, name: str, base: Path) -> np.ndarray:
    a = grid.find(f"Attribute[@Name='{name}']")
    return read_item(a.find("DataItem"), base)


@pytest.fixture(scope="module")
def exported(tmp_path_factory, floe_binary):
    d = tmp_path_factory.mktemp("xdmf")
    run_cli(floe_binary, "run", str(ROOT / "tests/data/run_fracture.toml"), "-o", str(d / "run.h5"), "-q")
    out = run_cli(floe_binary, "export", str(d / "run.h5"), "--xdmf")
    assert "9 snapshots" in out.stdout
    return d


def test_every_step_holds_the_run_s_floes_walls_and_contacts(exported):
    run = floe.open_run(exported / "run.h5")
    root = ET.parse(exported / "run.xdmf").getroot()
    floes, walls, contacts = root.find("Domain").findall("Grid")
    assert [g.get("Name") for g in (floes, walls, contacts)] == ["floes", "walls", "contacts"]
    size = run.parameters.attrs["domain_size_m"]
    periodic = run.parameters.attrs["periodic"].astype(bool)
    # A step without contacts has no contact grid (ParaView's reader cannot
    # take an empty one).
    by_time = lambda g: {float(s.find("Time").get("Value")): s for s in g.findall("Grid")}
    walls_at, contacts_at = by_time(walls), by_time(contacts)
    assert len(floes.findall("Grid")) == len(run)
    counts = set()
    for k, fg in enumerate(floes.findall("Grid")):
        ds, c = run.snapshot(k), run.contacts(k)
        t = float(ds["time"])
        wg = walls_at[t]
        assert float(fg.find("Time").get("Value")) == float(ds["time"])
        polys = polygons(fg, exported)
        counts.add(len(polys))
        assert len(polys) == ds.sizes["floe"]
        for p, q in zip(polys, run.polygons(k)):
            np.testing.assert_allclose(p, q, rtol=0, atol=1e-9)
        assert len(polygons(wg, exported)) == int(ds["prescribed"].sum())
        np.testing.assert_array_equal(field(fg, "velocity", exported), ds["velocity"].values)
        np.testing.assert_array_equal(field(fg, "angular_velocity", exported), ds["angular_velocity"].values)
        np.testing.assert_array_equal(field(fg, "stress", exported), ds["stress"].values)
        np.testing.assert_array_equal(field(fg, "id", exported), ds["id"].values)
        np.testing.assert_array_equal(field(fg, "thickness", exported), ds["thickness"].values)
        # Each floe's mean contact state, counted from the contacts here.
        theta = np.full(ds.sizes["floe"], np.nan)
        for i in range(ds.sizes["floe"]):
            mine = (c["a"].values == i) | (c["b"].values == i)
            if mine.any():
                theta[i] = c["theta"].values[mine].mean()
        np.testing.assert_allclose(field(fg, "mean_theta", exported), theta, rtol=1e-12)
        # Contacts: lines from a's centroid to b's image nearest to it.
        if c.sizes["contact"] == 0:
            assert t not in contacts_at
            continue
        cg = contacts_at[t]
        lines = read_item(cg.find("Topology/DataItem"), exported)
        ends = read_item(cg.find("Geometry/DataItem"), exported)
        pa, pb = ds["position"].values[c["a"].values], ds["position"].values[c["b"].values]
        pb = np.where(periodic, pb + size * np.round((pa - pb) / size), pb)
        np.testing.assert_array_equal(ends[lines[:, 0]], pa)
        np.testing.assert_allclose(ends[lines[:, 1]], pb, rtol=1e-15)
        assert (np.abs(pb - pa) < size / 2).all()
        np.testing.assert_array_equal(field(cg, "normal_force", exported), c["normal_force"].values)
        np.testing.assert_array_equal(field(cg, "mu", exported), c["mu"].values)
    assert len(counts) > 1, "the floes broke: the steps have different floe counts"


def test_the_sidecar_holds_only_geometry_and_summaries(exported):
    with h5py.File(exported / "run.xdmf.h5", "r") as f:
        names = []
        f.visit(lambda n: names.append(n) if isinstance(f[n], h5py.Dataset) else None)
    assert {n.split("/")[-1] for n in names} == {"vertices", "mean_theta", "mean_mu", "floes",
                                                 "walls", "contact_ends", "lines"}
    assert (exported / "run.xdmf.h5").stat().st_size < (exported / "run.h5").stat().st_size


def test_outputs_are_not_overwritten_without_force(exported, floe_binary):
    out = subprocess.run([str(floe_binary), "export", str(exported / "run.h5"), "--xdmf"],
                         capture_output=True, text=True)
    assert out.returncode == 2 and "already exists" in out.stderr
    out = subprocess.run([str(floe_binary), "export", str(exported / "run.h5"), "--xdmf", "--force"],
                         capture_output=True, text=True)
    assert out.returncode == 0
    out = subprocess.run([str(floe_binary), "export", str(exported / "missing.h5"), "--xdmf"],
                         capture_output=True, text=True)
    assert out.returncode == 2 and "missing.h5" in out.stderr


PVSCRIPT = r"""
import json, sys
from paraview.simple import XDMFReader, UpdatePipeline
from paraview import servermanager as sm
reader = XDMFReader(FileNames=[sys.argv[1]])
reader.UpdatePipelineInformation()
out = []
for t in reader.TimestepValues:
    reader.UpdatePipeline(t)
    data = sm.Fetch(reader)
    blocks = {}
    it = data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        name = it.GetCurrentMetaData().Get(data.NAME())
        block = it.GetCurrentDataObject()
        cells = block.GetCellData()
        speed = cells.GetArray("velocity")
        force = cells.GetArray("normal_force")
        blocks[name] = [block.GetNumberOfCells(),
                        speed.GetRange(-1)[1] if speed is not None else None,
                        force.GetRange(0)[1] if force is not None else None]
        it.GoToNextItem()
    out.append([t, blocks])
print(json.dumps(out))
"""


@pytest.mark.skipif(shutil.which("pvpython") is None, reason="ParaView not installed (make paraview)")
def test_paraview_reads_it(exported, tmp_path):
    script = tmp_path / "read.py"
    script.write_text(PVSCRIPT)
    out = subprocess.run(["pvpython", "--force-offscreen-rendering", str(script),
                          str(exported / "run.xdmf")], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    steps = json.loads(out.stdout.strip().splitlines()[-1])
    run = floe.open_run(exported / "run.h5")
    assert len(steps) == len(run)
    for k, (t, blocks) in enumerate(steps):
        ds, c = run.snapshot(k), run.contacts(k)
        assert t == pytest.approx(float(ds["time"]))
        cells = {name.split(" ")[0]: v for name, v in blocks.items()}
        assert cells["floes"][0] == ds.sizes["floe"]
        assert cells["walls"][0] == int(ds["prescribed"].sum())
        assert cells.get("contacts", [0])[0] == c.sizes["contact"]
        if c.sizes["contact"]:
            assert cells["contacts"][2] == float(c["normal_force"].max())
        assert cells["floes"][1] == pytest.approx(float(ds["speed"].max()), rel=1e-12)


def test_python_export_is_the_command_line_s(exported, tmp_path):
    shutil.copy(exported / "run.h5", tmp_path / "run.h5")
    xdmf = floe.export_xdmf(tmp_path / "run.h5")
    assert xdmf == str(tmp_path / "run.xdmf")
    assert (tmp_path / "run.xdmf").read_text() == (exported / "run.xdmf").read_text()
    with pytest.raises(FileExistsError):
        floe.export_xdmf(tmp_path / "run.h5")
    with pytest.raises(FileNotFoundError):
        floe.export_xdmf(tmp_path / "missing.h5")


def test_python_run_with_xdmf_writes_it_beside_the_file(tmp_path):
    s = floe.Scenario.from_file(ROOT / "scenarios" / "demo.toml").with_values(duration_s=60.0)
    summary = floe.run(s, tmp_path / "r.h5", progress=False, xdmf=True)
    assert summary["xdmf"] == str(tmp_path / "r.xdmf")
    assert (tmp_path / "r.xdmf.h5").exists()
    root = ET.parse(tmp_path / "r.xdmf").getroot()
    assert len(root.find("Domain").findall("Grid")[0].findall("Grid")) == len(floe.open_run(tmp_path / "r.h5"))
