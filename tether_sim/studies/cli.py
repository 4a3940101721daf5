"""Console script ``tether-sim-study``: run a study file, or report on a results folder.

    tether-sim-study STUDY.yaml [--out DIR] [--workers N] [--scheduler tcp://host:8786 | local]
                                [--retry-failed] [--limit N] [--cases 0,5,10-12] [--list]
    tether-sim-study report RESULTS [--out DIR]

Results go to ``out/studies/<study name>/`` unless ``--out`` says otherwise (docs/studies.md).
"""

import argparse
import os
import sys
from pathlib import Path

from tether_sim.errors import ConfigError
from tether_sim.stopping import SignalStop, interrupted_code


def _run_parser():
    ap = argparse.ArgumentParser(prog="tether-sim-study", description="Run a snap-load study: every case through "
                                 "the tether-sim-offline code path, results as Parquet and CSV (see "
                                 "'tether-sim-study report --help' for the figures).")
    ap.add_argument("study", help="study file (YAML, docs/studies.md)")
    ap.add_argument("--out", default=None, help="results folder (default out/studies/<study name>)")
    ap.add_argument("--workers", type=int, default=None, help="local worker processes (default: every core); "
                    "with --scheduler local, the number of Dask workers")
    ap.add_argument("--scheduler", default=None, help="Dask scheduler address (tcp://host:8786), or 'local' for a "
                    "Dask LocalCluster on this machine; default: local processes, no Dask")
    ap.add_argument("--retry-failed", action="store_true", help="run again the cases recorded as failed")
    ap.add_argument("--limit", type=int, default=None, help="run at most this many of the pending cases")
    ap.add_argument("--cases", default=None, help="run only these case indices (as --list numbers them), e.g. 0,5,10-12")
    ap.add_argument("--list", action="store_true", help="print the cases and whether each is done; run nothing")
    return ap


def _report_parser():
    ap = argparse.ArgumentParser(prog="tether-sim-study report", description="Figures (PNG) and a markdown summary "
                                 "of a study's results, chosen from what it varies: peak tension (a heat map over two "
                                 "axes), cage DAF, and for a study with seeds the exceedance of the per-case maxima "
                                 "with a Gumbel fit per condition; for a line-network study the same per line (both ends), the "
                                 "tension of each line at each body and the force on each point.")
    ap.add_argument("results", help="results folder (or its results.parquet)")
    ap.add_argument("--out", default=None, help="folder of the figures and report.md (default RESULTS/report)")
    return ap


def _list(args):
    """Each case as it is resolved (the first line at once, whatever the study's size), then the counts."""
    from tether_sim.studies.runner import default_out, plan_lazy
    from tether_sim.studies.spec import load_study

    study = load_study(args.study)
    out = args.out or default_out(study)
    states = {"task": "to run", "invalid": "invalid", "skipped": "done", "duplicate": "duplicate"}
    counts = dict.fromkeys(states, 0)
    try:
        for kind, index, item, variables in plan_lazy(study, out, args.retry_failed):
            counts[kind] += 1
            try:
                base = Path(study.base.format(**variables)).name
            except (ValueError, TypeError, KeyError, IndexError, AttributeError):
                base = "?"
            values = ", ".join(f"{k}={v}" for k, v in variables.items())
            print(f"{index:5d}  {states[kind]:14s}  {base}  {values}", flush=index < 100)
        print(f"{counts['task']} to run, {counts['skipped']} already in {out}, {counts['invalid']} invalid, "
              f"{counts['duplicate']} duplicate")
    except BrokenPipeError:  # the reader has gone (--list | head): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 0


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        if argv and argv[0] == "report":
            args = _report_parser().parse_args(argv[1:])
            from tether_sim.studies.report import write_report

            md = write_report(args.results, args.out)
            print(f"wrote {md}")
            return 0
        args = _run_parser().parse_args(argv)
        if args.list:
            return _list(args)
        from tether_sim.studies.runner import parse_indices, run_study

        with SignalStop("tether-sim-study") as stop:
            s = run_study(args.study, args.out, scheduler=args.scheduler, workers=args.workers,
                          retry_failed=args.retry_failed, limit=args.limit,
                          cases=parse_indices(args.cases) if args.cases is not None else None, stop=stop)
    except KeyboardInterrupt as exc:  # a signal while the cases were resolved: no case ran
        name, code = interrupted_code(exc)
        print(f"tether-sim-study: stopped by {name} before any case ran", file=sys.stderr)
        return code
    except (ConfigError, FileNotFoundError) as exc:
        print(f"tether-sim-study: {exc}", file=sys.stderr)
        return 2
    if s["interrupted"]:
        print(f"tether-sim-study: stopped by {s['interrupted']}: {s['ran']} case(s) finished and kept in the results, "
              f"{s['in_flight']} in flight dropped and {s['not_started']} not started (both run when the study "
              "is started again)", file=sys.stderr)
    print(f"{s['ran']} case(s) run ({s['ok']} ok, {s['failed']} failed), {s['skipped']} already in the results; "
          f"table {s['table']} (and results.csv)")
    if s["interrupted"]:
        return stop.exit_code
    return 1 if s["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
