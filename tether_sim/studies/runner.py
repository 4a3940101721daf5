"""A study from its file to its results folder: resolve and key every case, skip those already in
the results, run the rest (local processes or Dask), journal each one as it finishes, write the tables."""

import hashlib
import json
import math
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
    """(tasks to run, invalid cases as failed results, number skipped, duplicates) for a study: every
    case resolved (:func:`plan_lazy` all the way). Resolving takes about a millisecond a case: a progress
    line goes to ``stream`` every few seconds."""
    tasks, invalid, duplicates, skipped = [], [], [], 0
    t0 = last = time.monotonic()
    n = study.n_cases()
    for kind, index, item, _ in plan_lazy(study, out_dir, retry_failed):
        if stream is not None and time.monotonic() - last > RESOLVE_PROGRESS_S:
            last = time.monotonic()
            print(f"[study] resolving the cases: {index}/{n} in {last - t0:.0f} s", file=stream, flush=True)
        if kind == "task":
            tasks.append(item)
        elif kind == "invalid":
            invalid.append(item)
        elif kind == "duplicate":
            duplicates.append((index, item))
        else:
            skipped += 1
    return tasks, invalid, skipped, duplicates


def plan_lazy(study, out_dir, retry_failed=False, indices=None):
    """The cases of a study resolved one at a time, in order (only those in ``indices``, if given):
    yields (kind, case index, item, variables) with kind "task" (item: the task to run), "invalid" (a case the
    parameter loader or its ``set`` expression rejects: a failed result to record, not yet in the
    results), "skipped" (done already, or an invalid case already recorded) or "duplicate" (item: the
    index of the case it resolves like). The first case is ready at once, whatever the study's size."""
    code = code_version()
    done = ResultStore(out_dir).load()
    seen, base_files = {}, {}
    for index, variables in study.iter_variables():
        if indices is not None and index not in indices:
            continue
        case = None
        try:
            case = study.case(index, variables)
            task = make_task(case, study, code, out_dir, base_files)
        except ConfigError as exc:  # a case the loader rejects (StudyError: its expression): a failed row
            ident = [str(case.base), case.overrides] if case is not None else [study.base, repr(variables)]
            text = json.dumps([*ident, code["source_hash"]], sort_keys=True, default=repr)
            task = {"key": "invalid-" + hashlib.sha256(text.encode()).hexdigest()[:12], "index": index,
                    "study": study.name, "variables": dict(variables)}
            result = failed_result(task, f"{type(exc).__name__}: {exc}")
            yield ("skipped", index, None, variables) if task["key"] in done else ("invalid", index, result, variables)
            continue
        if task["key"] in seen:
            yield "duplicate", index, seen[task["key"]], variables
            continue
        seen[task["key"]] = index
        previous = done.get(task["key"])
        if previous is not None and (previous.get("status") == "ok" or not retry_failed):
            yield "skipped", index, None, variables
            continue
        yield "task", index, task, variables


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
    selected = study.n_cases() if cases is None else len({i for i in cases if 0 <= i < study.n_cases()})
    if limit is not None:
        selected = min(selected, max(0, int(limit)))
    _announce_cost(study, out_dir, retry_failed, cases, limit, selected, scheduler is None, workers, stream)
    store = ResultStore(out_dir, units=study.column_units())
    progress = Progress(selected, 0, stream=stream)  # the total shrinks as cases turn out done or duplicate
    last_table = [time.monotonic()]
    counts = {"skipped": 0, "tasks": 0, "exhausted": False}

    def on_result(result):
        store.append(result)
        progress.update(result["row"])
        if time.monotonic() - last_table[0] > TABLE_INTERVAL:
            store.write_tables()
            last_table[0] = time.monotonic()

    def tasks():
        """The tasks to run, resolved as the workers ask for them; invalid cases recorded on the way."""
        for kind, index, item, _ in plan_lazy(study, out_dir, retry_failed, cases):
            if limit is not None and counts["tasks"] >= limit:
                break
            if kind == "task":
                counts["tasks"] += 1
                yield item
            elif kind == "invalid":
                progress.instant += 1
                on_result(item)
            else:
                if limit is None:  # (with --limit the total is the limit until the tasks are known)
                    progress.total -= 1
                if kind == "skipped":
                    counts["skipped"] += 1
                    progress.skipped += 1
                else:
                    print(f"[study] case {index} resolves to the same configuration as case {item}: run once",
                          file=stream)
        counts["exhausted"] = True
        progress.total = progress.instant + counts["tasks"]  # now known: the invalid cases and the tasks

    if stop is not None:
        stop.graceful = True  # from here on results are written: a signal asks for a clean stop
    progress.update(None, force=True)
    account = None
    source = tasks()
    if scheduler is None:
        account = run_local(source, on_result, workers, tick=progress.tick, stop=stop)
    else:
        cluster = _cluster(scheduler, workers)
        try:
            account = run_dask(source, on_result, cluster, tick=progress.tick, stop=stop)
        finally:
            if cluster is not scheduler:
                cluster.close()
    progress.close()
    table = store.write_tables()
    summary = {"out": str(out_dir), "table": str(table), "ran": progress.done + progress.failed,
               "ok": progress.done, "failed": progress.failed, "skipped": counts["skipped"], "interrupted": "",
               "in_flight": 0, "not_started": 0}
    if account is not None:
        for task in account["in_flight"] + account["not_started"]:  # not in the results: no file of theirs
            if task.get("mcap"):  # either (a case cut short leaves an MCAP without its summary)
                Path(task["mcap"]).unlink(missing_ok=True)
        # not started: those cancelled, and (not resolved yet) the selected cases still to come
        later = 0 if counts["exhausted"] else max(0, progress.total - progress.done - progress.failed
                                                  - len(account["in_flight"]) - len(account["not_started"]))
        summary.update(interrupted=account["signal"], in_flight=len(account["in_flight"]),
                       not_started=len(account["not_started"]) + later)
    return summary


ESTIMATE_CASES = 500  # cases resolved before the start to state the cost (a larger study: extrapolated)


def _announce_cost(study, out_dir, retry_failed, cases, limit, selected, local, workers, stream):
    """One line, before the cases start, on what they should cost: the run estimate of each case to run
    (solvers/work.py run_estimate, in its task), summed; from the first ESTIMATE_CASES cases, scaled to
    the ``selected`` ones, when there are more; divided over the ``workers`` when they are ``local``."""
    cpu, n_tasks, examined, complete = 0.0, 0, 0, True
    for kind, _, item, _ in plan_lazy(study, out_dir, retry_failed, cases):
        if limit is not None and n_tasks >= limit:
            break
        if examined >= ESTIMATE_CASES:
            complete = False
            break
        examined += 1
        if kind == "task":
            n_tasks, cpu = n_tasks + 1, cpu + item["expected_cpu"]
    if n_tasks == 0:
        return
    what = f"{n_tasks} case(s)"
    if not complete:  # the rest as the resolved ones
        scale = selected / examined
        n_tasks, cpu = max(n_tasks, round(n_tasks * scale)), cpu * scale
        what = f"about {n_tasks} case(s) (from the first {examined})"
    if not math.isfinite(cpu):  # a network case has no cost model yet
        print(f"[study] {what} to run (line-network cases: no estimate of their cost)", file=stream, flush=True)
        return
    line = f"[study] {what} to run: expected about {span(cpu)} of CPU on idle cores"
    if local:
        n = max(1, min(workers or os.cpu_count() or 1, n_tasks))
        line += f", about {span(cpu / n)} on {n} local worker(s)"
    print(line + " (a busy machine takes longer)", file=stream, flush=True)


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
