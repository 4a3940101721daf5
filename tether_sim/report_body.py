"""The bodies of a line-network recording in tether-sim-report: the cage's motion and the forces on
it (no rclpy).

Read per body ``<body>`` (docs/network.md, "The node on a network"): ``/<body>/sim_pose`` (its
centre of gravity and orientation), ``/<body>/sim_twist`` and ``/<body>/sim_accel`` (velocity and
acceleration, world frame), ``/tether/<body>_wrench`` (the lines' force on it, body frame: turned
into the world frame with the pose of the same stamp), ``/<body>/hydro_wrench`` (drag, world frame),
``/<body>/wet_weight`` (latched); each line ending on it (``network.lines.<line>.from`` / ``.to``
of the line's description) gives its end tension there from ``/tether/<line>/state``; the vehicle's
force from ``/tether/vehicle_wrench``. A recording made before the twist, acceleration, drag and
weight topics existed gets the figures of what it holds (pose, line tensions, the lines' force).

Figures (PNG, in ``<out-dir>/<body>/``): ``motion.png`` (height of the centre of gravity, horizontal
offset from the first state, vertical velocity, vertical acceleration against time) and
``forces.png`` (each line's end tension at the body and the vehicle force; the vertical forces on
the body: the lines', the wet weight, the drag, and their sum, against time). ``report.json`` holds
the series' extremes; :class:`BodySeries` the series themselves (the report's result).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from tether_sim.io.mcap_log import read_messages, read_summary
from tether_sim.numerics.rotations import quaternion_matrix

POSE_TYPE = "geometry_msgs/msg/PoseStamped"
DESCRIPTION_TYPE = "tether_sim_msgs/msg/TetherDescription"
STATE_TYPE = "tether_sim_msgs/msg/TetherState"


@dataclass
class BodySeries:
    """One body's recorded series, times in s relative to the report's t0 (``t``: the pose stamps;
    every other series is taken at those stamps, None when its topic is not in the file)."""

    name: str
    t: np.ndarray
    position: np.ndarray                # (n, 3) centre of gravity, world, m
    orientation: np.ndarray             # (n, 4) quaternion x, y, z, w
    velocity: np.ndarray | None = None  # (n, 3) m/s, world
    acceleration: np.ndarray | None = None  # (n, 3) m/s^2, world
    line_force: np.ndarray | None = None    # (n, 3) the lines' summed force on the body, world, N
    drag: np.ndarray | None = None          # (n, 3) N, world
    wet_weight: float | None = None         # N (weight - buoyancy; acts along -z)
    end_tension: dict = field(default_factory=dict)  # "<line> (<end> end)" -> (t (k,), tension (k,)) at the body
    vehicle_force: tuple | None = None      # (t (k,), |F| (k,)) of /tether/vehicle_wrench

    def vertical_forces(self) -> dict:
        """name -> (n,) vertical force on the body, N: the lines', the wet weight, the drag (those
        recorded) and their sum ("net")."""
        out = {}
        if self.line_force is not None:
            out["lines"] = self.line_force[:, 2]
        if self.wet_weight is not None:
            out["wet weight"] = np.full(len(self.t), -self.wet_weight)
        if self.drag is not None:
            out["drag"] = self.drag[:, 2]
        if len(out) == 3:
            out["net"] = out["lines"] + out["wet weight"] + out["drag"]
        return out


def _seconds(stamp) -> float:
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def _key(stamp) -> int:
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def network_bodies(path) -> list:
    """The bodies of a network recording: the ``/<body>/sim_pose`` topics whose ``/tether/<body>_wrench``
    is recorded too (a single line's ``vehicle/sim_pose`` has no such wrench)."""
    topics = read_summary(Path(path)).topics
    return sorted(t.split("/")[1] for t, info in topics.items()
                  if info.type_name == POSE_TYPE and t.count("/") == 2 and t.endswith("/sim_pose")
                  and f"/tether/{t.split('/')[1]}_wrench" in topics)


def _vectors(rows, keys, field_a):
    """(n, 3) of the messages in ``rows`` ({stamp key: msg}) at ``keys`` (None if any is missing)."""
    if not rows or any(k not in rows for k in keys):
        return None
    return np.array([[getattr(field_a(rows[k]), c) for c in "xyz"] for k in keys], float)


def load_body(path, name: str, t0: float) -> BodySeries | None:
    """Body ``name`` of a network recording (module doc), times relative to ``t0``; None without its pose."""
    path = Path(path)
    topics = read_summary(path).topics
    want = {f"/{name}/sim_pose", f"/{name}/sim_twist", f"/{name}/sim_accel", f"/tether/{name}_wrench",
            f"/{name}/hydro_wrench", f"/{name}/wet_weight", "/tether/vehicle_wrench"}
    descriptions = [t for t, info in topics.items() if info.type_name == DESCRIPTION_TYPE]
    rows = {t: {} for t in want}
    ends = {}  # line -> "ship" / "vehicle" end on this body
    for topic, _, _, msg in read_messages(path, [t for t in (*want, *descriptions) if t in topics]):
        if topic in descriptions:
            line = topic.split("/")[2]
            for kv in msg.parameters:
                if kv.key in (f"network.lines.{line}.from", f"network.lines.{line}.to") and kv.value == name:
                    ends[line] = "ship" if kv.key.endswith(".from") else "vehicle"
        else:
            rows[topic][_key(msg.header.stamp)] = msg
    poses = rows[f"/{name}/sim_pose"]
    if not poses:
        return None
    keys = sorted(poses)
    t = np.array([k * 1e-9 for k in keys]) - t0
    position = _vectors(poses, keys, lambda m: m.pose.position)
    q = np.array([[getattr(poses[k].pose.orientation, c) for c in "xyzw"] for k in keys], float)
    series = BodySeries(name, t, position, q,
                        velocity=_vectors(rows[f"/{name}/sim_twist"], keys, lambda m: m.twist.linear),
                        acceleration=_vectors(rows[f"/{name}/sim_accel"], keys, lambda m: m.accel.linear),
                        drag=_vectors(rows[f"/{name}/hydro_wrench"], keys, lambda m: m.wrench.force))
    body_frame = _vectors(rows[f"/tether/{name}_wrench"], keys, lambda m: m.wrench.force)
    if body_frame is not None:  # the lines' force, body frame -> world with the pose of the same stamp
        series.line_force = np.einsum("nij,nj->ni", np.array([quaternion_matrix(x) for x in q]), body_frame)
    weights = rows[f"/{name}/wet_weight"]
    if weights:
        series.wet_weight = -float(weights[max(weights)].wrench.force.z)
    vehicle = rows["/tether/vehicle_wrench"]
    if vehicle:
        vk = sorted(vehicle)
        f = _vectors(vehicle, vk, lambda m: m.wrench.force)
        series.vehicle_force = (np.array([k * 1e-9 for k in vk]) - t0, np.linalg.norm(f, axis=1))
    if ends:
        states = {line: ([], []) for line in ends}
        for topic, _, _, msg in read_messages(path, [f"/tether/{line}/state" for line in ends]):
            line = topic.split("/")[2]
            states[line][0].append(_seconds(msg.header.stamp) - t0)
            states[line][1].append(msg.ship_end_tension if ends[line] == "ship" else msg.vehicle_end_tension)
        for line, (tt, tension) in states.items():
            order = np.argsort(tt, kind="stable")
            series.end_tension[f"{line} ({'s = 0' if ends[line] == 'ship' else 's = L'} end)"] = (
                np.asarray(tt)[order], np.asarray(tension, float)[order])
    return series


def _extremes(x) -> dict:
    return {"min": float(np.min(x)), "max": float(np.max(x))}


def body_summary(b: BodySeries) -> dict:
    """The extremes of the recorded series (report.json, report.md), SI units in the key names."""
    out = {"body": b.name, "states": int(len(b.t)), "z_m": _extremes(b.position[:, 2]),
           "horizontal_offset_m": float(np.max(np.hypot(*(b.position[:, :2] - b.position[0, :2]).T)))}
    if b.velocity is not None:
        out["vertical_velocity_m_s"] = _extremes(b.velocity[:, 2])
    if b.acceleration is not None:
        out["vertical_acceleration_m_s2"] = _extremes(b.acceleration[:, 2])
    if b.wet_weight is not None:
        out["wet_weight_N"] = b.wet_weight
    out["end_tension_N"] = {k: _extremes(v) for k, (_, v) in b.end_tension.items()}
    out["vertical_force_N"] = {k: _extremes(v) for k, v in b.vertical_forces().items()}
    if b.vehicle_force is not None:
        out["vehicle_force_N"] = _extremes(b.vehicle_force[1])
    return out


def body_markdown(b: BodySeries, summary: dict, figures: dict, base: Path) -> list:
    """Markdown lines of one body's section of the network report."""
    z = summary["z_m"]
    lines = ["", f"## Body `{b.name}`", "",
             f"Centre of gravity z = {z['min']:.3f} to {z['max']:.3f} m (up; the first state {b.position[0, 2]:.3f} m), "
             f"largest horizontal offset from the first state {summary['horizontal_offset_m']:.3f} m."]
    if "vertical_velocity_m_s" in summary:
        v, a = summary["vertical_velocity_m_s"], summary.get("vertical_acceleration_m_s2")
        lines.append(f"Vertical velocity {v['min']:.3f} to {v['max']:.3f} m/s"
                     + (f", vertical acceleration {a['min']:.3f} to {a['max']:.3f} m/s^2." if a else "."))
    if b.wet_weight is not None:
        lines.append(f"Wet weight (weight - buoyancy) {b.wet_weight:.1f} N.")
    lines += ["", "| force at the output instants | min [N] | max [N] |", "|---|---|---|"]
    for k, e in summary["end_tension_N"].items():
        lines.append(f"| {k} tension at the body | {e['min']:.1f} | {e['max']:.1f} |")
    for k, e in summary["vertical_force_N"].items():
        lines.append(f"| vertical force: {k} | {e['min']:.1f} | {e['max']:.1f} |")
    if "vehicle_force_N" in summary:
        e = summary["vehicle_force_N"]
        lines.append(f"| vehicle force \\|F\\| (tether/vehicle_wrench) | {e['min']:.1f} | {e['max']:.1f} |")
    lines += [""] + [f"- {k}: `{Path(p).relative_to(base)}`" for k, p in figures.items()]
    return lines


def body_figures(b: BodySeries, out_dir: Path, time_label: str) -> dict:
    """Write ``motion.png`` and ``forces.png`` of body ``b`` into ``out_dir``; returns {name: path}."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    panels = [("z", "centre of gravity z (up) [m]"), ("xy", "horizontal offset from the first state [m]")]
    if b.velocity is not None:
        panels.append(("v", "vertical velocity [m/s]"))
    if b.acceleration is not None:
        panels.append(("a", "vertical acceleration [m/s²]"))
    fig, axes = plt.subplots(len(panels), 1, figsize=(10, 2.2 * len(panels) + 1), sharex=True, constrained_layout=True)
    for ax, (kind, label) in zip(axes, panels):
        if kind == "z":
            ax.plot(b.t, b.position[:, 2], color="tab:blue", lw=1.2)
        elif kind == "xy":
            for c, name, colour in ((0, "x (east)", "tab:green"), (1, "y (north)", "tab:purple")):
                ax.plot(b.t, b.position[:, c] - b.position[0, c], color=colour, lw=1.2, label=name)
            ax.legend(loc="upper right", fontsize=8)
        elif kind == "v":
            ax.plot(b.t, b.velocity[:, 2], color="tab:orange", lw=1.2)
        else:
            ax.plot(b.t, b.acceleration[:, 2], color="tab:red", lw=1.0)
        ax.set_ylabel(label, fontsize=9)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel(f"{time_label} [s]")
    axes[0].set_title(f"Body {b.name}: motion of its centre of gravity (world frame, ENU)")
    motion = out_dir / "motion.png"
    fig.savefig(motion, dpi=110)
    plt.close(fig)

    vertical = b.vertical_forces()
    fig, axes = plt.subplots(2 if vertical else 1, 1, figsize=(10, 7 if vertical else 4), sharex=True,
                             constrained_layout=True, squeeze=False)
    ax = axes[0, 0]
    for k, (tt, tension) in b.end_tension.items():
        ax.plot(tt, tension / 1e3, lw=1.2, label=f"{k} tension at {b.name}")
    if b.vehicle_force is not None:
        ax.plot(b.vehicle_force[0], b.vehicle_force[1] / 1e3, color="k", lw=1.0, ls="--",
                label="|force| on the vehicle (tether/vehicle_wrench)")
    ax.set_ylabel("force [kN]")
    ax.set_yscale("symlog", linthresh=0.1)
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"Body {b.name}: the lines' end tensions at it and the vehicle force")
    if vertical:
        ax = axes[1, 0]
        styles = {"lines": ("tab:blue", "-"), "wet weight": ("tab:brown", ":"), "drag": ("tab:green", "-"),
                  "net": ("k", "-")}
        for k, f in vertical.items():
            colour, ls = styles[k]
            ax.plot(b.t, f / 1e3, color=colour, ls=ls, lw=1.6 if k == "net" else 1.1, label=k)
        ax.set_ylabel("vertical force on the body [kN]")
        ax.grid(alpha=0.3)
        ax.legend(loc="best", fontsize=8)
        ax.set_title("vertical forces (up +): lines (tether/<body>_wrench in the world frame), wet weight, drag")
    axes[-1, 0].set_xlabel(f"{time_label} [s]")
    forces = out_dir / "forces.png"
    fig.savefig(forces, dpi=110)
    plt.close(fig)
    return {"motion": motion, "forces": forces}
