"""Ctrl-C stops long planning promptly: exit code 130 from the CLI, no traceback, no
partial output file."""

from __future__ import annotations

import json
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

N = 200_000  # chain length: every plan below walks most of it


def chain(path: Path) -> None:
    with path.open("w") as fh:
        for i in range(N):
            fh.write(f"O\titem\nS\ts{i}\nM\tstep\nO\titem\nS\ts{i + 1}\n//\n")


def interrupt_cli(p: subprocess.Popen[str]) -> None:
    """Ctrl-C to a running ``foon`` command: it exits promptly with 130 and a one-line
    message, no traceback."""
    assert p.poll() is None, "the batch finished before it could be interrupted"
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    stopped_after = time.monotonic() - sent
    assert p.returncode == 130, err
    assert "foon: interrupted" in err and "Traceback" not in err
    assert stopped_after < 10, f"took {stopped_after:.1f} s to stop"


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("threads", ["1", "2"])
def test_ctrl_c_stops_a_long_batch(tmp_path: Path, threads: str) -> None:
    f = tmp_path / "chain.foon"
    chain(f)
    k = tmp_path / "kitchen.json"
    k.write_text(
        json.dumps([{"label": "item", "states": ["s0"], "ingredients": [], "container": None}])
    )
    goals = tmp_path / "goals.json"
    goals.write_text(
        json.dumps(
            [
                {"label": "item", "states": [f"s{N - i}"], "ingredients": [], "container": None}
                for i in range(3000)
            ]
        )
    )
    out = tmp_path / "out"
    script = shutil.which("foon") or str(Path(sys.executable).parent / "foon")
    p = subprocess.Popen(
        [
            script,
            "plan",
            "--foon",
            str(f),
            "--kitchen",
            str(k),
            "--goals",
            str(goals),
            "--method",
            "ids",
            "--threads",
            threads,
            "--out",
            str(out),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    time.sleep(2.5)
    interrupt_cli(p)
    assert not out.exists() or list(out.iterdir()) == []


SCRIPT = """
import json, signal, sys, time
import foon

class Stop(Exception):
    pass

def handler(signum, frame):
    raise Stop("stopped by the handler")

signal.signal(signal.SIGINT, handler)
f = foon.load(sys.argv[1])
p = f.planner([foon.Object("item", ("s0",))])
goals = [foon.Object("item", (f"s{N - i}",)) for i in range(3000)]
print("ready", flush=True)
start = time.monotonic()
try:
    p.plan_many(goals, "ids", threads=int(sys.argv[2]))
except Stop as e:
    print("Stop", round(time.monotonic() - start, 1), e, flush=True)
else:
    print("finished", flush=True)
""".replace("N - i", f"{N} - i")


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("threads", ["1", "2"])
def test_the_signal_handlers_exception_ends_a_python_call(tmp_path: Path, threads: str) -> None:
    f = tmp_path / "chain.foon"
    chain(f)
    p = subprocess.Popen(
        [sys.executable, "-c", SCRIPT, str(f), threads],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    assert p.stdout is not None
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.5)
    assert p.poll() is None, "the batch finished before it could be interrupted"
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    stopped_after = time.monotonic() - sent
    # The handler's own exception, not a generic KeyboardInterrupt, and promptly.
    assert out.startswith("Stop") and "stopped by the handler" in out, out + err
    assert "Traceback" not in err
    assert stopped_after < 10, f"took {stopped_after:.1f} s to stop"


LOAD_SCRIPT = """
import signal, sys, time
import foon

call = foon.load if sys.argv[2] == "load" else foon.check
start = time.monotonic()
call(sys.argv[1])
full = time.monotonic() - start
print("ready", full, flush=True)
try:
    call(sys.argv[1])
except KeyboardInterrupt:
    print("interrupted", time.monotonic(), flush=True)
else:
    print("finished", time.monotonic(), flush=True)
"""


@pytest.fixture(scope="module")
def big_foon(tmp_path_factory: pytest.TempPathFactory) -> Path:
    f = tmp_path_factory.mktemp("big") / "big.foon"
    with f.open("w") as fh:
        for i in range(1_000_000):
            fh.write(f"O\titem\nS\ts{i}\nM\tstep\nO\titem\nS\ts{i + 1}\n//\n")
    return f


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("call", ["load", "check"])
def test_ctrl_c_stops_a_long_load_or_check(big_foon: Path, call: str) -> None:
    """The loader and the linter ask for interruption as they go: Ctrl-C early in a load (or
    a check) stops it long before it would have ended (measured against a full run on the
    same file in the same process, so the bound holds on a slow machine too)."""
    p = subprocess.Popen(
        [sys.executable, "-c", LOAD_SCRIPT, str(big_foon), call],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    assert p.stdout is not None
    word, full = p.stdout.readline().split()
    assert word == "ready"
    time.sleep(min(0.1 * float(full), 0.5))
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=120)
    word, when = out.split()
    assert word == "interrupted", out + err
    assert float(when) - sent < 0.5 * float(full), (float(when) - sent, full)


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("threads", ["1", "2"])
def test_ctrl_c_stops_foon_batch_with_whole_partitions(tmp_path: Path, threads: str) -> None:
    """The local engine plans several chunks at once on more than one thread: Ctrl-C stops
    them all promptly, and the output holds only whole partitions, each in the manifest."""
    pytest.importorskip("pyarrow")
    f = tmp_path / "chain.foon"
    chain(f)
    kitchens = tmp_path / "kitchens.json"
    item = {"label": "item", "states": ["s0"], "ingredients": [], "container": None}
    kitchens.write_text(json.dumps({"k": [item]}))
    queries = tmp_path / "queries.jsonl"
    with queries.open("w") as fh:
        for i in range(6000):
            goal = {"label": "item", "states": [f"s{N - i % 3000}"], "ingredients": [],
                    "container": None}  # fmt: skip
            fh.write(json.dumps({"query_id": i, "kitchen_id": "k", "goal": goal,
                                 "method": "ids"}) + "\n")  # fmt: skip
    out = tmp_path / "out"
    script = shutil.which("foon") or str(Path(sys.executable).parent / "foon")
    p = subprocess.Popen(
        [script, "batch", str(queries), "--foon", str(f), "--kitchens", str(kitchens),
         "-o", str(out), "--chunk-size", "100", "--threads", threads],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    from foon._batch import MANIFEST

    # Interrupted once the first partition is recorded (whatever the build's speed).
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and p.poll() is None:
        m = out / MANIFEST
        if m.exists() and json.loads(m.read_text() or "{}").get("partitions"):
            break
        time.sleep(0.05)
    interrupt_cli(p)
    import pyarrow.parquet as pq  # type: ignore[import-untyped]

    manifest = json.loads((out / MANIFEST).read_text())
    parts = sorted(x.name for x in out.iterdir() if x.name != MANIFEST)
    assert parts == [f"part-{k}.parquet" for k in manifest["partitions"]]
    assert 0 < len(parts) < 60, parts
    for name in parts:
        assert pq.read_table(out / name).num_rows == 100
