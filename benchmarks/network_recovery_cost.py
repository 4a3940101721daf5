"""CPU cost of the network driver's recovery ticks on config/ropos_tms.yaml (docs/network.md,
"Recovery after a divergence"): a regular 20 ms tick, the tick that restores the network's snapshot,
and the tick that rebuilds the network from its statics (a second divergence before a newer snapshot).
The divergences are forced through the solver interface (tether_sim.network.faults, as the fault tests
do): one line's end motion thrown 1e30 m away for one tick, its DG state blows up.

Usage: PYTHONPATH=. nice -n 5 python benchmarks/network_recovery_cost.py [--repeat 3]
"""

import argparse
import sys
import time
from pathlib import Path


ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tether_sim.network.faults import throw_end_once  # noqa: E402
from tether_sim.network.params import load_network_files  # noqa: E402
from tether_sim.ros.network_driver import NetworkDriver  # noqa: E402


def once():
    spec, cfg = load_network_files([ROOT / "config" / "ropos_tms.yaml"])
    d = NetworkDriver(spec, cfg.node)
    d.start(0.0)
    now = 0.0
    for _ in range(75):
        now += 0.02
        d.tick(now)
    out = {}
    for what, line, end in (("regular", None, None), ("restore", "excursion", "ship"), ("rebuild", "tether", "vehicle")):
        if line is not None:
            throw_end_once(d.net.lines[line], end)
        now += 0.02
        c = time.process_time()
        r = d.tick(now)
        out[what] = time.process_time() - c
        assert (r.recovery or None) == {"regular": None, "restore": "snapshot", "rebuild": "static"}[what]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    runs = [once() for _ in range(args.repeat)]
    for what in runs[0]:
        print(f"{what:8s} tick: min {min(r[what] for r in runs):.4f} CPU s over {args.repeat} runs")


if __name__ == "__main__":
    main()
