"""A study from its file to its results folder: resolve and key every case, skip those already in
the results, run the rest (local processes or Dask), journal each one as it finishes, write the tables."""

import hashlib
import json
import os
import shutil
import sys
import time
from pathlib import Path

from tether_sim.errors import ConfigError
from tether_sim.solvers.work import span
from tether_sim.studies.case import code_version, make_task
from tether_sim.studies.execute import Progress, failed_result, run_dask, run_local
from tether_sim.studies.results import ResultStore
from tether_sim.studies.spec import load_study

TABLE_INTERVAL = 30.0  # s between rewrites of the Parquet/CSV tables while a study runs
RESOLVE_PROGRESS_S = 3.0  # s between progress lines while the cases are resolved


def default_out(study) -> Path:
    return Path("out") / "studies" / study.name


def plan(study, out_dir, retry_failed=False, stream=None):
    """(tasks to run, invalid cases as failed results, number skipped, duplicates) for a study.
    Resolving takes about a millisecond a case: a progress line goes to ``stream`` every few seconds."""
    code = code_version()
    done = ResultStore(out_dir).load()
    tasks, invalid, seen, duplicates, skipped = [], [], {}, [], 0
    base_files = {}
    cases = study.cases()
    t0 = last = time.monotonic()
    for case in cases:
        if stream is not None and time.monotonic() - last > RESOLVE_PROGRESS_S:
            last = time.monotonic()
            print(f"[study] resolving the cases: {case.index}/{len(cases)} in {last - t0:.0f} s", file=stream,
                  flush=True)
        try:
            task = make_task(case, study, code, out_dir, base_files)
        except ConfigError as exc:  # a case the parameter loader rejects: a failed row, not the end
            text = json.dumps([str(case.base), case.overrides, code["source_hash"]], sort_keys=True, default=repr)
            task = {"key": "invalid-" + hashlib.sha256(text.encode()).hexdigest()[:12], "index": case.index,
                    "study": study.name, "variables": dict(case.variables)}
            invalid.append(failed_result(task, f"ConfigError: {exc}"))
            continue
        if task["key"] in seen:
            duplicates.append((case.index, seen[task["key"]]))
            continue
        seen[task["key"]] = case.index
        previous = done.get(task["key"])
        if previous is not None and (previous.get("status") == "ok" or not retry_failed):
            skipped += 1
            continue
        tasks.append(task)
    new = [r for r in invalid if r["row"]["key"] not in done]
    return tasks, new, skipped + len(invalid) - len(new), duplicates


def parse_indices(text) -> set:
    """Case indices from ``"0,3,10-12"`` (ranges inclusive)."""
    out = set()
    for part in str(text).split(","):
        part = part.strip()
        if not part:
            continue
        try:
            lo, _, hi = part.partition("-")
            out.update(range(int(lo), int(hi or lo) + 1))
        except ValueError:
            raise ConfigError(f"--cases: expected indices like 0,3,10-12, got {part!r}") from None
    return out


def run_study(path, out_dir=None, *, scheduler=None, workers=None, retry_failed=False, limit=None,
              cases=None, stream=None, stop=None) -> dict:
    """Run the study file ``path`` (only the case indices ``cases``, if given); returns a summary.

    ``stop``: a :class:`tether_sim.stopping.SignalStop`, made graceful when the cases start: a stop
    request then keeps every finished case (journaled as it finished), cancels the rest, removes the
    incomplete MCAP files of the cases in flight, writes the tables and returns with ``interrupted``
    (the signal's name), ``in_flight`` and ``not_started`` (counts) in the summary."""
    stream = stream or sys.stderr
    study = load_study(path)
    out_dir = Path(out_dir) if out_dir else default_out(study)
    out_dir.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(study.path, out_dir / "study.yaml")
    tasks, invalid, skipped, duplicates = plan(study, out_dir, retry_failed, stream=stream)
    for index, first in duplicates:
        print(f"[study] case {index} resolves to the same configuration as case {first}: run once", file=stream)
    if cases is not None:
        tasks = [t for t in tasks if t["index"] in cases]
        invalid = [r for r in invalid if r["row"]["index"] in cases]
    if limit is not None:
        tasks = tasks[:max(0, int(limit))]
    if tasks:  # what the cases to run should cost, before they start (solvers/work.py run_estimate)
        cpu = sum(t["expected_cpu"] for t in tasks)
        line = f"[study] {len(tasks)} case(s) to run: expected about {span(cpu)} of CPU on idle cores"
        if scheduler is None:
            n = max(1, min(workers or os.cpu_count() or 1, len(tasks)))
            line += f", about {span(cpu / n)} on {n} local worker(s)"
        print(line + " (a busy machine takes longer)", file=stream, flush=True)
    store = ResultStore(out_dir, units=study.column_units())
    progress = Progress(len(tasks) + len(invalid), skipped, stream=stream)
    last_table = [time.monotonic()]

    def on_result(result):
        store.append(result)
        progress.update(result["row"])
        if time.monotonic() - last_table[0] > TABLE_INTERVAL:
            store.write_tables()
            last_table[0] = time.monotonic()

    if stop is not None:
        stop.graceful = True  # from here on results are written: a signal asks for a clean stop
    for result in invalid:
        on_result(result)
    progress.instant = len(invalid)
    progress.update(None, force=True)
    account = None
    if tasks:
        if scheduler is None:
            account = run_local(tasks, on_result, workers, tick=progress.tick, stop=stop)
        else:
            cluster = _cluster(scheduler, workers)
            try:
                account = run_dask(tasks, on_result, cluster, tick=progress.tick, stop=stop)
            finally:
                if cluster is not scheduler:
                    cluster.close()
    progress.close()
    table = store.write_tables()
    summary = {"out": str(out_dir), "table": str(table), "ran": progress.done + progress.failed,
               "ok": progress.done, "failed": progress.failed, "skipped": skipped, "interrupted": "",
               "in_flight": 0, "not_started": 0}
    if account is not None:
        for task in account["in_flight"] + account["not_started"]:  # not in the results: no file of theirs
            if task.get("mcap"):  # either (a case cut short leaves an MCAP without its summary)
                Path(task["mcap"]).unlink(missing_ok=True)
        summary.update(interrupted=account["signal"], in_flight=len(account["in_flight"]),
                       not_started=len(account["not_started"]))
    return summary


def _cluster(scheduler, workers):
    """An address as given, or ``local``: a LocalCluster on loopback (one thread per worker process)."""
    if scheduler != "local":
        return scheduler
    import signal
    import threading

    from dask.distributed import LocalCluster

    # a terminal's Ctrl-C goes to the whole process group: the cluster's processes inherit SIGINT
    # ignored, and this process alone stops the study (cancels the cases, closes the cluster)
    main = threading.current_thread() is threading.main_thread()
    old = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        return LocalCluster(n_workers=workers or None, threads_per_worker=1, processes=True, host="127.0.0.1",
                            dashboard_address="127.0.0.1:8787")
    finally:
        if main:
            signal.signal(signal.SIGINT, old)
