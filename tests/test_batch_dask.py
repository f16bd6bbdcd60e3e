"""``foon.batch`` on a real two-worker ``LocalCluster`` (processes): the same answers as the
local engine, the index opened once per worker, the workers writing the partitions when
they see the output folder (and the client when they do not), and a worker killed in the
middle of a batch costs nothing: every query answered exactly once, no partition left half
written, the results equal a local run's."""

from __future__ import annotations

import hashlib
import json
import os
import signal
import time
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("pyarrow")
distributed = pytest.importorskip("distributed")

import foon
from batch_files import Data, read_parts
from foon import _arrow, _batch, _dask
from foon._dask import FoonPlugin


@pytest.fixture(scope="module")
def data(tmp_path_factory: pytest.TempPathFactory) -> Data:
    return Data(tmp_path_factory.mktemp("batch-dask"), n=1200)


@pytest.fixture(scope="module")
def whole(data: Data) -> Any:
    return _arrow.plan_table(data.foon, data.kitchens, data.table, motions=data.motions)


@pytest.fixture(scope="module")
def client() -> Any:
    cluster = distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    )
    c = distributed.Client(cluster)
    c.wait_for_workers(2, timeout=60)
    yield c
    c.close()
    cluster.close()


def _opens(dask_worker: Any) -> list[tuple[int, bool]]:
    return [(p.opens, p.writes) for p in dask_worker.plugins.values()
            if isinstance(p, FoonPlugin)]  # fmt: skip


def _check_folder(out: Path, partitions: int) -> None:
    """The folder holds the manifest and the partitions, no temporary file; every partition
    has the SHA-256 the manifest records."""
    m = json.loads((out / _batch.MANIFEST).read_text())
    names = [_batch.part_name(k) for k in range(partitions)]
    assert sorted(os.listdir(out)) == [_batch.MANIFEST, *names]
    assert [e["file"] for e in m["partitions"].values()] == names
    for e in m["partitions"].values():
        assert hashlib.sha256((out / e["file"]).read_bytes()).hexdigest() == e["sha256"]


def test_dask_equals_local(data: Data, whole: Any, client: Any, tmp_path: Path) -> None:
    opens: list[dict[str, list[tuple[int, bool]]]] = []

    def progress(done: int, total: int) -> None:
        if not opens:
            opens.append(client.run(_opens))

    s = foon.batch(
        data.csv, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o",
        engine="dask", client=client, chunk_size=100, motions=data.motions, progress=progress,
    )  # fmt: skip
    assert read_parts(tmp_path / "o").equals(whole)
    assert (s.queries, s.partitions, s.planned_partitions, s.engine) == (1200, 12, 12, "dask")
    # Each worker opened the index once, whatever the number of tasks, and writes the
    # partitions itself (it sees the output folder).
    assert sorted(opens[0].values()) == [[(1, True)], [(1, True)]]
    # The plugin is gone once the batch is done, and so is the probe file.
    assert all(v == [] for v in client.run(_opens).values())
    _check_folder(tmp_path / "o", 12)
    # The local engine, resuming the same output, finds nothing to do.
    s = foon.batch(data.csv, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o",
                   chunk_size=100, motions=data.motions)  # fmt: skip
    assert s.planned_partitions == 0 and s.kept_partitions == 12


def test_workers_that_do_not_see_the_folder_send_their_answers(
    data: Data, whole: Any, client: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A probe that the workers do not find (as on machines without the client's folder):
    # the workers send their answers and the client writes the partitions.
    monkeypatch.setattr(_dask, "_make_probe", lambda out, token: ".no-such-probe.tmp")
    opens: list[dict[str, list[tuple[int, bool]]]] = []

    def progress(done: int, total: int) -> None:
        if not opens:
            opens.append(client.run(_opens))

    s = foon.batch(
        data.jsonl, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o",
        engine="dask", client=client, chunk_size=300, motions=data.motions, progress=progress,
    )  # fmt: skip
    assert sorted(opens[0].values()) == [[(1, False)], [(1, False)]]
    assert read_parts(tmp_path / "o").equals(whole)
    assert (s.partitions, s.planned_partitions) == (4, 4)
    _check_folder(tmp_path / "o", 4)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def test_a_killed_worker_loses_no_query(data: Data, whole: Any, client: Any, tmp_path: Path
                                        ) -> None:  # fmt: skip
    pids: dict[str, int] = client.run(os.getpid)
    killed: list[tuple[int, int]] = []
    written: list[int] = []

    def progress(done: int, total: int) -> None:
        written.append(done)
        if done == 100:
            # What a worker killed while writing leaves: a temporary file, removed at the end.
            (tmp_path / "o" / ".part-00059.parquet.dead.tmp").write_bytes(b"PAR1 half")
        if killed or done < 200:
            return
        # Once some but not all partitions are written, kill the worker holding the most of
        # the batch's tasks: running, queued, or finished with answers not yet fetched.
        busy, held = client.processing(), client.has_what()

        def tasks(a: str) -> int:
            keys = [*busy.get(a, ()), *held.get(a, ())]
            return sum(1 for k in keys if str(k).startswith("foon-batch-"))

        addr = max(pids, key=tasks)
        killed.append((pids[addr], tasks(addr)))
        os.kill(pids[addr], signal.SIGKILL)

    s = foon.batch(
        data.parquet, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o",
        engine="dask", client=client, chunk_size=20, motions=data.motions, progress=progress,
    )  # fmt: skip
    assert killed and killed[0][1] >= 1, "the killed worker held some of the batch's tasks"
    deadline = time.monotonic() + 10
    while _alive(killed[0][0]) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _alive(killed[0][0])
    got = read_parts(tmp_path / "o")
    ids = got.column("query_id").to_pylist()
    assert ids == [r["query_id"] for r in data.rows] and len(set(ids)) == len(ids)
    assert got.equals(whole)
    # Each partition written once: one progress call per partition.
    assert len(written) == s.partitions == 60 and written[-1] == 1200
    assert s.planned_partitions == 60
    _check_folder(tmp_path / "o", 60)
    client.wait_for_workers(2, timeout=30)  # the nanny restarts the killed worker
