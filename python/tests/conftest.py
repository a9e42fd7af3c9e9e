"""Shared fixtures: the repository, the `floe` binary (built by `make
test` before pytest runs; built here if missing), small scenarios."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
FLOE = ROOT / "target" / "release" / "floe"


@pytest.fixture(scope="session")
def floe_binary() -> Path:
    if not FLOE.exists():
        subprocess.run(["cargo", "build", "--release", "-p", "floe-cli"], cwd=ROOT, check=True)
    return FLOE


def run_cli(binary: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(binary), *args], capture_output=True, text=True, check=True, cwd=ROOT
    )


# Attributes that say who ran a file, how and with which build, not what
# it holds.
PROVENANCE_ATTRIBUTES = {"command_line", "author", "threads", "git_commit"}


def _bytes(value) -> bytes:
    a = np.asarray(value)
    # Strings (variable-length ones come back as Python objects) by value.
    return repr(a.tolist()).encode() if a.dtype.kind in "OSU" else a.tobytes()


def file_contents(path: os.PathLike, checkpoints: bool = True) -> dict:
    """Every dataset's bytes and every attribute of an HDF5 file, by path,
    without the provenance attributes; without the checkpoint slots (but
    with the valid checkpoint's payload) if not ``checkpoints``."""
    out: dict = {}

    def visit(name: str, obj) -> None:
        if not checkpoints and name.startswith("checkpoint"):
            return
        for key, value in obj.attrs.items():
            if key not in PROVENANCE_ATTRIBUTES:
                out[f"{name}@{key}"] = _bytes(value)
        if isinstance(obj, h5py.Dataset):
            out[name] = _bytes(obj[()])

    with h5py.File(path, "r") as f:
        visit("/", f)
        f.visititems(visit)
        if not checkpoints:
            slot = f["checkpoint"].attrs["valid_slot"]
            out["valid checkpoint"] = _bytes(f[f"checkpoint/slot{slot}"][()])
    return out


def assert_same_file(
    a: os.PathLike, b: os.PathLike, checkpoints: bool = True, ignore: tuple = ()
) -> None:
    """The two files hold the same bits (a resumed file's checkpoints sit in
    other slots than an uninterrupted run's: ``checkpoints=False`` compares
    only the valid one's payload), but for the items in ``ignore``."""
    ca, cb = file_contents(a, checkpoints), file_contents(b, checkpoints)
    for item in ignore:
        ca.pop(item), cb.pop(item)
    assert sorted(ca) == sorted(cb)
    differ = [k for k in ca if ca[k] != cb[k]]
    assert not differ, f"{len(differ)} items differ, e.g. {differ[:8]}"
