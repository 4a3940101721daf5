"""Run the pending cases of a study on local processes or on a Dask distributed cluster.

Local (default): a :class:`concurrent.futures.ProcessPoolExecutor` (spawned processes; no server).
If a worker process dies (the pool breaks), the cases in flight are submitted again on a new pool,
and a case that was in flight at two breakages is recorded as failed.

Dask: ``scheduler`` is an address (``tcp://host:8786``) or a ``distributed`` cluster object. Each case
is one task named ``case-<index>-<key>`` (the dashboard groups them as ``case``); a task the cluster
loses (e.g. ``KilledWorker``) is recorded as a failed case. Workers need the same tether_sim
(checked: the source hash of each case is compared on the worker).

Both feed finished cases, in completion order, to ``on_result`` (the result store) and to the
progress line.
"""

import math
import multiprocessing
import os
import signal
import sys
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

from tether_sim.studies.case import run_task

SUBMIT_AHEAD = 4  # cases submitted per worker ahead of the finished ones (the rest resolved as they are needed)


class Progress:
    """Cases done / failed, throughput and time left, on one terminal line (or a line per update)."""

    def __init__(self, total, skipped=0, stream=None, every=2.0, heartbeat=30.0):
        self.total, self.skipped = total, skipped
        self.done = self.failed = 0
        self.instant = 0  # cases recorded without running (rejected by the loader): not in the rate
        self.heartbeat = heartbeat
        self.stream = stream or sys.stderr
        self.every = every
        self.t0 = time.monotonic()
        self._last = -math.inf
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()

    def line(self) -> str:
        finished = self.done + self.failed
        elapsed = time.monotonic() - self.t0
        ran = finished - self.instant
        rate = ran / elapsed if elapsed > 0 and ran > 0 else 0.0
        left = (self.total - finished) / rate if rate > 0 else math.nan
        eta = "?" if math.isnan(left) else _duration(left)
        return (f"[study] {finished}/{self.total} cases ({self.done} ok, {self.failed} failed"
                f"{f', {self.skipped} already in the results' if self.skipped else ''}) | "
                f"{rate * 3600:.3g} cases/h | {_duration(elapsed)} elapsed, ~{eta} left")

    def update(self, row, force=False):
        if row is not None:
            if row.get("status") == "ok":
                self.done += 1
            else:
                self.failed += 1
                self._print(f"[study] case {row.get('index')} ({row.get('key')}) failed: {row.get('error')}", newline=True)
        now = time.monotonic()
        if force or now - self._last >= self.every or self.done + self.failed == self.total:
            self._last = now
            self._print(self.line(), newline=not self.tty)

    def tick(self):
        """Called while cases run: reprint the line at least every ``heartbeat`` seconds."""
        if time.monotonic() - self._last >= self.heartbeat:
            self.update(None, force=True)

    def close(self):
        self._print(self.line(), newline=True)

    def _print(self, text, newline):
        if self.tty:
            self.stream.write("\r\033[K" + text + ("\n" if newline else ""))
        else:
            self.stream.write(text + "\n")
        self.stream.flush()


def _duration(seconds):
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}h{m:02d}m" if h else (f"{m}m{s:02d}s" if m else f"{s}s")


def failed_result(task, error) -> dict:
    return {"row": {"key": task["key"], "index": task["index"], "study": task["study"], "status": "failed",
                    "error": error, **{f"var.{k}": v for k, v in task["variables"].items()}}, "events": []}


