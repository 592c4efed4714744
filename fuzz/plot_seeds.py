#!/usr/bin/env python3
"""Writes the seeds of the plot fuzz target (fuzz/seeds/plot/): output folders of shipped
models, each run by `zenosim run` and cut to fit in SEED_LEN bytes, as
`summary.json NUL trajectory.csv [NUL options]` (fuzz/checks/plot.rs).

    cargo build --release && python3 fuzz/plot_seeds.py target/release/zenosim

A folder is cut at a row of its trajectory: the rows up to it, the events and intervals up to
its time, the first Zeno point and those up to its time, and `trajectory.rows` set to match,
so that the seed still draws. summary.json is written compactly (the plots read it whatever its layout).
"""

import json
import pathlib
import subprocess
import sys
import tempfile

FUZZ = pathlib.Path(__file__).resolve().parent
ROOT = FUZZ.parent
OUT = FUZZ / "seeds" / "plot"
# Under the plot target's -max_len (16384), with room for the fuzzer to grow them.
SEED_LEN = 8192

# (seed name, model, extra arguments of `zenosim run`, the seed's options)
RUNS = [
    ("bouncing-ball", "bouncing-ball", [], ""),
    ("ball-on-sine", "ball-on-sine", [], ""),
    ("ball-on-sine-zeno-off", "ball-on-sine", ["--zeno", "off"], ""),
    ("ball-on-sine-png", "ball-on-sine", [], "png x2,x3"),
    ("dragged-ball", "dragged-ball", [], ""),
    ("floor-and-wall", "floor-and-wall", [], "x_dot,y"),
    ("newtons-cradle", "newtons-cradle", [], ""),
    ("corner", "corner", [], ""),
    ("vibrating-table", "vibrating-table", [], "png"),
    # Friction: the tangential forces' columns, stick and slip in the modes and the events,
    # impacts' tangential impulses, the friction plot.
    ("belt-stick-slip", "belt-stick-slip", [], ""),
    ("housner-block", "housner-block", [], "png"),
    ("ball-backspin", "ball-backspin", [], "x,y"),
]


def seed(folder, options):
    """The smallest cut of the run in `folder` that fits, as a seed."""
    summary = json.loads((folder / "summary.json").read_text())
    lines = (folder / "trajectory.csv").read_text().splitlines(keepends=True)
    header, rows = lines[0], lines[1:]
    keep = len(rows)
    while True:
        t_cut = float(rows[keep - 1].split(",", 1)[0])
        cut = dict(summary)
        cut["events"] = [e for e in summary["events"] if e["t"] <= t_cut]
        cut["zeno"] = summary["zeno"][:1] + [
            z for z in summary["zeno"][1:] if z["t_switch"] <= t_cut
        ]
        cut["intervals"] = [i for i in summary["intervals"] if i["start"] <= t_cut]
        cut["trajectory"] = dict(summary["trajectory"], rows=keep)
        text = json.dumps(cut, separators=(",", ":")).encode()
        data = text + b"\0" + (header + "".join(rows[:keep])).encode()
        if options:
            data += b"\0" + options.encode()
        if len(data) <= SEED_LEN:
            return data, keep, len(rows)
        assert keep > 1, f"{folder.name} does not fit in {SEED_LEN} bytes"
        keep = max(1, keep * 9 // 10)


def main():
    zenosim = pathlib.Path(sys.argv[1]).resolve()
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        for name, model, extra, options in RUNS:
            folder = pathlib.Path(scratch) / name
            subprocess.run(
                [zenosim, "run", ROOT / "models" / f"{model}.toml", "--out", folder, *extra],
                check=False,
                stdout=subprocess.DEVNULL,
            )
            data, kept, rows = seed(folder, options)
            (OUT / name).write_bytes(data)
            print(f"plot/{name}: {len(data)} bytes, {kept} of {rows} rows")


if __name__ == "__main__":
    main()
