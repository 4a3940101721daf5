"""Calibration of the snap forecast's ensemble against the run: is it over-dispersed or biased?

Reads ``forecast_skill.py --dump`` JSON files, runs each dumped sea again without forecasts (the end
tensions of every substep; forecast_skill.truth_tensions) and sets every forecast's members against
the run over the forecast's horizon [stamp, stamp + horizon):

- the members' least end tension (``member_troughs``) against the run's own least tension: a rank
  histogram (flat for an ensemble as wide as its error, a hump in the middle when it is too wide, a U
  when too narrow);
- spread and skill, binned by the ensemble's mean trough in units of the slack level: the bias (run
  minus ensemble mean), the rms error of the ensemble mean, and the members' spread (standard deviation,
  ddof 1). For a calibrated ensemble of n members, rms error = sqrt(1 + 1/n) x spread and the bias is 0;
  conditioned on the forecast (the ensemble mean), not on the run, so a bias found is one a forecast
  can correct;
- the slack event itself: forecasts binned by the fraction of members whose trough is below the slack
  level against the fraction of those forecasts in which the run's trough was;
- the peak: for every forecast with p >= 0.5, the members' median snap peak against the run's largest
  tension within +-1.5 s of the predicted time (verified warnings and false alarms apart);
- with ``member_slack_depths`` in the dump (code of 2026-11-28 on): each snapping member's least tension
  before its snap (in slack levels), warnings that verified against false alarms.

Usage (the tuning seeds' figures of docs/forecast.md, "Calibration of the members' slack"):

    .venv/bin/python benchmarks/forecast_calibration.py out/forecast_skill/tune12_L1730_s21-23.json
"""

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from forecast_skill import truth_tensions  # noqa: E402
from tether_sim.forecast.skill import TIE_TOLERANCE, trough_rank  # noqa: E402

BINS = (0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0, math.inf)  # ensemble mean trough / slack level


def collect(paths, end):
    """Per forecast at ``end`` (horizon inside the run): dict of the run's and the members' numbers."""
    rows = []
    for path in paths:
        doc = json.loads(Path(path).read_text())
        horizon, tol = doc["args"]["horizon"], 1.5
        end_time = doc["args"]["minutes"] * 60.0
        for run in doc["runs"]:
            t, tensions, slack, level = truth_tensions(run["file"], run["seed"], doc["args"])
            T = tensions[end]
            snaps = [x for e, x in run["snaps"] if e == end]
            for f in run["forecasts"].get("known_sea", []):
                e, stamp, p, tts, members, msnaps, *extra = f
                if e != end or not extra or not extra[0] or stamp + horizon > end_time:
                    continue
                inside = (t > stamp - 1e-9) & (t < stamp + horizon - 1e-9)
                row = {"seed": run["seed"], "stamp": stamp, "p": p, "members": np.asarray(extra[0], float) / slack[end],
                       "run": T[inside].min() / slack[end], "slack": slack[end], "level": level[end],
                       "run_snap": any(stamp < x <= stamp + horizon for x in snaps),
                       "depths": np.asarray(extra[1], float) / slack[end] if len(extra) > 1 and extra[1] is not None else None}
                if p >= 0.5 and math.isfinite(tts):
                    pred = stamp + tts
                    win = (t >= pred - tol) & (t <= pred + tol)
                    row["run_peak"] = T[win].max() / level[end] if win.any() else math.nan
                    row["member_peak"] = float(np.median([pk for _, pk in msnaps])) / level[end]
                    row["verified"] = any(abs(pred - x) <= tol for x in snaps)
                rows.append(row)
    return rows


def report(rows, end):
    if not rows:
        print(f"{end}: no forecasts with member troughs")
        return
    n = rows[0]["members"].size
    print(f"\n{end} end: {len(rows)} forecasts, {n} members each (tensions in slack levels unless said)")
    hist = np.zeros(n + 1)
    for r in rows:
        if r["members"].size == n:  # ties (round-off in slack, a trough at the stamp) spread over their ranks
            hist += trough_rank(r["members"], r["run"], TIE_TOLERANCE)
    print("  rank of the run's least tension among the members' (0: below all; ties spread over their ranks): "
          + " ".join(f"{x:.1f}" for x in hist)
          + f"; below all {100 * hist[0] / hist.sum():.0f} %, above all {100 * hist[-1] / hist.sum():.0f} % "
          f"(calibrated: {100 / (n + 1):.0f} % each)")
    print("  ensemble mean trough bin | forecasts | bias run - mean | rms error of mean | spread (sd) | "
          "rms error / (sqrt(1 + 1/n) spread) | median of (run - member median)")
    for lo, hi in zip(BINS[:-1], BINS[1:]):
        sel = [r for r in rows if lo <= r["members"].mean() < hi]
        if not sel:
            continue
        err = np.array([r["run"] - r["members"].mean() for r in sel])
        sd = np.array([r["members"].std(ddof=1) for r in sel])
        med = np.array([r["run"] - np.median(r["members"]) for r in sel])
        ratio = math.sqrt(np.mean(err ** 2)) / (math.sqrt(1 + 1 / n) * math.sqrt(np.mean(sd ** 2)))
        print(f"    [{lo:.1f}, {hi:.1f}) | {len(sel):4d} | {err.mean():+.3f} | {math.sqrt(np.mean(err ** 2)):.3f} | "
              f"{math.sqrt(np.mean(sd ** 2)):.3f} | {ratio:.2f} | {np.median(med):+.3f}")
    print("  slack event: fraction of members below the slack level | forecasts | mean fraction | run below it")
    for lo, hi in ((0.0, 0.001), (0.001, 0.375), (0.375, 0.625), (0.625, 0.999), (0.999, 1.001)):
        sel = [r for r in rows if lo <= np.mean(r["members"] < 1.0) < hi]
        if sel:
            print(f"    [{lo:.3f}, {hi:.3f}) | {len(sel):4d} | {np.mean([np.mean(r['members'] < 1.0) for r in sel]):.2f} | "
                  f"{np.mean([r['run'] < 1.0 for r in sel]):.2f}")
    warn = [r for r in rows if "verified" in r]
    for verified in (True, False):
        sel = [r for r in warn if r["verified"] == verified]
        if not sel:
            continue
        ratio = np.array([r["member_peak"] / r["run_peak"] for r in sel])
        print(f"  p >= 0.5, {'verified' if verified else 'false alarm'}: {len(sel)} forecasts; members' median peak / run's "
              f"peak at the predicted time: median {np.median(ratio):.2f} (range {ratio.min():.2f}-{ratio.max():.2f}); run's "
              f"trough within the horizon: " + " ".join(f"{r['run']:.2f}" for r in sel[:40]))
        depths = [r["depths"] for r in sel if r["depths"] is not None]
        if depths:
            d = np.concatenate([x[np.isfinite(x)] for x in depths])
            if d.size:
                print(f"    snapping members' least tension before their snap: {d.size} members, quartiles "
                      + " ".join(f"{q:.2f}" for q in np.percentile(d, [0, 25, 50, 75, 100])))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dumps", nargs="+")
    ap.add_argument("--ends", nargs="+", default=["vehicle"])
    args = ap.parse_args(argv)
    for end in args.ends:
        report(collect(args.dumps, end), end)
    return 0


if __name__ == "__main__":
    sys.exit(main())
