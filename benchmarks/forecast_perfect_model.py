"""Perfect-model check of a dumped forecast skill run (``forecast_skill.py --dump``).

Each forecast is scored on its own (per-forecast rule), against the real run and against a perfect model:

- alarm: a forecast with probability p >= 0.5 whose predicted time is the median of its snapping members'
  snap times; false when no snap of the truth lies within +-1.5 s of that time;
- warned: a snap of the truth at t with stamp + 5 s <= t <= stamp + horizon is warned by that forecast when
  the forecast is an alarm and |predicted - t| <= 1.5 s;
- real: the truth is the run's snaps at that end, the forecast's probability and members as dumped;
- perfect model: each of the M members in turn is the truth (its snap, or none) and the other M - 1 are the
  forecast (p = snapping others / (M - 1)); each held-out member weighs 1 / M.

A perfect model's members are statistically indistinguishable from the truth, so its false alarms and warned
fraction are the best this ensemble size and forecast error allow under the rule. The per-forecast warned
fraction is not the skill benchmark's (a snap warned by any earlier forecast): the perfect model has no one
truth across forecasts, so both are scored per forecast here.

Usage: forecast_perfect_model.py DUMP.json [...]
"""
import json
import statistics
import sys
from dataclasses import dataclass

LEAD, TOLERANCE, THRESHOLD = 5.0, 1.5, 0.5


@dataclass
class Counts:
    alarms: float = 0.0
    false: float = 0.0
    snaps: float = 0.0  # (forecast, truth snap) pairs stamp + lead <= t <= stamp + horizon
    warned: float = 0.0

    def add(self, other, weight=1.0):
        self.alarms += weight * other.alarms
        self.false += weight * other.false
        self.snaps += weight * other.snaps
        self.warned += weight * other.warned


def score_one(stamp, horizon, p, member_snaps, truth, *, lead=LEAD, tolerance=TOLERANCE, threshold=THRESHOLD):
    """Counts of one forecast (``stamp``, ``horizon``, probability ``p``, its snapping members' snap times
    ``member_snaps``) against the truth's snap times ``truth``."""
    c = Counts()
    alarm = p >= threshold and len(member_snaps) > 0
    predicted = statistics.median(member_snaps) if alarm else None
    if alarm:
        c.alarms = 1
        c.false = 0 if any(abs(t - predicted) <= tolerance for t in truth) else 1
    for t in truth:
        if stamp + lead <= t <= stamp + horizon:
            c.snaps += 1
            c.warned += 1 if alarm and abs(t - predicted) <= tolerance else 0
    return c


def score_real(forecasts, snaps, members, horizon, **kw):
    """Per-forecast counts of dumped ``forecasts`` ((end, stamp, p, ..., [[snap time, peak], ...]) rows of one
    end) against the run's snap times ``snaps`` at that end."""
    total = Counts()
    for f in forecasts:
        total.add(score_one(f[1], horizon, f[2], [s[0] for s in f[5]], snaps, **kw))
    return total


def score_perfect_model(forecasts, members, horizon, **kw):
    """Per-forecast counts with each member in turn the truth against the other ``members`` - 1."""
    total = Counts()
    for f in forecasts:
        times = [s[0] for s in f[5]]
        for k in range(members):
            if k < len(times):
                truth, others = [times[k]], times[:k] + times[k + 1:]
            else:
                truth, others = [], times
            total.add(score_one(f[1], horizon, len(others) / (members - 1), others, truth, **kw), 1.0 / members)
    return total


def main(paths):
    for path in paths:
        d = json.load(open(path))
        a = d["args"]
        pooled = {}
        for r in d["runs"]:
            for end in ("ship", "vehicle"):
                fcs = [x for x in r["forecasts"]["known_sea"] if x[0] == end]
                if not fcs:
                    continue
                real = score_real(fcs, [s[1] for s in r["snaps"] if s[0] == end], a["members"], a["horizon"])
                pm = score_perfect_model(fcs, a["members"], a["horizon"])
                per10 = 10.0 / a["minutes"]
                both = pooled.setdefault(end, [Counts(), Counts(), 0.0])
                both[0].add(real)
                both[1].add(pm)
                both[2] += a["minutes"]
                print(f"{path.split('/')[-1]} seed {r['seed']} {end}: alarms real {real.alarms:.0f} false {real.false:.0f}, "
                      f"perfect model {pm.alarms:.1f} false {pm.false:.1f}; false per 10 min real {real.false * per10:.2f} "
                      f"pm {pm.false * per10:.2f}; warned (per forecast, >= 5 s ahead) real {real.warned:.0f}/{real.snaps:.0f} "
                      f"= {real.warned / max(real.snaps, 1e-9):.3f}, pm {pm.warned:.2f}/{pm.snaps:.2f} "
                      f"= {pm.warned / max(pm.snaps, 1e-9):.3f}")

        for end, (real, pm, minutes) in pooled.items():
            print(f"{path.split('/')[-1]} pooled {end} ({minutes:g} min): false per 10 min real {real.false * 10 / minutes:.2f} "
                  f"pm {pm.false * 10 / minutes:.2f}; warned per forecast real {real.warned:.0f}/{real.snaps:.0f} = "
                  f"{real.warned / max(real.snaps, 1e-9):.3f}, pm {pm.warned:.3f}/{pm.snaps:.3f} = {pm.warned / max(pm.snaps, 1e-9):.3f}")


if __name__ == "__main__":
    main(sys.argv[1:])
