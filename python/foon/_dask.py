"""The ``dask`` engine of :func:`foon.batch`: chunks of queries planned on the workers of a
``distributed`` cluster.

Each worker opens the ``.foonidx`` once, through a worker plugin (:class:`FoonPlugin`,
``foon.load`` of the index path, its fingerprint checked against the client's), and holds
the kitchen set, shipped once per worker as its bytes. A task carries only its chunk of
queries (Arrow IPC bytes). A worker that sees the output folder (the client puts a probe
file with a random name in it before the batch) writes the task's partition there itself,
atomically, and returns only its manifest entry; a worker that does not returns the answers
(Arrow IPC bytes) and the client writes them. The client alone records the partitions in
the manifest, as their tasks complete, with a bounded number of tasks in flight. A worker
that dies takes its running tasks (and results not yet fetched) with it; the scheduler runs
them again elsewhere, a partition written twice is the same bytes renamed over itself, and
the client records each partition once. Needs ``pip install foon[dask]``."""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Callable, Iterable, Iterator
from typing import TYPE_CHECKING, Any

from distributed import WorkerPlugin

if TYPE_CHECKING:
    import pyarrow as pa  # type: ignore[import-untyped]

    from foon import Foon, MotionRates
    from foon._kitchens import KitchenSet

__all__ = ["LOCAL_CLUSTER_CONFIG", "FoonPlugin", "local_cluster", "plan_chunk", "run"]

#: Tasks in flight per worker thread: one planning, one queued behind it so that the
#: worker never waits for the client.
IN_FLIGHT_PER_THREAD = 2

#: How many times a task is retried when it fails (on top of the scheduler's own reruns of
#: the tasks of a worker that died).
RETRIES = 2


#: The Dask settings of the local cluster that the engine starts when it is given neither a
#: client nor a scheduler (:func:`local_cluster`): Dask's statistical profiler of the
#: workers off, and its event-loop tick and system monitor at 500 ms and 5 s instead of
#: 20 ms and 500 ms. An idle two-worker cluster then costs about a third of the CPU time
#: (the workers plan in a native call that shows nothing to a Python profiler).
LOCAL_CLUSTER_CONFIG: dict[str, Any] = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "500ms",
    "distributed.admin.system-monitor.interval": "5s",
}


def local_cluster(n_workers: int | None = None) -> Any:
    """A ``LocalCluster`` of ``n_workers`` (default: one per core) single-threaded worker
    processes, with :data:`LOCAL_CLUSTER_CONFIG`."""
    import dask
    from distributed import LocalCluster

    with dask.config.set(LOCAL_CLUSTER_CONFIG), _workers_ignore_ctrl_c():
        return LocalCluster(  # type: ignore[no-untyped-call]
            n_workers=n_workers or os.cpu_count() or 1,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
        )


@contextlib.contextmanager
def _workers_ignore_ctrl_c() -> Iterator[None]:
    """The worker processes started while in ignore Ctrl-C (they inherit the ignored
    signal): the terminal sends it to the whole process group, and the client alone
    answers it (it closes the cluster, whose workers stop), without a traceback from each
    worker. A Ctrl-C while the cluster starts (a few seconds) is not seen. Only in the main
    thread, where signal handlers are set, and when the handler there can be put back."""
    import signal
    import threading

    old = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or old is None:
        yield
        return
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


def _to_ipc(table: pa.Table) -> bytes:
    import pyarrow as pa

    sink = pa.BufferOutputStream()
    with pa.ipc.new_stream(sink, table.schema) as w:
        w.write_table(table)
    return sink.getvalue().to_pybytes()  # type: ignore[no-any-return]


def _from_ipc(data: bytes) -> pa.Table:
    import pyarrow as pa

    with pa.ipc.open_stream(pa.py_buffer(data)) as r:
        return r.read_all()


