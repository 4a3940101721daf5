"""One study case: resolve its configuration, key it, run it through ``tether-sim-offline``'s code path.

The key of a case is a hash of its full resolved configuration (every parameter, after the base file,
the study's overrides and the public loader's own resolution) and of the code version (package
version + a hash of the tether_sim source tree). A case whose key is already in the results is not
run again; a change of any parameter or of any source file of the package runs it again.

:func:`run_task` is what a worker executes (a local process or a Dask worker). It never raises: a
failing case comes back as a row with ``status = "failed"`` and its error.
"""

import hashlib
import importlib.metadata
import json
import math
import os
import platform
import subprocess
import time
import traceback

import numpy as np
from functools import lru_cache
from pathlib import Path

import tether_sim
from tether_sim.io.params import ParamFileOverlay, from_flat, load_config, to_flat
from tether_sim.solvers.work import run_estimate
from tether_sim.solvers.base import LOAD_F
from tether_sim.studies.stats import TensionTap, end_statistics, event_rows

# Columns that depend on the machine and the moment, not on the physics (left out of comparisons).
TIMING_COLUMNS = ("wall_s", "cpu_s", "rtf", "worker", "nth_in_process", "finished_utc", "git_describe")


@lru_cache(maxsize=1)
def code_version() -> dict:
    """Package version, hash of every ``tether_sim/**/*.py`` (path and content), ``git describe``."""
    root = Path(tether_sim.__file__).resolve().parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    try:
        version = importlib.metadata.version("tether_sim")
    except importlib.metadata.PackageNotFoundError:
        version = "0+unknown"
    try:
        git = subprocess.run(["git", "describe", "--always", "--dirty", "--tags"], cwd=root, capture_output=True,
                             text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        git = ""
    return {"version": version, "source_hash": digest.hexdigest()[:16], "git_describe": git}


def _jsonable(value):
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    return value


def case_key(config, code: dict) -> str:
    """Hash of the resolved configuration and the code version (20 hex digits)."""
    flat = {k: _jsonable(v) for k, v in sorted(to_flat(config).items())}
    text = json.dumps({"config": flat, "code": [code["version"], code["source_hash"]]}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


DRIVE_KEYS = ("motion.", "duration", "waves.")  # a network case's drive of its ship point (not network-file keys)


def _network_case(case, code, base_files):
    """(network file's flat parameters with the case's network / node overrides, the drive's flat
    keys, the key) of a case whose base is a network file, or None for a single-line base."""
    from tether_sim.io.params import read_param_file
    from tether_sim.network.params import is_network

    cache = base_files if base_files is not None else {}
    flat = cache.get(("flat", case.base))
    if flat is None:  # each base file read once (make_task's ParamFileOverlay takes it from here)
        flat = cache[("flat", case.base)] = read_param_file(case.base)
        cache[("network", case.base)] = is_network(flat)
    if not cache[("network", case.base)]:
        return None
    drive = {k: v for k, v in case.overrides.items() if k.startswith(DRIVE_KEYS)}
    network = {**flat, **{k: v for k, v in case.overrides.items() if k not in drive}}
    text = json.dumps({"network": {k: _jsonable(v) for k, v in sorted(network.items())},
                       "drive": {k: _jsonable(v) for k, v in sorted(to_flat(from_flat(drive, where=str(case.base))).items())},
                       "code": [code["version"], code["source_hash"]]}, sort_keys=True, default=str)
    return network, drive, hashlib.sha256(text.encode()).hexdigest()[:20]


def make_task(case, study, code, out_dir, base_files=None) -> dict:
    """Everything a worker needs for one case (plain data: it travels to other machines).
    ``base_files`` ({path: ParamFileOverlay}) keeps each base file read once over the cases of a study.
    A network base file (docs/network.md) gives a network case: its ``motion.*`` / ``duration``
    keys drive the network's ``ship`` point, every other key is the network file's (:func:`run_task`)."""
    network = _network_case(case, code, base_files)
    if network is not None:
        flat, drive, key = network
        mcap = str(Path(out_dir) / "mcap" / f"case{case.index:05d}_{key}.mcap") if study.keep.get("mcap") else None
        return {"key": key, "index": case.index, "study": study.name, "variables": dict(case.variables),
                "base": str(case.base), "overrides": dict(case.overrides), "source_hash": code["source_hash"],
                "mcap": mcap, "events": bool(study.keep.get("events", True)), "network": True,
                "expected_cpu": math.nan}  # (no cost model of a network yet)
    if base_files is None:
        config = load_config(case.base, case.overrides)
    else:
        if case.base not in base_files:
            base_files[case.base] = ParamFileOverlay(case.base, flat=base_files[("flat", case.base)])
        config = base_files[case.base](case.overrides)
    key = case_key(config, code)
    mcap = str(Path(out_dir) / "mcap" / f"case{case.index:05d}_{key}.mcap") if study.keep.get("mcap") else None
    return {"key": key, "index": case.index, "study": study.name, "variables": dict(case.variables),
            "base": str(case.base), "overrides": dict(case.overrides), "source_hash": code["source_hash"],
            "mcap": mcap, "events": bool(study.keep.get("events", True)),
            "expected_cpu": run_estimate(config, config.duration)[0]}


def _resolution(tap, config) -> dict:
    """N, P, cfl (DG) or segments and time step (hybrid) of the solver that ran, and its substep."""
    solver = tap.solvers[0] if tap.solvers else None
    cfg = getattr(solver, "config", config)
    row = {"solver": cfg.solver, "dg_N": math.nan, "dg_P": math.nan, "dg_cfl": math.nan, "dg_damping": "",
           "hybrid_segments": math.nan, "hybrid_dt_s": math.nan, "dt_start_s": math.nan}
    if solver is not None and cfg.solver == "dg":
        row.update(dg_N=int(getattr(solver, "N", cfg.dg.n_elements)), dg_P=int(getattr(solver, "P", cfg.dg.order)),
                   dg_cfl=float(cfg.dg.cfl), dg_damping=str(cfg.dg.damping))
    elif solver is not None:
        row.update(hybrid_segments=int(cfg.hybrid.n_segments), hybrid_dt_s=float(cfg.hybrid.time_step))
    if solver is not None:
        try:
            row["dt_start_s"] = float(solver.stable_time_step())
        except Exception:  # noqa: BLE001 - a diagnostic only
            pass
    return row


def fairlead_motion(motion) -> tuple:
    """(amplitude m, frequency Hz) of the fairlead motion: those of a circle (its radius) or a heave sine;
    for a sum of sines the amplitude of one sine of equal variance, sqrt(sum a_i^2), and the
    variance-weighted mean frequency sum a_i^2 f_i / sum a_i^2; (0, 0) at rest; NaN for a record."""
    if motion.kind in ("circle", "heave"):
        return float(motion.amplitude), float(motion.frequency)
    if motion.kind == "sines" and motion.sine_amplitudes:
        a2 = [a * a for a in motion.sine_amplitudes]
        total = sum(a2)
        f = sum(w * f for w, f in zip(a2, motion.sine_frequencies)) / total if total > 0 else 0.0
        return math.sqrt(total), float(f)
    if motion.kind in ("none", "sines"):
        return 0.0, 0.0
    return math.nan, math.nan


def _config_columns(config) -> dict:
    """The resolved quantities the report plots against, whatever the study called its variables."""
    amplitude, frequency = fairlead_motion(config.motion)
    return {"cable_length_m": float(config.cable.length), "cable_EI_Nm2": float(config.cable.EI),
            "motion.kind": str(config.motion.kind), "fairlead_amplitude_m": amplitude,
            "fairlead_frequency_Hz": frequency, "duration_s": float(config.duration)}


_CASES_IN_PROCESS = [0]


class NetworkTap:
    """Per line, the extremes of both end tensions over every substep after the start (the
    :class:`TensionTap` of a network run, ``run_network_offline(tap=...)``), and per point the
    largest |force| of the lines on it at the ticks (the node's ``tether/<point>_wrench`` instants)."""

    def __init__(self):
        self.lines = {}  # line -> TensionTap (its take() and extremes)
        self.point_force = {}  # point -> largest |F|, N

    def __call__(self, net, out):
        for line, o in out.items():
            tap = self.lines.setdefault(line, TensionTap(None))
            s = o["samples"]
            tap.take(s[0], s[1], s[2])
        for point in net.points:
            f = [0.0, 0.0, 0.0]
            for row in net.load_rows(point):
                for c in range(3):
                    f[c] += row[LOAD_F + c]
            self.point_force[point] = max(self.point_force.get(point, 0.0), math.sqrt(sum(x * x for x in f)))


def _network_columns(spec, drive) -> dict:
    amplitude, frequency = fairlead_motion(drive.motion)
    row = {"network": True, "motion.kind": str(drive.motion.kind), "fairlead_amplitude_m": amplitude,
           "fairlead_frequency_Hz": frequency, "duration_s": float(drive.duration)}
    for name, line in spec.lines.items():
        row[f"{name}.length_m"] = float(line.config.cable.length)
        row[f"{name}.solver"] = str(line.config.solver)
        row[f"{name}.from"], row[f"{name}.to"] = (str(e.target) for e in line.ends)  # point, body or free
    for name, body in spec.bodies.items():
        row[f"{name}.mass_kg"] = float(body.props.mass)
    return row


def run_network_task(task: dict, row: dict) -> list:
    """Run a network case (make_task's ``network``) into ``row``: per line ``<line>.<end>_<statistic>``
    (stats.end_statistics of that line's two ends: ship = its s = 0 end, vehicle = its s = L end),
    per point ``<point>_force_max_N``; returns the event rows (location ``<line>/<end>``)."""
    from dataclasses import replace

    from tether_sim.io.params import read_param_file
    from tether_sim.network.params import load_network
    from tether_sim.physics.motion import build_motion
    from tether_sim.physics.waves import wave_components
    from tether_sim.ros.end_commands import MotionSource
    from tether_sim.ros.network_offline import run_network_offline

    drive_keys = {k: v for k, v in task["overrides"].items() if k.startswith(DRIVE_KEYS)}
    flat = {**read_param_file(task["base"]), **{k: v for k, v in task["overrides"].items() if k not in drive_keys}}
    spec, node_config = load_network(flat, where=task["base"])
    drive = from_flat(drive_keys, where=f"{task['base']} (the study's drive)")
    row.update(_network_columns(spec, drive))
    sources = {}
    ship = spec.points.get("ship")
    if ship is not None and ship.kind == "prescribed" and drive.motion.kind != "none":
        sources["ship"] = MotionSource(build_motion(drive.motion, np.asarray(ship.position, float), wave_components(drive)))
    tap = NetworkTap()
    if task["mcap"]:
        Path(task["mcap"]).parent.mkdir(parents=True, exist_ok=True)
    summary = run_network_offline(spec, node_config, task["mcap"], duration=drive.duration, progress=False,
                                  sources=sources, tap=tap)
    if summary["failed"]:
        raise RuntimeError(f"the network simulation stopped at {summary['duration']:.6g} s: {summary['failed']}")
    for line in spec.lines:
        events = [replace(ev, location=ev.location.rsplit("/", 1)[-1]) for ln, ev in summary["events"] if ln == line]
        stats = end_statistics(events, summary["static_tensions"][line], tap.lines.get(line, TensionTap(None)))
        row.update({f"{line}.{k}": v for k, v in stats.items()})
    row.update({f"{p}_force_max_N": f for p, f in tap.point_force.items()})
    row.update({"sim_s": float(summary["duration"]), "substeps": int(sum(t.samples for t in tap.lines.values())),
                "divergences": 0, "mcap": task["mcap"] or ""})
    return event_rows(ev for _, ev in summary["events"])


def run_task(task: dict) -> dict:
    """Run one case (see the module docstring); returns {"row": {...}, "events": [...]}."""
    wall0, cpu0 = time.perf_counter(), time.thread_time()
    row = {"key": task["key"], "index": task["index"], "study": task["study"], "status": "failed", "error": "",
           **{f"var.{k}": v for k, v in task["variables"].items()}}
    events = []
    try:
        code = code_version()
        if code["source_hash"] != task["source_hash"]:
            raise RuntimeError(f"this worker runs tether_sim source {code['source_hash']}, the study was keyed with "
                               f"{task['source_hash']}: install the same code on every worker")
        row.update(code=f"{code['version']}+{code['source_hash']}", git_describe=code["git_describe"])
        if task.get("network"):
            found = run_network_task(task, row)
            if task["events"]:
                events = [{"key": task["key"], **e} for e in found]
        else:
            config = load_config(task["base"], task["overrides"])
            row.update(_config_columns(config))
            from tether_sim.ros.offline import run_offline  # the tether-sim-offline code path (imports rclpy)
            from tether_sim.solvers.factory import build_solver

            tap = TensionTap(build_solver)
            if task["mcap"]:
                Path(task["mcap"]).parent.mkdir(parents=True, exist_ok=True)
            summary = run_offline(config, task["mcap"], progress=False, solver_factory=tap)
            row.update(_resolution(tap, config))
            row.update(end_statistics(summary["events"], summary["static_tensions"], tap))
            row.update({"sim_s": float(summary["duration"]), "substeps": int(tap.samples),
                        "divergences": int(summary["divergences"]), "mcap": task["mcap"] or ""})
            if task["events"]:
                events = [{"key": task["key"], **e} for e in event_rows(summary["events"])]
        row["status"] = "ok"
    except Exception as exc:  # noqa: BLE001 - a failed case is a row of the table, not the end of the study
        tb = traceback.extract_tb(exc.__traceback__)
        where = f" (at {Path(tb[-1].filename).name}:{tb[-1].lineno})" if tb else ""
        row["error"] = f"{type(exc).__name__}: {exc}{where}"
    _CASES_IN_PROCESS[0] += 1
    wall = time.perf_counter() - wall0
    row.update({"wall_s": wall, "cpu_s": time.thread_time() - cpu0,
                "rtf": row.get("sim_s", math.nan) / wall if wall > 0 else math.nan,
                "worker": f"{platform.node()}:{os.getpid()}",
                "nth_in_process": _CASES_IN_PROCESS[0],  # 1 = first: its times include loading compiled kernels
                "finished_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())})
    return {"row": row, "events": events}
