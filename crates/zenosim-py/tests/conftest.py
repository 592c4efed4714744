"""Shared fixtures: the repository's models and the `zenosim` command built beside the package."""

from __future__ import annotations

import csv
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
MODELS = ROOT / "models"
FAULTS = ROOT / "crates" / "zenosim-cli" / "tests" / "corpus" / "faults"


def target_dir() -> Path:
    return Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `zenosim` binary of the same sources, built (a no-op after `cargo test`) if needed."""
    binary = os.environ.get("ZENOSIM_BIN")
    if binary:
        return Path(binary)
    subprocess.run(
        ["cargo", "build", "--quiet", "--locked", "-p", "zenosim-cli"],
        cwd=ROOT,
        check=True,
    )
    return target_dir() / "debug" / "zenosim"


class CliRun:
    """What `zenosim run` wrote: trajectory.csv as columns, summary.json as a dict."""

    def __init__(self, out: Path, code: int):
        self.code = code
        self.summary = json.loads((out / "summary.json").read_text())
        with open(out / "trajectory.csv", newline="") as f:
            rows = list(csv.reader(f))
        self.header = rows[0]
        self.columns = {name: [row[i] for row in rows[1:]] for i, name in enumerate(self.header)}

    def numbers(self, names) -> np.ndarray:
        """The columns `names` as a rows × len(names) array, read exactly."""
        return np.array([[float(x) for x in self.columns[n]] for n in names]).T.reshape(
            -1, len(names)
        )


@pytest.fixture
def cli_run(cli, tmp_path):
    """`zenosim run MODEL ARGS... --out DIR`, read back."""

    def run(model, *args: str, expect=(0, 1, 3)) -> CliRun:
        out = tmp_path / f"out{len(list(tmp_path.iterdir()))}"
        done = subprocess.run(
            [str(cli), "run", str(model), "--out", str(out), *args],
            capture_output=True,
            text=True,
        )
        assert done.returncode in expect, done.stderr
        return CliRun(out, done.returncode)

    return run


def interrupt(script: str, *args: str, delay: float, timeout: float = 60.0):
    """Runs `script` (which prints "started" before its long call) in a new Python with `args`,
    sends SIGINT `delay` seconds after it started, and returns its exit status, its stdout,
    its stderr and how long it took to end after the signal."""
    import signal
    import sys
    import time

    process = subprocess.Popen(
        [sys.executable, "-c", script, *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert process.stdout.readline() == "started\n"
        time.sleep(delay)
        sent = time.perf_counter()
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=timeout)
        latency = time.perf_counter() - sent
    finally:
        process.kill()
    return process.returncode, out, err, latency
