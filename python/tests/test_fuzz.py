"""A seeded fuzz test of the Python API's inputs: random keys and values
for scenarios, mutated scenario texts, wrong types for every argument,
garbage and truncated run files. Every call returns or raises one of the
exceptions floe documents; none crashes the interpreter, panics or hangs."""

from __future__ import annotations

import contextlib
import math
import random
import shutil
import signal

import h5py
import pytest

import floe
from conftest import ROOT, run_cli

SEED = 20261129
ALLOWED = (floe.FloeError, ValueError, TypeError, KeyError, IndexError, OSError, OverflowError)
DEMO = ROOT / "scenarios" / "demo.toml"
KEYS = [
    "duration_s", "dt_s", "seed", "threads", "domain.size_m", "domain.periodic",
    "tessellation.kind", "tessellation.side_m", "ice.thickness_m", "friction.law",
    "friction.mu", "friction.a", "contact.youngs_modulus_pa", "wind.shear",
    "wall[0].side", "wall[1].velocity_m_per_s", "wall[7].side", "output.snapshot_every_s",
    "fracture.criterion", "ridging.rubble", "no_such_table.key", "friction", "wall", "",
    "a..b", "wall[x].side", "domain.size_m.x",
]


def values(rng: random.Random):
    return rng.choice([
        None, True, 0, -1, 7, 2**62, 2**80, 0.0, -0.0, 1e-300, 1e300, math.nan, math.inf,
        -math.inf, 3.5, "", "amontons", "rate-state", "x" * 300, "\u00e9\u0000",
        [1.0, 2.0], [1, "a"], [], [[1.0, 2.0]], {"a": 1}, {1: 2}, {}, object(), b"bytes",
        (1.0, 2.0), rng.uniform(-1e6, 1e6), rng.randint(-10**6, 10**6),
    ])


def test_scenario_edits(tmp_path):
    rng = random.Random(SEED)
    base = floe.Scenario.from_file(DEMO)
    outcomes = {"ok": 0, "refused": 0}
    for _ in range(400):
        s = base.with_values()
        key = rng.choice(KEYS)
        try:
            if rng.random() < 0.5:
                s[key] = values(rng)
            else:
                s.update({key: values(rng), rng.choice(KEYS): values(rng)})
            outcomes["ok"] += 1
            assert s.duration_s > 0
        except ALLOWED:
            outcomes["refused"] += 1
        try:
            s[key]
        except ALLOWED:
            pass
    assert outcomes["ok"] > 0 and outcomes["refused"] > 100, outcomes


def test_mutated_scenario_texts():
    rng = random.Random(SEED + 1)
    text = DEMO.read_text()
    for _ in range(300):
        chars = list(text)
        for _ in range(rng.randint(1, 5)):
            i = rng.randrange(len(chars))
            op = rng.random()
            if op < 0.4:
                chars[i] = rng.choice('=[]{}"#.,0123456789-e \n\t\\xX')
            elif op < 0.7:
                del chars[i]
            else:
                chars.insert(i, rng.choice("[]=\"'0.1e5\n"))
        try:
            floe.Scenario.from_text("".join(chars))
        except floe.ScenarioError as e:
            assert e.file == "<string>"
        except ALLOWED:
            pass


def test_wrong_types_for_every_argument(tmp_path):
    rng = random.Random(SEED + 2)
    s = floe.Scenario.from_file(DEMO).with_values(duration_s=5.0)
    calls = [
        lambda v: floe.Scenario.from_file(v),
        lambda v: floe.Scenario.from_text(v),
        lambda v: floe.Scenario.from_text("duration_s = 1.0", v),
        lambda v: floe.run(v, tmp_path / "x.h5", progress=False),
        lambda v: floe.run(s, v, progress=False, force=True),
        lambda v: floe.run(s, tmp_path / "y.h5", threads=v, progress=False, force=True),
        lambda v: floe.run(s, tmp_path / "z.h5", max_steps=v, progress=False, force=True),
        lambda v: floe.resume(v, progress=False),
        lambda v: floe.open_run(v),
        lambda v: floe.grid(v, 100.0),
        lambda v: floe.grid(tmp_path / "y.h5", v),
        lambda v: floe.compare(s, tmp_path / "c", v, progress=False, force=True),
        lambda v: s.with_values(v),
    ]
    for _ in range(250):
        call = rng.choice(calls)
        try:
            call(values(rng))
        except ALLOWED:
            pass


class Hang(BaseException):
    """A call that took longer than it may (not an exception floe raises)."""


@contextlib.contextmanager
def at_most(seconds: int):
    def hang(*_):
        raise Hang(f"no answer within {seconds} s")

    old = signal.signal(signal.SIGALRM, hang)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def test_garbage_and_truncated_run_files(tmp_path, floe_binary):
    rng = random.Random(SEED + 3)
    good = tmp_path / "good.h5"
    run_cli(floe_binary, "run", str(ROOT / "tests/data/run_fracture.toml"), "-o", str(good), "-q")
    size = good.stat().st_size
    # A contact naming a floe past the snapshot's: refused, not a panic.
    pair = tmp_path / "pair.h5"
    shutil.copy(good, pair)
    with h5py.File(pair, "r+") as f:
        start = int(f["contacts/start"][-1])
        f["contacts/pair"][start, 1] = 60000
    with pytest.raises(floe.RunFileError, match="past its"):
        floe.export_xdmf(pair, tmp_path / "pair.xdmf")
    for i in range(8):
        bad = tmp_path / f"bad{i}.h5"
        if i < 4:
            bad.write_bytes(bytes(rng.randrange(256) for _ in range(rng.randint(0, 4096))))
        else:
            shutil.copy(good, bad)
            with open(bad, "r+b") as f:
                if i % 2:
                    f.truncate(rng.randrange(size))
                else:
                    f.seek(rng.randrange(size))
                    f.write(bytes(rng.randrange(256) for _ in range(64)))
        with at_most(60):
            try:
                run = floe.open_run(bad)
                for k in (0, -1):
                    run.snapshot(k)
                    run.contacts(k)
                run.observables
                run.fractures()
            except ALLOWED:
                pass
            for call in (lambda: floe.export_xdmf(bad, tmp_path / f"bad{i}.xdmf", force=True),
                         lambda: floe.grid(bad, 2000.0)):
                try:
                    call()
                except ALLOWED:
                    pass
        assert not list(tmp_path.glob("*.part")), "a failed export leaves no half file"
