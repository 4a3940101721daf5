"""Every numeric parameter at the ends of its documented range, through the offline runner.

For each float/int key of the schema, the ROPOS L = 200 m file on a small manual mesh (N = 3, P = 2,
0.3 s of a 1 m heave) is run with the key at its documented minimum and maximum. A value is fine
when the loader refuses it with a ConfigError (a clear message) or the run ends with finite states and
no numpy warning; anything else (another exception, a numpy warning, non-finite output) is printed.

    .venv/bin/python tools/audit_param_ranges.py [--keys cable.EA dg.cfl ...] [--solver dg|hybrid]

With ``--loader``: every key (numeric or not) with values outside its range, non-finite and of the
wrong type through the loader alone (no run): each must end in a ConfigError that names the key.
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


LIMIT_S = 20


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


def bad_values(key) -> list:
    """(label, value) the loader must refuse for ``key``: outside the documented range, non-finite,
    of the wrong type."""
    out = []
    if key.kind in ("float", "int"):
        span = max(abs(key.max or 0.0), abs(key.min or 0.0), 1.0)
        if key.min is not None and math.isfinite(key.min):
            below = key.min - max(1e-6 * span, 1.0 if key.kind == "int" else 1e-9 * span)
            out.append(("below min", int(math.floor(below)) if key.kind == "int" else below))
        if key.max is not None and math.isfinite(key.max):
            above = key.max + max(1e-6 * span, 1.0 if key.kind == "int" else 1e-9 * span)
            out.append(("above max", int(math.ceil(above)) if key.kind == "int" else above))
        out += [("nan", math.nan), ("inf", math.inf), ("-inf", -math.inf), ("text", "abc"), ("list", [1.0, 2.0]),
                ("bool", True), ("null", None)]
        if key.kind == "int":
            out.append(("fraction", 2.5))
    elif key.kind == "bool":
        out += [("text", "maybe"), ("number", 2), ("list", [True]), ("null", None)]
    elif key.kind == "str":
        out += [("number", 3.0), ("list", ["a"]), ("null", None)]
        if key.choices:
            out.append(("not a choice", "no-such-choice"))
    elif key.kind in ("float_array", "str_array"):
        out += [("scalar", 1.0), ("text", "abc"), ("null", None)]
        if key.kind == "float_array":
            out += [("nan element", [math.nan, 0.0, 0.0]), ("text element", ["a", 0.0, 0.0])]
    return out


def audit_loader(names, base_file, out=print) -> list:
    """Every bad value of every key through the loader (the file's keys plus the value): it must
    end in a ConfigError that names the key; any other exception or an acceptance is a fault
    (printed with ``out``). Returns the faults as (key, label, value, verdict, detail)."""
    from tether_sim.io.params import from_flat, read_param_file

    keys = key_map()
    base = {**read_param_file(base_file), **BASE}
    faults = []
    for name in names:
        for label, value in bad_values(keys[name]):
            try:
                from_flat({**base, name: value}, where=str(base_file))
                verdict, detail = "ACCEPTED", ""
            except ConfigError as exc:
                verdict, detail = ("refused", "") if name in str(exc) else ("KEY NOT NAMED", str(exc)[:120])
            except Exception as exc:  # noqa: BLE001 - what the audit looks for
                verdict, detail = "CRASH", f"{type(exc).__name__}: {str(exc)[:120]}"
            if verdict != "refused":
                faults.append((name, label, value, verdict, detail))
                out(f"{name:36s} {label:14s} {value!r:>14.14} {verdict:14s} {detail}")
    out(f"{len(faults)} fault(s) over {len(names)} keys")
    return faults


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--keys", nargs="*")
    ap.add_argument("--solver", default="dg")
    ap.add_argument("--loader", action="store_true", help="every key (default: all) with values outside its range "
                    "and of the wrong type through the loader only: each must be a ConfigError naming the key")
    args = ap.parse_args(argv)
    if args.loader:
        return 1 if audit_loader(args.keys or list(key_map()), ROOT / "config" / "ropos_L200.yaml") else 0
    signal.signal(signal.SIGALRM, _alarm)
    keys = key_map()
    names = args.keys or [k for k, v in keys.items() if v.kind in ("float", "int")]
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
