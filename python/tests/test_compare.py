"""floe.compare: `floe compare` from Python, the same report and run files
as the command line's, its table as a DataFrame."""

from __future__ import annotations

import numpy as np
import pytest

import floe
from conftest import ROOT, assert_same_file, run_cli


@pytest.fixture(scope="module")
def short_demo(tmp_path_factory):
    d = tmp_path_factory.mktemp("compare")
    floe.Scenario.from_file(ROOT / "scenarios" / "demo.toml").with_values(
        duration_s=600.0).write(d / "demo.toml")
    return d / "demo.toml"


def test_compare_is_floe_compare(short_demo, floe_binary, tmp_path):
    laws = ["amontons", "rate-state"]
    df = floe.compare(short_demo, tmp_path / "py", laws, progress=False)
    run_cli(floe_binary, "compare", str(short_demo), "-o", str(tmp_path / "cli"),
            "--laws", ",".join(laws), "--quiet")
    assert list(df.index) == laws
    assert (tmp_path / "py" / "report.md").read_text() == (tmp_path / "cli" / "report.md").read_text()
    for law in laws:
        # Each run names its own scenario file, DIR/<law>.toml.
        assert_same_file(tmp_path / "py" / f"{law}.h5", tmp_path / "cli" / f"{law}.h5",
                         ignore=("parameters@scenario_path",))
        # The table's dissipation is the run's own ledger at the end.
        ledger = floe.open_run(df.loc[law, "file"]).observables["friction_dissipation"]
        assert df.loc[law, "friction_dissipation_j"] == ledger.values[-1]
    assert df.attrs["report"] == str(tmp_path / "py" / "report.md")
    assert "mu = " in df.loc["amontons", "friction"]
    assert df["slip_events"].dtype == np.int64


def test_an_edited_scenario_is_written_beside_the_runs(short_demo, tmp_path):
    s = floe.Scenario.from_file(short_demo).with_values(duration_s=60.0)
    df = floe.compare(s, tmp_path, ["amontons"], progress=False, amontons_mu=0.5)
    assert floe.Scenario.from_file(tmp_path / "scenario.toml").duration_s == 60.0
    assert 'mu = 0.5' in df.loc["amontons", "friction"]
    with pytest.raises(FileExistsError):
        floe.compare(s, tmp_path, ["amontons"], progress=False)


def test_bad_comparisons(short_demo, tmp_path):
    with pytest.raises(ValueError, match="laws"):
        floe.compare(short_demo, tmp_path, ["coulomb"], progress=False)
    with pytest.raises(ValueError, match="laws"):
        floe.compare(short_demo, tmp_path, [], progress=False)
    with pytest.raises(ValueError, match="amontons_mu"):
        floe.compare(short_demo, tmp_path, ["amontons"], amontons_mu=-1.0, progress=False)
    with pytest.raises(ValueError, match="reference_slip_m_per_s"):
        floe.compare(short_demo, tmp_path, reference_slip_m_per_s=0.0, progress=False)
    assert not any(tmp_path.iterdir()), "a refused comparison writes nothing"
    # Refused after the edited scenario was written beside the runs: gone again.
    edited = floe.Scenario.from_file(short_demo).with_values(duration_s=60.0)
    with pytest.raises(ValueError, match="threads"):
        floe.compare(edited, tmp_path / "c", ["amontons"], threads=0, progress=False)
    assert not (tmp_path / "c").exists()
    # An edited scenario read from OUT/scenario.toml is not written over it.
    (tmp_path / "d").mkdir()
    edited.write(tmp_path / "d" / "scenario.toml")
    mine = floe.Scenario.from_file(tmp_path / "d" / "scenario.toml").with_values(seed=7)
    with pytest.raises(ValueError, match="read from"):
        floe.compare(mine, tmp_path / "d", ["amontons"], progress=False, force=True)
    assert floe.Scenario.from_file(tmp_path / "d" / "scenario.toml")["seed"] != 7
