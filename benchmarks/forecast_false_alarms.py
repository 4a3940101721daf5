"""Why the snap forecast raises false alarms: every false alarm of ``forecast_skill.py --dump`` files,
classified against the run's own end tension and snap events (docs/forecast.md, "Why the false alarms").

Each dumped sea is run again without forecasts (the same driver and detector as the skill run),
recording the end tension of every substep and every snap event the detector publishes (the further
events of an episode, its new maxima, included). Every warning (p >= 0.5, or ``--margin``'s
forecasts) with no scored snap within +-1.5 s of its predicted time is put in one of
``tether_sim.forecast.skill.FALSE_ALARM_KINDS`` (``classify_false_alarm``): a detector event the
scoring does not count, a timing error (the run snapped within the horizon, elsewhere), a near miss
(the run into the hysteresis band between the slack and the re-tension level, a peak at the snap
level), members slack where the run stayed above the re-tension level, or other. For the timing
errors it also prints which time estimates would have been within +-1.5 s of the run's snap.

    .venv/bin/python benchmarks/forecast_false_alarms.py out/forecast_skill/heldout15_L200_s50-51.json \
        --cache out/forecast_skill/truth_L200_s50-51.pkl

``--cache``: keep the reruns in this file (pickle) and read them from it when present.
"""

import argparse
import json
import math
import pickle
import sys
from dataclasses import asdict
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks.forecast_skill import run_slack_levels, truth_tensions, with_margin  # noqa: E402
from tether_sim.forecast.skill import FALSE_ALARM_KINDS, classify_false_alarm  # noqa: E402
from tether_sim.physics.snap import SnapEvent, episode_maxima  # noqa: E402


def truth_run(path, seed, dumped_args):
    """The run of a dumped sea again: {"t", "ship", "vehicle" (tension of every substep), "slack",
    "snap" ({end: level N}), "events" (every SnapEvent as a dict)}."""
    events = []
    t, tensions, slack, snap = truth_tensions(path, seed, dumped_args, events=events)
    return {"t": t, "ship": tensions["ship"], "vehicle": tensions["vehicle"],
            "slack": {end: float(x) for end, x in slack.items()}, "snap": {end: float(x) for end, x in snap.items()},
            "events": [asdict(e) for e in events]}


def classify(paths, cache=None, margin=0.0, tolerance=1.5):
    stored = pickle.loads(Path(cache).read_bytes()) if cache and Path(cache).exists() else {}
    totals = {k: 0 for k in FALSE_ALARM_KINDS}
    episodes = {k: 0 for k in FALSE_ALARM_KINDS}
    for path in paths:
        doc = json.loads(Path(path).read_text())
        horizon = doc["args"]["horizon"]
        end_time = doc["args"]["minutes"] * 60.0
        for run in doc["runs"]:
            key = f"{run['file']}:{run['seed']}"
            if key not in stored:
                stored[key] = truth_run(run["file"], run["seed"], doc["args"])
                if cache:
                    Path(cache).write_bytes(pickle.dumps(stored))
            truth = stored[key]
            events = [SnapEvent(**e) for e in truth["events"]]
            maxima = episode_maxima(events)
            dumped = sorted((e, round(x, 6)) for e, x, *_ in run.get("snap_events", run["snaps"]))
            rerun = sorted((e.location, round(e.time, 6)) for e in events)
            print(f"\n{Path(run['file']).stem} seed {run['seed']}: {len(events)} snap events in the rerun "
                  f"({len(maxima)} episodes; the dump has {len(dumped)}, {'the same' if dumped == rerun else 'DIFFERENT'})")
            for e in events:
                print(f"  event {e.location:7s} {e.time:8.3f} s peak {e.peak_tension / 1e3:6.1f} kN, slack from {e.slack_start:8.3f} s")
            slack = run_slack_levels(run, doc["args"])
            for source, fc in run["forecasts"].items():
                if margin > 0.0:
                    fc = [with_margin(f, horizon, source, slack, margin) for f in fc]
                    fc = [(g.end, g.stamp, g.probability, g.time_to_snap, g.members, g.member_snaps, None, g.member_slack_depths)
                          for g in fc]
                last = {}
                for f in fc:
                    end, stamp, p, tts, members, ms = f[:6]
                    depths = f[7] if len(f) > 7 else None
                    pred = stamp + tts
                    snaps = ([x for e, x, *_ in run["snap_events"] if e == end] if "snap_events" in run
                             else [x for e, x, *_ in run["snaps"] if e == end])  # every published peak
                    if not p >= 0.5 or pred > end_time - tolerance or any(abs(pred - x) <= tolerance for x in snaps):
                        continue
                    kind, depth, peak = classify_false_alarm(
                        stamp, pred, horizon, truth["t"], truth[end], truth["slack"][end], truth["snap"][end], snaps,
                        [(e.time, e.slack_start) for e in events if e.location == end], tolerance=tolerance)
                    totals[kind] += 1
                    new = end not in last or abs(pred - last[end]) > tolerance
                    last[end] = pred
                    episodes[kind] += new
                    times = sorted(x - stamp for x, _ in ms)
                    line = (f"  {'' if new else '  '}{end:7s} stamp {stamp:6.1f} p {p:.3f} predicted {pred:7.2f}: {kind}; run: least "
                            f"{depth:.2f} x slack level (stamp to predicted), peak {peak:.2f} x snap level (+-{tolerance:g} s)")
                    if kind == "timing":
                        run_snap = min((x for x in snaps if stamp < x <= stamp + horizon + tolerance), key=lambda x: abs(x - pred))
                        alt = {"earliest member": stamp + times[0],
                               "median of the snapping": stamp + float(np.median(times))}
                        ok = [k for k, v in alt.items() if abs(v - run_snap) <= tolerance]
                        line += (f"; run's snap {run_snap:.2f} ({run_snap - pred:+.2f} s); within +-{tolerance:g} s: "
                                 f"{', '.join(ok) if ok else 'none of the earliest member, the median of the snapping'}")
                    print(line)
                    print("        members' snaps (s after the stamp): " + " ".join(f"{x:.2f}" for x in times)
                          + ("; their least tension before it / slack level: "
                             + " ".join(f"{d / slack[end]:.2f}" for d in depths if d is not None and not math.isnan(d))
                             if depths else ""))
    print("\nfalse alarms by kind (forecasts; episodes): " + ", ".join(f"{k} {totals[k]} ({episodes[k]})" for k in FALSE_ALARM_KINDS))
    return totals, episodes


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dumps", nargs="+")
    ap.add_argument("--cache", default=None, help="pickle file for the reruns (read when present)")
    ap.add_argument("--margin", type=float, nargs="+", default=[0.0], help="forecast.slack_margin of the forecasts classified")
    args = ap.parse_args(argv)
    for margin in args.margin:
        print(f"\n=== slack margin {margin:g}")
        classify(args.dumps, args.cache, margin)
    return 0


if __name__ == "__main__":
    sys.exit(main())
