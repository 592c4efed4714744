"""What zenosim's Python package adds to a run: zenosim.run and zenosim.sweep against the Rust
run of the same model file, timed in one process by `zenosim bench` (no output written).

    python bench/python_overhead.py [MODEL] [ZENOSIM_BINARY]

Build both optimised first: `cargo build --release -p zenosim-cli` and
`pip install ./crates/zenosim-py` (or `maturin develop --release -m crates/zenosim-py/Cargo.toml`).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time

import numpy as np

import zenosim


def median_time(call, min_time: float = 1.0) -> float:
    """The median wall time of `call()`, repeated for at least `min_time` seconds."""
    times = []
    start = time.perf_counter()
    while time.perf_counter() - start < min_time or len(times) < 5:
        t = time.perf_counter()
        call()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main() -> None:
    path = sys.argv[1] if len(sys.argv) > 1 else "models/ball-on-sine.toml"
    binary = sys.argv[2] if len(sys.argv) > 2 else "target/release/zenosim"
    report = json.loads(
        subprocess.run(
            [binary, "bench", path, "--min-time", "2"], capture_output=True, text=True, check=True
        ).stdout
    )
    rust = report["runs"][0]["wall_time_s"]["median"]
    load = report["load_time_s"]["median"]

    model = zenosim.Model.from_file(path)
    run = zenosim.run(model)
    rows = len(run.t)
    by_model = median_time(lambda: zenosim.run(model))
    by_path = median_time(lambda: zenosim.run(path))
    sampled = median_time(lambda: zenosim.run(model, dt=0.01))
    name = next(iter(model.parameters))
    points = 20_000
    values = {name: np.full(points, model.parameters[name])}
    start = time.perf_counter()
    table = zenosim.sweep(model, values)
    sweep = time.perf_counter() - start
    assert set(table["status"]) == {run.status}

    us = 1e6
    print(f"model {path}: {rows} rows, {len(run.events)} events, status {run.status}")
    print(f"  Rust run (zenosim bench, no samples)      {rust * us:9.1f} µs")
    print(f"  Rust load (read, parse, compile the file) {load * us:9.1f} µs")
    print(f"  zenosim.run(model)                        {by_model * us:9.1f} µs  "
          f"({by_model / rust:.2f}× the Rust run)")
    print(f"  zenosim.run(path)                         {by_path * us:9.1f} µs  "
          f"({by_path / (rust + load):.2f}× the Rust load + run)")
    print(f"  zenosim.run(model, dt=0.01)               {sampled * us:9.1f} µs")
    print(f"  zenosim.sweep, {points} points            {sweep / points * us:9.1f} µs a run, "
          f"{points / sweep:,.0f} runs/s on all cores")


if __name__ == "__main__":
    main()
