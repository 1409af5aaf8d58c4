"""Running a study: every point a dask task, rows written as they finish.

:func:`run_study` skips the points that already have a row in ``<out>/points``
(failed ones too, unless ``retry_failed``), sends the others to the workers as
JSON scene documents, writes each row the moment its point finishes
(:func:`~efgkit.study.table.write_row`), and at the end writes the table (CSV and
Parquet) and the figures. Where it runs (``scheduler``):

================  ================================================================
``"local"``       a :class:`distributed.LocalCluster` of ``workers`` processes (default:
                  one per core) with one thread each, and ``OMP_NUM_THREADS``,
                  ``OPENBLAS_NUM_THREADS``, ``MKL_NUM_THREADS``, ``NUMBA_NUM_THREADS`` = 1
                  in the workers: a core runs one point, never a pool of threads
                  competing with another's; glibc's malloc left as it is
                  (:data:`NANNY_CONFIG`) (default)
``"inprocess"``   a LocalCluster of ``workers`` threads in this process (tests)
``"synchronous"`` a plain loop in this process, no dask
address           an existing scheduler, ``tcp://host:8786`` (``docs/studies.md``)
``*.json``        an existing scheduler by its scheduler file (``dask scheduler
                  --scheduler-file``, dask-mpi, dask-jobqueue)
a Client          a :class:`distributed.Client` the caller made
================  ================================================================

On dask, each point runs with one numba thread; a worker process that dies (out of
memory, node lost) is retried by dask on another worker, and a point whose workers
keep dying is left without a row (status ``missing``) for the next run.
"""

from __future__ import annotations

import logging
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from .figures import plot_study
from .point import run_point
from .table import DONE, read_row, study_table, write_row, write_table

__all__ = ["THREAD_ENV", "StudyRun", "TerminalProgress", "open_client", "run_study"]

THREAD_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
              "NUMBA_NUM_THREADS": "1"}
# dask's nanny sets MALLOC_TRIM_THRESHOLD_=65536 in its workers; any value switches off
# glibc's dynamic mmap threshold, so every large array is a fresh mmap, and a point runs
# about 2x slower (measured: 8 SENT points, 2.5 s unset against 5.1 s with it). Unset here.
NANNY_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}
SCHEDULERS = ("local", "inprocess", "synchronous")


@dataclass(frozen=True)
class StudyRun:
    """What :func:`run_study` did: the ``table`` (a pandas DataFrame, one row per point),
    the counts of points (``total``, ``skipped``: done before, ``computed``, ``failed``
    among the computed, ``lost``: their workers died), the written ``files`` (table
    and figures) and the wall time ``seconds``."""

    table: object
    out: Path
    total: int
    skipped: int
    computed: int
    failed: int
    lost: int
    files: tuple
    seconds: float
    lost_errors: dict

    @property
    def ok(self) -> bool:
        """Whether every point of the study has a row with status ``ok`` (this run's or an
        earlier one's)."""
        return bool((self.table["status"] == "ok").all())

    def summary(self) -> str:
        """The report of ``efgkit sweep``: counts, then the files written."""
        t = self.table
        lines = [f"points    {self.total}: {self.skipped} done before, {self.computed} computed "
                 f"({self.failed} failed), {self.lost} lost (workers died; rerun to retry)",
                 f"time      {self.seconds:.1f} s"]
        bad = t[t["status"] == "failed"]
        for _, r in bad.head(5).iterrows():
            lines.append(f"failed    {r['key']}: {r['error_type']}: {r['error_message']}")
        if len(bad) > 5:
            lines.append(f"          ... and {len(bad) - 5} more (table column error_message)")
        for k, msg in list(self.lost_errors.items())[:5]:
            lines.append(f"lost      {k}: {msg}")
        lines += [("written   " if i == 0 else "          ") + str(f)
                  for i, f in enumerate(self.files)]
        return "\n".join(lines)


