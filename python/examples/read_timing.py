"""How fast floe.open_run reads a large run, against h5py reading the same
datasets (docs/python.md, "Performance"): the demo scenario on a 400 km x
200 km domain (about 145,000 floes), three snapshots, then best of 5.

    .venv/bin/python python/examples/read_timing.py OUT_DIR
"""

import sys
import time
from pathlib import Path

import h5py

import floe

ROOT = Path(__file__).resolve().parents[2]


def best(f, n=5):
    times = []
    for _ in range(n):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    path = out / "big.h5"
    if not path.exists():
        s = floe.Scenario.from_file(ROOT / "scenarios" / "demo.toml")
        s.update({"domain.size_m": [400000.0, 200000.0], "duration_s": 60.0,
                  "output.snapshot_every_s": 20.0})
        floe.run(s, path)
    run = floe.open_run(path)
    ds = run.snapshot(-1)
    c = run.contacts(-1)
    print(f"{ds.sizes['floe']} floes, {ds.sizes['vertex']} vertices, {c.sizes['contact']} contacts")

    def raw_floes():
        with h5py.File(path, "r") as f:
            g = f["particles/floes"]
            for k in ["position", "velocity", "angle", "angular_velocity"]:
                g[k + "/value"][-1]
            for k in ["id", "vertex_offsets", "vertices", "thickness", "mass", "area",
                      "inertia", "prescribed"]:
                g[k][()]

    def raw_contacts():
        with h5py.File(path, "r") as f:
            s, n = f["contacts/start"][-1], f["contacts/count"][-1]
            for k in ["pair", "theta", "mu", "normal_force", "tangential_force", "slip_rate",
                      "overlap_area", "point", "normal"]:
                f["contacts"][k][s:s + n]

    a, b = best(lambda: run.snapshot(-1)), best(raw_floes)
    print(f"snapshot: floe {a:.3f} s, h5py {b:.3f} s, ratio {a / b:.2f}")
    a, b = best(lambda: run.contacts(-1)), best(raw_contacts)
    print(f"contacts: floe {a:.3f} s, h5py {b:.3f} s, ratio {a / b:.2f}")
    print(f"len and times: {best(lambda: (len(run), run.times)) * 1e3:.2f} ms")


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "out/read_timing"))