def _worker_ignores_sigint():
    """Worker initializer: a terminal's Ctrl-C goes to the whole process group; the parent alone
    decides (it stops the workers itself), so a worker prints no KeyboardInterrupt traceback."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def stopped_tasks(futures: dict, stop) -> dict:
    """After a stop request: cancel the cases not started, and return {"in_flight": [tasks],
    "not_started": [tasks], "signal": name}; the caller ends the workers of the in-flight ones."""
    in_flight, not_started = [], []
    for fut, task in futures.items():
        if fut.cancel():
            not_started.append(task)
        elif not fut.done():
            in_flight.append(task)
    return {"in_flight": in_flight, "not_started": not_started, "signal": stop.name}


def run_local(tasks, on_result, workers=None, tick=None, stop=None):
    """Run ``tasks`` (an iterable: taken as workers free up, so a lazily resolved study starts at
    once) on ``workers`` local processes (default: every core); ``tick()`` is called every few
    seconds while they run (progress heartbeat). ``stop``: a :class:`tether_sim.stopping.SignalStop`;
    on a stop request the cases submitted but not started are cancelled, the workers are ended (their
    cases in flight are not in the results and run again on the next start) and the function returns
    :func:`stopped_tasks`' account (None when every case ran)."""
    workers = max(1, workers or os.cpu_count() or 1)
    if isinstance(tasks, (list, tuple)):
        workers = min(workers, len(tasks) or 1)
    source, retry = iter(tasks), []
    breakages = {}
    context = multiprocessing.get_context("spawn")  # a clean interpreter per worker (numba, DDS libraries)
    more = True
    while more or retry:
        with ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=_worker_ignores_sigint) as pool:
            futures = {}
            broken = False
            while True:
                while not broken and len(futures) < SUBMIT_AHEAD * workers and (retry or more):
                    task = retry.pop(0) if retry else next(source, None)
                    if task is None:
                        more = False
                        break
                    futures[pool.submit(run_task, task)] = task
                if not futures:
                    break
                finished, _ = wait(futures, timeout=0.5 if stop is not None else 5.0, return_when=FIRST_COMPLETED)
                if tick is not None:
                    tick()
                if stop is not None and stop.requested:
                    for fut in finished:  # finished before the stop was seen: keep them
                        if not fut.cancelled() and fut.exception() is None:
                            on_result(fut.result())
                            futures.pop(fut)
                    account = stopped_tasks(futures, stop)
                    for proc in list(getattr(pool, "_processes", {}).values()):
                        proc.terminate()
                    return account
                for fut in finished:
                    task = futures.pop(fut)
                    try:
                        on_result(fut.result())
                    except BrokenProcessPool:
                        broken = True
                        breakages[task["key"]] = breakages.get(task["key"], 0) + 1
                        if breakages[task["key"]] >= 2:
                            on_result(failed_result(task, "a worker process died twice while this case was running "
                                                          "(BrokenProcessPool; out of memory or a crash in compiled code?)"))
                        else:
                            retry.append(task)
                if broken and not futures:
                    break
            if broken:
                print(f"[study] a worker process died; {len(retry)} case(s) run again on a new pool", file=sys.stderr)
    return None


def run_dask(tasks, on_result, scheduler, tick=None, stop=None):
    """Run ``tasks`` on the Dask cluster at ``scheduler`` (an address or a cluster object).
    ``stop``: as for :func:`run_local` (the cases in flight are cancelled on the cluster)."""
    from dask.distributed import Client
    from dask.distributed import wait as dask_wait

    with Client(scheduler) as client:
        link = client.dashboard_link
        print(f"[study] Dask scheduler {client.scheduler.address}, {len(client.scheduler_info()['workers'])} "
              f"worker(s); dashboard: {link}", file=sys.stderr)
        source, futures, more = iter(tasks), {}, True
        ahead = SUBMIT_AHEAD * max(1, len(client.scheduler_info()["workers"]))
        while True:
            while more and len(futures) < ahead:  # (taken as the cluster frees up: a lazy study starts at once)
                t = next(source, None)
                if t is None:
                    more = False
                    break
                futures[client.submit(run_task, t, key=f"case-{t['index']:05d}-{t['key']}", pure=False)] = t
            if not futures:
                break
            if stop is not None and stop.requested:
                in_flight = _dask_in_flight(client, futures)
                account = {"in_flight": in_flight, "signal": stop.name,
                           "not_started": [t for t in futures.values() if t not in in_flight]}
                client.cancel(list(futures))
                return account
            try:
                finished, _ = dask_wait(list(futures), timeout=0.5 if stop is not None else 5.0,
                                        return_when="FIRST_COMPLETED")
            except TimeoutError:
                finished = ()
            except Exception:  # noqa: BLE001 - FuturesCancelledError: the cancelled ones become failed cases
                finished = [f for f in futures if f.status != "pending"]
            if tick is not None:
                tick()
            for fut in finished:
                task = futures.pop(fut)
                try:
                    result = fut.result()
                except Exception as exc:  # noqa: BLE001 - lost worker, cancelled task: a failed case
                    result = failed_result(task, f"{type(exc).__name__}: {exc}")
                on_result(result)
                fut.release()
    return None



def _dask_in_flight(client, futures: dict) -> list:
    """The tasks of ``futures`` the scheduler has on a worker (state ``processing``); all of them
    when the scheduler cannot be asked (an account only)."""
    keys = [f.key for f in futures]

    def states(dask_scheduler):
        return {k: getattr(dask_scheduler.tasks.get(k), "state", None) for k in keys}

    try:
        known = client.run_on_scheduler(states)
    except Exception:  # noqa: BLE001
        known = {}
    return [t for f, t in futures.items() if known.get(f.key, "processing") == "processing"]
