"""Every numeric parameter at the ends of its documented range, through the offline runner.

For each float/int key of the schema, the ROPOS L = 200 m file on a small manual mesh (N = 3, P = 2,
0.3 s of a 1 m heave) is run with the key at its documented minimum and maximum. A value is fine
when the loader refuses it with a ConfigError (a clear message) or the run ends with finite states and
no numpy warning; anything else (another exception, a numpy warning, non-finite output) is printed.

    .venv/bin/python tools/audit_param_ranges.py [--keys cable.EA dg.cfl ...] [--solver dg|hybrid]
"""

import argparse
import math
import signal
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from tether_sim.errors import ConfigError
from tether_sim.io.params import load_config
from tether_sim.io.schema import key_map

ROOT = Path(__file__).resolve().parents[1]
BASE = {"dg.resolution": "manual", "dg.n_elements": 3, "dg.order": 2, "duration": 0.3,
        "motion.kind": "heave", "motion.amplitude": 1.0, "motion.frequency": 0.2, "motion.ramp_time": 0.1,
        "node.output_rate": 20.0, "node.output_points": 5}


LIMIT_S = 30


class _Slow(Exception):
    pass


def _alarm(signum, frame):
    raise _Slow


def _try(key, value, solver):
    from tether_sim.ros.offline import run_offline

    overrides = {**BASE, "solver": solver, key: value}
    try:
        config = load_config(ROOT / "config" / "ropos_L200.yaml", overrides)
    except ConfigError as exc:
        return "refused", str(exc).split(": ", 1)[-1][:100]
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        signal.alarm(LIMIT_S)
        try:
            summary = run_offline(config, None, progress=False)
        except ConfigError as exc:
            return "refused at build", str(exc)[:100]
        except _Slow:
            return "slow", f"not done in {LIMIT_S} s (many substeps; not a fault in itself)"
        except Exception as exc:  # noqa: BLE001 - what the audit looks for
            return "BROKEN", f"{type(exc).__name__}: {str(exc)[:100]}"
        finally:
            signal.alarm(0)
    tensions = np.asarray(summary.get("static_tensions", [0.0]), float)
    if not np.all(np.isfinite(tensions)):
        return "BROKEN", f"non-finite static tensions {tensions}"
    return "ran", ""


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--keys", nargs="*")
    ap.add_argument("--solver", default="dg")
    args = ap.parse_args(argv)
    signal.signal(signal.SIGALRM, _alarm)
    keys = key_map()
    names = args.keys or [k for k, v in keys.items() if v.kind in ("float", "int")
                          and k.split(".")[0] in ("cable", "environment", "body", "dg", "hybrid", "snap")]
    broken = 0
    for name in names:
        key = keys[name]
        for value in (key.min, key.max):
            if value is None or (isinstance(value, float) and not math.isfinite(value)):
                continue
            t0 = time.perf_counter()
            verdict, detail = _try(name, int(value) if key.kind == "int" else float(value), args.solver)
            broken += verdict == "BROKEN"
            print(f"{name:36s} {value!r:>10} {verdict:16s} {time.perf_counter() - t0:5.1f} s  {detail}", flush=True)
    print(f"{broken} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
