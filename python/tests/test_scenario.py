"""floe.Scenario: reading, keys as Python values, edits checked by the
scenario reader with errors located as `floe run` locates them."""

from __future__ import annotations

import copy

import pytest

import floe
from conftest import ROOT

DEMO = ROOT / "scenarios" / "demo.toml"


def test_reads_a_file_and_its_keys():
    s = floe.Scenario.from_file(DEMO)
    assert s.title.startswith("demo")
    assert s.duration_s == 1800.0
    assert s["friction.law"] == "rate-state"
    assert s["wall[1].side"] == "top"
    assert isinstance(s["domain"], dict)
    assert "friction.law" in s and "friction.mu" not in s
    with pytest.raises(KeyError):
        s["friction.mu"]


def test_time_step_is_the_run_s():
    # The demo's automatic step: half the stable limit of its stiffest floe
    # (the run's own report says 0.759 s).
    assert floe.Scenario.from_file(DEMO).dt_s == pytest.approx(0.759, abs=5e-4)


def test_edits_keep_the_file_s_layout_and_are_checked():
    s = floe.Scenario.from_file(DEMO)
    s["duration_s"] = 600.0
    assert s.duration_s == 600.0
    s["domain.size_m"] = [20000, 20000.0]
    assert s["domain.size_m"] == [20000, 20000.0]
    # Setting one of the wind's forms where the file has another is refused.
    with pytest.raises(floe.ScenarioError) as e:
        s["wind.velocity_m_per_s"] = [5.0, 0.0]
    assert e.value.key == "wind"
    # Comments stay with the text.
    assert s.text.count("#") == DEMO.read_text().count("#")


def test_a_bad_value_is_located_and_leaves_the_scenario_as_it_was():
    s = floe.Scenario.from_file(DEMO)
    before = s.text
    with pytest.raises(floe.ScenarioError) as e:
        s["duration_s"] = -5.0
    err = e.value
    assert err.key == "duration_s"
    assert err.file == str(DEMO)
    lines = s.text.splitlines()
    assert lines[err.line - 1].startswith("duration_s")
    assert err.column >= 1
    assert str(err).startswith(f"{DEMO}:{err.line}:{err.column}: `duration_s`")
    assert s.text == before
    # A ScenarioError is a ValueError, and a floe.FloeError.
    assert isinstance(err, ValueError) and isinstance(err, floe.FloeError)


def test_unknown_keys_are_refused_naming_the_key():
    s = floe.Scenario.from_file(DEMO)
    with pytest.raises(floe.ScenarioError) as e:
        s["friction.bogus"] = 1.0
    assert e.value.key == "friction.bogus"
    assert "unknown key" in e.value.reason


def test_update_checks_keys_that_are_only_valid_together():
    s = floe.Scenario.from_file(DEMO)
    # Amontons takes `mu`, which rate-and-state refuses: one at a time fails.
    with pytest.raises(floe.ScenarioError):
        s["friction.mu"] = 0.4
    s.update({"friction.law": "amontons", "friction.mu": 0.4})
    assert s["friction"] == {"law": "amontons", "mu": 0.4}
    v = s.with_values(duration_s=60.0)
    assert v.duration_s == 60.0 and s.duration_s == 1800.0


def test_keys_inside_inline_tables_can_be_set():
    s = floe.Scenario.from_file(DEMO)
    s["wind.shear.y_min_m"] = 500.0
    assert s["wind.shear"]["y_min_m"] == 500.0
    assert s["wind.shear"]["velocity_at_y_max_m_per_s"] == [15.0, -2.0]
    with pytest.raises(floe.ScenarioError):
        s["wind.shear.no_such_key"] = 1.0


def test_types_toml_cannot_hold_are_type_errors():
    s = floe.Scenario.from_file(DEMO)
    with pytest.raises(TypeError):
        s["duration_s"] = object()
    with pytest.raises(TypeError):
        s.update([("duration_s", 1.0)])
    with pytest.raises(KeyError):
        s["a..b"] = 1


def test_missing_and_bad_files():
    with pytest.raises(FileNotFoundError):
        floe.Scenario.from_file(ROOT / "no-such-file.toml")
    with pytest.raises(floe.ScenarioError) as e:
        floe.Scenario.from_text('duration_s = 10.0\n[domain]\nsize_m = "big"\n')
    assert (e.value.line, e.value.column, e.value.key) == (3, 10, "size_m")
    assert e.value.file == "<string>"


def test_copies_are_independent():
    s = floe.Scenario.from_file(DEMO)
    c = copy.deepcopy(s)
    c["duration_s"] = 10.0
    assert s.duration_s == 1800.0
