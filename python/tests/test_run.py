"""floe.run and floe.resume: in this process, the same file as `floe run`
to the bit; paused and resumed, or interrupted by Ctrl-C and resumed, the
same file as one uninterrupted run."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import floe
from conftest import ROOT, assert_same_file, run_cli

DEMO = ROOT / "scenarios" / "demo.toml"
FRACTURE = ROOT / "tests" / "data" / "run_fracture.toml"


def short_demo(tmp_path: Path, duration_s: float = 300.0) -> Path:
    s = floe.Scenario.from_file(DEMO).with_values(duration_s=duration_s)
    path = tmp_path / "demo_short.toml"
    s.write(path)
    return path


def test_python_run_is_the_command_line_s_file(tmp_path, floe_binary):
    scenario = short_demo(tmp_path)
    run_cli(floe_binary, "run", str(scenario), "-o", str(tmp_path / "cli.h5"), "--quiet")
    summary = floe.run(floe.Scenario.from_file(scenario), tmp_path / "py.h5", progress=False)
    assert summary["status"] == "completed"
    assert summary["final_step"] == summary["total_steps"] == 395
    assert_same_file(tmp_path / "cli.h5", tmp_path / "py.h5")


def test_fracture_and_cohesion_run_is_the_command_line_s_file(tmp_path, floe_binary):
    # Floes break, bond and change between snapshots: the segments, the
    # fracture log and the checkpoints are bitwise the CLI's too.
    floe.Scenario.from_file(FRACTURE).write(tmp_path / "fracture.toml")
    s = floe.Scenario.from_file(tmp_path / "fracture.toml")
    run_cli(floe_binary, "run", str(tmp_path / "fracture.toml"), "-o", str(tmp_path / "cli.h5"),
            "--quiet", "--threads", "2")
    floe.run(s, tmp_path / "py.h5", progress=False, threads=1)
    assert_same_file(tmp_path / "cli.h5", tmp_path / "py.h5")
    assert len(floe.open_run(tmp_path / "py.h5").fractures()["step"]) > 0


def test_paused_and_resumed_is_one_run(tmp_path):
    s = floe.Scenario.from_file(short_demo(tmp_path))
    floe.run(s, tmp_path / "whole.h5", progress=False)
    paused = floe.run(s, tmp_path / "parts.h5", progress=False, max_steps=137)
    assert paused["status"] == "paused" and paused["final_step"] == 137
    assert floe.open_run(tmp_path / "parts.h5").status == "paused at step 137"
    done = floe.resume(tmp_path / "parts.h5", progress=False, threads=1)
    assert done["status"] == "completed"
    assert_same_file(tmp_path / "whole.h5", tmp_path / "parts.h5", checkpoints=False)


def test_ctrl_c_stops_with_a_checkpoint_and_resumes_to_the_same_file(tmp_path):
    s = floe.Scenario.from_file(short_demo(tmp_path, duration_s=6000.0))
    floe.run(s, tmp_path / "whole.h5", progress=False)
    # A process that runs the scenario and sends itself SIGINT 0.3 s in.
    script = textwrap.dedent(
        f"""
        import os, signal, threading, floe
        s = floe.Scenario.from_file({str(tmp_path / "demo_short.toml")!r})
        threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
        try:
            floe.run(s, {str(tmp_path / "cut.h5")!r}, progress=False)
            print("completed")
        except KeyboardInterrupt as e:
            print("interrupted:", e)
        """
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=300, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("interrupted: interrupted at step"), out.stdout
    run = floe.open_run(tmp_path / "cut.h5")
    assert run.status.startswith("interrupted at step")
    step = int(run.status.split()[-1])
    assert 0 < step < 7905
    assert run.parameters.attrs["checkpoint_step"] == step
    floe.resume(tmp_path / "cut.h5", progress=False)
    assert_same_file(tmp_path / "whole.h5", tmp_path / "cut.h5", checkpoints=False)


def test_run_errors(tmp_path):
    s = floe.Scenario.from_file(short_demo(tmp_path, duration_s=10.0))
    floe.run(s, tmp_path / "a.h5", progress=False, force=True)
    with pytest.raises(FileExistsError, match="force=True"):
        floe.run(s, tmp_path / "a.h5", progress=False)
    floe.run(s, tmp_path / "a.h5", progress=False, force=True)
    with pytest.raises(FileNotFoundError):
        floe.run(tmp_path / "missing.toml", tmp_path / "b.h5")
    with pytest.raises(FileNotFoundError):
        floe.resume(tmp_path / "missing.h5")
    (tmp_path / "text.h5").write_text("not a run file")
    with pytest.raises(floe.RunFileError):
        floe.resume(tmp_path / "text.h5", progress=False)
    with pytest.raises(ValueError, match="max_steps"):
        floe.run(s, tmp_path / "a.h5", progress=False, max_steps=0, force=True)
    with pytest.raises(ValueError, match="max_steps"):
        floe.resume(tmp_path / "a.h5", progress=False, max_steps=0)
    with pytest.raises(ValueError, match="threads"):
        floe.run(s, tmp_path / "a.h5", progress=False, threads=0, force=True)
    with pytest.raises(TypeError):
        floe.run(s, tmp_path / "c.h5", threads="two")
    # Running onto the scenario file itself is refused, with or without force.
    with pytest.raises(ValueError, match="overwrite the scenario file"):
        floe.run(tmp_path / "demo_short.toml", tmp_path / "demo_short.toml", force=True)


def test_progress_goes_to_standard_error(tmp_path, capfd):
    s = floe.Scenario.from_file(short_demo(tmp_path, duration_s=30.0))
    floe.run(s, tmp_path / "p.h5")
    err = capfd.readouterr().err
    assert "dt: 0.759 s" in err