class FoonPlugin(WorkerPlugin):
    """Opens the index once per worker (checking its fingerprint) and holds the kitchen set
    and the planning settings for the tasks of one batch, and whether this worker writes
    the partitions (it sees the probe file in the output folder). Pickled to each worker
    with only the paths, the fingerprint and the kitchen set's bytes."""

    def __init__(
        self,
        index_path: str,
        fingerprint: str,
        kitchens: bytes,
        motions: list[tuple[str, float]] | None,
        utensils: list[str],
        default_rate: float | None,
        out: str | None = None,
        probe: str | None = None,
    ) -> None:
        self.index_path = index_path
        self.fingerprint = fingerprint
        self.kitchen_bytes = kitchens
        self.motions = motions
        self.utensils = utensils
        self.default_rate = default_rate
        self.out = out
        self.probe = probe
        self.foon: Foon | None = None
        self.kitchens: KitchenSet | None = None
        #: How many times this worker opened the index (1 after setup).
        self.opens = 0
        #: Whether this worker writes the partitions of its tasks (set by setup).
        self.writes = False

    def __getstate__(self) -> dict[str, Any]:
        state = dict(self.__dict__)
        state["foon"] = None
        state["kitchens"] = None
        state["opens"] = 0
        state["writes"] = False
        return state

    def setup(self, worker: Any) -> None:
        import foon
        from foon._kitchens import KitchenSet

        f = foon.load(self.index_path)
        if f.fingerprint != self.fingerprint:
            raise RuntimeError(
                f"{self.index_path}: on worker {worker.address} the index has fingerprint "
                f"{f.fingerprint}, not the client's {self.fingerprint}"
            )
        self.foon = f
        self.kitchens = KitchenSet.from_bytes(self.kitchen_bytes)
        self.opens += 1
        # The probe's name is random: a folder at the same path on another machine does
        # not have it.
        self.writes = (
            self.out is not None
            and self.probe is not None
            and os.path.isfile(os.path.join(self.out, self.probe))
        )

    def teardown(self, worker: Any) -> None:
        self.foon = None
        self.kitchens = None


def plan_chunk(name: str, k: int, queries: bytes, threads: int) -> tuple[str, Any]:
    """The task: answers chunk ``k`` of the queries (Arrow IPC bytes) with the index and
    kitchens of the worker's plugin ``name``. Returns ``("entry", manifest entry)`` when the
    worker wrote the partition itself, else ``("table", the result table as Arrow IPC
    bytes)``."""
    from distributed import get_worker

    from foon import _arrow, _batch

    worker = get_worker()
    plugin = worker.plugins.get(name)
    if not isinstance(plugin, FoonPlugin) or plugin.foon is None or plugin.kitchens is None:
        raise RuntimeError(f"worker {worker.address} has not opened the batch's index")
    table = _arrow.plan_table(
        plugin.foon,
        plugin.kitchens,
        _from_ipc(queries),
        threads=threads,
        motions=None if plugin.motions is None else dict(plugin.motions),
        utensils=plugin.utensils,
        default_rate=plugin.default_rate,
    )
    if plugin.writes and plugin.out is not None:
        return "entry", _batch.write_partition(plugin.out, k, table)
    return "table", _to_ipc(table)


def _make_probe(out: str, token: str) -> str:
    """Puts an empty file with a random name in ``out`` (a temporary file of the batch's,
    removed by a rerun if left over) and returns its name: the workers that see it write
    their partitions there."""
    from foon._batch import MANIFEST

    name = f".{MANIFEST}.probe-{token}-{secrets.token_hex(8)}.tmp"
    with open(os.path.join(out, name), "wb"):
        pass
    return name


def _worker_threads(client: Any) -> int:
    info = client.scheduler_info()
    return max(1, sum(int(w.get("nthreads", 1)) for w in info.get("workers", {}).values()))


