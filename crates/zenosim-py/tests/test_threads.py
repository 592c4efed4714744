"""The GIL is released while simulating, and Ctrl-C interrupts a long run."""

from __future__ import annotations

import textwrap
import threading
import time

import zenosim
from conftest import MODELS, interrupt

# A long run: the ball on the sine surface, rolling for a long while after its Zeno point
# (about 1 s of wall time in an optimised build, several in a debug one).
LONG = dict(t_end=1e5, rtol=1e-12, atol=1e-12)


def test_other_threads_run_while_a_run_simulates():
    model = zenosim.Model.from_file(MODELS / "ball-on-sine.toml")
    count = [0]
    done = threading.Event()

    def counter():
        while not done.is_set():
            count[0] += 1

    thread = threading.Thread(target=counter)
    thread.start()
    try:
        time.sleep(0.05)
        # Read while this thread holds the GIL, just before and just after the run.
        before = count[0]
        start = time.perf_counter()
        zenosim.run(model, t_end=4000.0)
        seconds = time.perf_counter() - start
        during = count[0] - before
        time.sleep(0.05)
        after = count[0] - before - during
    finally:
        done.set()
        thread.join()
    # Held for the whole run, the GIL would let the counter move only in the interpreter's
    # switch interval (5 ms) before the run starts; released, it counts all along, at about
    # the rate it counts in the 50 ms after the run.
    rate_after = after / 0.05
    assert seconds > 0.1, seconds
    assert during > 0.25 * rate_after * seconds, (during, rate_after, seconds)
    assert during > 20 * rate_after * 0.005, (during, rate_after)


SCRIPT = textwrap.dedent(
    """
    import sys, time, zenosim
    model = zenosim.Model.from_file(sys.argv[1])
    print("started", flush=True)
    start = time.perf_counter()
    try:
        zenosim.run(model, t_end=1e5, rtol=1e-12, atol=1e-12)
    except KeyboardInterrupt:
        print(f"interrupted after {time.perf_counter() - start:.3f}", flush=True)
        sys.exit(42)
    print("finished", flush=True)
    """
)


def test_ctrl_c_interrupts_a_long_run():
    code, out, _, latency = interrupt(
        SCRIPT, str(MODELS / "ball-on-sine.toml"), delay=0.3, timeout=30
    )
    assert code == 42, out
    assert out.startswith("interrupted after"), out
    # Polled every 50 ms; the bound is loose (a loaded machine), yet far below the minutes the
    # run would take: the signal, not the end of the run, stopped it.
    assert latency < 10.0, latency


SCRIPT_EVENTS = textwrap.dedent(
    """
    import sys, zenosim
    model = zenosim.Model.from_file(sys.argv[1])
    print("started", flush=True)
    try:
        run = zenosim.run(model, set={"e": 1.0}, t_end=float(sys.argv[2]))
    except KeyboardInterrupt:
        print("interrupted", flush=True)
        sys.exit(42)
    print("finished", run.status, len(run.events), flush=True)
    """
)


def test_ctrl_c_at_any_moment_of_a_run_is_a_keyboard_interrupt():
    # Regression: a Ctrl-C that landed as the run handed over to building its numpy arrays
    # made numpy's first lookup of its C API raise, which the numpy crate turned into a panic
    # (a PanicException, which `except KeyboardInterrupt` misses). An elastic ball (it bounces
    # for ever) with tens of thousands of events: signals at moments spread over the
    # simulation and the conversion of its events must each end in KeyboardInterrupt (or, once
    # done, a finished run), never in anything else.
    for delay in (0.05, 0.2, 0.4, 0.7, 1.0):
        code, out, err, _ = interrupt(
            SCRIPT_EVENTS, str(MODELS / "ball-on-sine.toml"), "1e4", delay=delay, timeout=120
        )
        assert "Panic" not in err and "panicked" not in err, err
        assert code == 42 or out.startswith("finished"), (delay, out, err)