class TerminalProgress:
    """A progress line on ``stream`` (``sys.stderr``) when it is a terminal, nothing
    otherwise (CI, logs, pipes): call it as ``progress(done, total, failed)``."""

    def __init__(self, stream=None):
        self.stream = stream if stream is not None else sys.stderr
        self.live = bool(getattr(self.stream, "isatty", lambda: False)())
        self.t0 = time.perf_counter()

    def __call__(self, done: int, total: int, failed: int) -> None:
        if not self.live:
            return
        dt = time.perf_counter() - self.t0
        eta = dt / done * (total - done) if done else float("nan")
        line = (f"\rsweep: {done}/{total} points" + (f", {failed} failed" if failed else "")
                + (f", {dt / done:.2f} s/point, {eta:.0f} s left" if done else ""))
        self.stream.write(line.ljust(72) + ("\n" if done == total else ""))
        self.stream.flush()


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def open_client(scheduler="local", workers: int | None = None, timeout: float = 20.0):
    """A dask client for ``scheduler`` (module docstring) and the cluster to close after
    (None when the client connects to a scheduler it did not start).

    Raises
    ------
    ValueError
        ``workers`` not a positive integer, or an address that cannot be reached (naming
        it, with the remedy).
    """
    import dask
    from distributed import Client, LocalCluster

    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 1):
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    if scheduler in ("local", "inprocess", None):
        inproc = scheduler == "inprocess"
        n = workers or (1 if inproc else _cores())
        kw = {} if inproc else {"env": dict(THREAD_ENV)}
        try:
            with dask.config.set(NANNY_CONFIG):
                cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=not inproc,
                                       dashboard_address=None, silence_logs=logging.ERROR, **kw)
        except RuntimeError as err:  # a worker process could not start
            raise RuntimeError(
                f"the local dask cluster did not start ({err}); a script that starts one must "
                "do so under `if __name__ == \"__main__\":` (its workers are new processes that "
                "import the script), or use scheduler='synchronous'") from err
        return Client(cluster), cluster
    if not isinstance(scheduler, str):
        raise TypeError(f"scheduler must be 'local', 'inprocess', 'synchronous', an address "
                        f"or a scheduler file, got {scheduler!r}")
    if not scheduler.endswith(".json") and ":" not in scheduler:
        raise ValueError(f"scheduler {scheduler!r} is neither one of {SCHEDULERS} nor an address "
                         "such as 'tcp://host:8786' nor a scheduler file '*.json'")
    try:
        if scheduler.endswith(".json"):
            return Client(scheduler_file=scheduler, timeout=timeout), None
        return Client(scheduler, timeout=timeout), None
    except (OSError, TimeoutError, ValueError) as err:
        raise ValueError(
            f"cannot reach the dask scheduler {scheduler!r} ({type(err).__name__}: {err}); "
            "start one (`dask scheduler`, then `dask worker ADDRESS --nthreads 1` on each "
            "machine) or leave the scheduler out to run on a local cluster") from err


def _todo(points, out: Path, retry_failed: bool) -> tuple[list, dict]:
    done_status = ("ok",) if retry_failed else DONE
    rows, todo = {}, []
    for p in points:
        row = read_row(out, p.key)
        if row is not None and row.get("status") in done_status:
            rows[p.key] = row
        else:
            todo.append(p)
    return todo, rows


def _on_dask(client, todo, threads, record) -> dict:
    """Submit every point, record each row as it finishes; returns key -> error of the
    points whose workers died."""
    from distributed import as_completed

    futures = client.map(run_point, [p.task() for p in todo], threads=threads,
                         key=[f"efgkit-point-{p.key}" for p in todo], pure=False)
    lost = {}
    by_key = {f.key: p for f, p in zip(futures, todo, strict=True)}
    try:
        for fut in as_completed(futures):
            p = by_key[fut.key]
            try:
                row = fut.result()
            except Exception as err:  # KilledWorker, cancelled: no row, next run retries
                lost[p.key] = f"{type(err).__name__}: {err}"
                record(None)
            else:
                record(row)
            fut.release()
    finally:
        client.cancel(futures)
    return lost


def run_study(study, out=None, scheduler="local", workers: int | None = None,
              retry_failed: bool = False, progress=None, figures: bool = True,
              threads: int | None = 1) -> StudyRun:
    """Run the points of ``study`` that have no row yet; write the table and the figures.

    Parameters
    ----------
    study : Study
    out : path, optional
        Output directory (default ``out/<study name>``): rows in ``points/``, the table
        ``<name>.csv`` and ``<name>.parquet``, the figures ``<name>_<parameter>.png``.
    scheduler : str or distributed.Client
        Where to run (module docstring).
    workers : int, optional
        ``local`` and ``inprocess``: the number of workers.
    retry_failed : bool
        Run the failed points again too (after a fix; a failure is otherwise final).
    progress : callable, optional
        ``progress(done, total, failed)`` after every point (:class:`TerminalProgress`).
    figures : bool
        Write the figures of K against each parameter.
    threads : int, optional
        Numba threads per point on dask (None: the worker's own setting). The
        synchronous loop leaves them as they are.
    """
    from ..io import file_name, write_figure

    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 1):
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    t0 = time.perf_counter()
    out = Path(out) if out is not None else Path("out") / file_name(study.name)
    points = study.points()
    todo, rows = _todo(points, out, retry_failed)
    counts = {"done": 0, "failed": 0}

    def record(row):
        if row is not None:
            write_row(out, row)
            rows[row["key"]] = row
            counts["failed"] += row["status"] != "ok"
        counts["done"] += 1
        if progress is not None:
            progress(counts["done"], len(todo), counts["failed"])

    lost = {}
    if scheduler == "synchronous":
        for p in todo:
            record(run_point(p.task()))
    elif todo:
        if isinstance(scheduler, str) or scheduler is None:
            client, cluster = open_client(scheduler, workers)
        else:
            client, cluster = scheduler, None
        try:
            lost = _on_dask(client, todo, threads, record)
        finally:
            if client is not scheduler:
                client.close()
            if cluster is not None:
                cluster.close()
    table = study_table(study, out, rows)
    name = file_name(study.name)
    files = list(write_table(table, out, name))
    if figures:
        for label, fig in plot_study(table, study).items():
            files.append(write_figure(fig, out / f"{name}_{file_name(label)}.png"))
    return StudyRun(table, out, len(points), len(points) - len(todo), len(todo) - len(lost),
                    counts["failed"], len(lost), tuple(files), time.perf_counter() - t0, lost)