def run(
    chunks: Iterable[tuple[int, pa.Table]],
    record: Callable[[int, dict[str, Any]], None],
    *,
    out: str,
    foon: Foon,
    kitchens: KitchenSet,
    client: Any,
    threads: int | None,
    motions: MotionRates | None,
    utensils: list[str],
    default_rate: float | None,
    token: str,
) -> None:
    """Plans ``chunks`` on the cluster of ``client`` (:func:`connected`) into partitions of
    the folder ``out`` and calls ``record(k, entry)`` once per chunk with its manifest
    entry, as the tasks complete."""
    path = foon.index_path
    if path is None:
        raise ValueError("the dask engine needs a FOON opened from a .foonidx file")
    name = f"foon-batch-{token}"
    probe = _make_probe(out, token)
    try:
        plugin = FoonPlugin(
            os.path.abspath(path),
            foon.fingerprint,
            kitchens.to_bytes(),
            None if motions is None else list(motions.items()),
            list(utensils),
            default_rate,
            os.path.abspath(out),
            probe,
        )
        client.register_plugin(plugin, name=name)
        try:
            _drive(client, chunks, record, out, name, threads or 1)
        finally:
            # A closed or broken client has nothing to undo.
            with contextlib.suppress(Exception):
                client.unregister_worker_plugin(name)
    finally:
        with contextlib.suppress(OSError):
            os.unlink(os.path.join(out, probe))


@contextlib.contextmanager
def connected(client: Any, scheduler: str | None) -> Iterator[Any]:
    """The client a batch runs on: ``client``, else a client of ``scheduler``, else one of a
    local cluster of one single-threaded worker process per core; a client or cluster made
    here is closed on exit."""
    if client is not None:
        yield client
        return
    from distributed import Client

    own: list[Any] = []
    try:
        if scheduler is not None:
            client = Client(scheduler)  # type: ignore[no-untyped-call]
        else:
            cluster = local_cluster()
            own.append(cluster)
            client = Client(cluster)  # type: ignore[no-untyped-call]
        own.insert(0, client)
        yield client
    finally:
        for c in own:
            c.close()


def _drive(
    client: Any,
    chunks: Iterable[tuple[int, pa.Table]],
    record: Callable[[int, dict[str, Any]], None],
    out: str,
    name: str,
    threads: int,
) -> None:
    from distributed import as_completed

    from foon._batch import part_name, write_partition

    limit = max(2, IN_FLIGHT_PER_THREAD * _worker_threads(client))
    source = iter(chunks)
    running: dict[Any, tuple[int, int]] = {}
    ac = as_completed()  # type: ignore[no-untyped-call]

    def submit_next() -> bool:
        try:
            k, table = next(source)
        except StopIteration:
            return False
        fut = client.submit(
            plan_chunk,
            name,
            k,
            _to_ipc(table),
            threads,
            key=f"{name}-{k:05d}",
            pure=False,
            retries=RETRIES,
        )
        running[fut] = (k, table.num_rows)
        ac.add(fut)  # type: ignore[no-untyped-call]
        return True

    try:
        while len(running) < limit and submit_next():
            pass
        for fut in ac:
            k, rows = running.pop(fut)
            try:
                kind, value = fut.result()
            except Exception as e:
                raise RuntimeError(f"partition {k}: the task failed on the cluster: {e}") from e
            fut.release()
            del fut
            if kind == "entry":
                entry = value
                if entry.get("file") != part_name(k) or entry.get("rows") != rows:
                    raise RuntimeError(
                        f"partition {k}: a worker wrote {entry.get('file')} with "
                        f"{entry.get('rows')} rows, not {part_name(k)} with {rows}"
                    )
            else:
                entry = write_partition(out, k, _from_ipc(value))
            record(k, entry)
            while len(running) < limit and submit_next():
                pass
    except BaseException:
        # The tasks not yet started are dropped; a running one may still write its (whole)
        # partition, which the manifest does not list and a rerun plans again.
        for other in running:
            other.cancel()
        raise
