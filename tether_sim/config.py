"""The whole run configuration: one frozen dataclass tree built from a parameter file.

Sections (YAML keys under ``tether_sim: ros__parameters:``): ``solver``, ``duration``, ``cable``,
``environment``, ``ship_end``, ``vehicle_end``, ``body``, ``dg``, ``hybrid``, ``initial``,
``motion``, ``snap``, ``node``, ``winch``, ``waves``, ``forecast``. ``io.schema`` derives the flat key list from these classes.
"""

from dataclasses import dataclass, field

from tether_sim.errors import ConfigError
from tether_sim.forecast.config import ForecastConfig
from tether_sim.physics.bodies import RigidBodyProperties
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.physics.motion import MotionConfig
from tether_sim.physics.snap import SnapConfig
from tether_sim.physics.waves import WaveConfig
from tether_sim.physics.winch import WinchConfig
from tether_sim.solvers.config import DGOptions, HybridOptions, InitialState
from tether_sim.spec import param


@dataclass(frozen=True)
class NodeOptions:
    """ROS node and offline-runner output options (topics are remappable too)."""

    output_rate: float = param(50.0, unit="Hz", doc="rate of the stepping timer and of the outputs", min=0.1, max=1000.0)
    output_points: int = param(41, doc="number of equally spaced output points along the cable", min=2, max=10000)
    shape_rate: float = param(0.0, unit="Hz", doc="the shape outputs (tether/state, tether/marker, tether/path) at most this often, every output_rate / shape_rate-th output (wrenches, poses, /tf, events stay at output_rate); 0: at every output. A lower rate saves the node the sampling, encoding and publishing of the shape on the other outputs", min=0.0, max=1000.0)
    visual_rate: float = param(10.0, unit="Hz", doc="the simulation node's visualisation outputs (tether/marker, tether/path and the /tf transforms) at most this often: every output_rate / visual_rate-th output, the messages a node at the full rate publishes at those stamps (tether/state, the wrenches, sim poses and events stay at output_rate); 0: at every output. RViz and Foxglove draw them at 10-20 Hz; the node's tick cost of building them at every output is in docs/node.md. The line-network node the same (its lines' marker and path, its bodies' transforms); the offline runner writes them at every output", min=0.0, max=1000.0)
    world_frame: str = param("map", doc="world frame id (ENU)")
    ship_frame: str = param("ship/base_link", doc="ship body frame id (FLU)")
    vehicle_frame: str = param("rov/base_link", doc="vehicle body frame id (FLU)")
    ship_attachment_frame: str = param("", doc="frame of the fairlead (child of ship_frame on /tf_static); empty: ship_frame with its last element replaced, ship/base_link -> ship/tether_sheave")
    vehicle_attachment_frame: str = param("", doc="frame of the tether attachment on the vehicle (child of vehicle_frame on /tf_static); empty: rov/base_link -> rov/tether_attach")
    frame_prefix: str = param("", doc="prepended to every frame the node names except world_frame (body, attachment and tether frames), e.g. 'rov1/' for each of several tethers (as robot_state_publisher's frame_prefix)")
    ship_attachment: tuple = param((0.0, 0.0, 0.0), unit="m", doc="fairlead position in the ship body frame")
    vehicle_attachment: tuple = param((0.0, 0.0, 0.0), unit="m", doc="tether attachment in the vehicle body frame")
    max_end_speed: float = param(20.0, unit="m/s", doc="a pose implying a faster end motion is rejected as a jump", min=0.0, max=1e4)
    input_timeout: float = param(1.0, unit="s", doc="an input silent this long is reported stale", min=0.0, max=1e4)
    max_substeps_per_tick: int = param(200000, doc="cap on substeps in one tick; beyond it the node falls behind (reported)", min=1, max=100000000)
    tick_budget: float = param(0.8, doc="fraction of the output period one tick may spend stepping (wall time); the rest carries over as lag", min=0.01, max=1e6)
    missed_outputs: int = param(5, doc="the simulation node's catch-up: a tick that comes this many output periods late or less (its process was not scheduled, the timer skipped the periods) first steps to and publishes the state of each period it skipped, each with its own stamp, so a subscriber gets one state per period through scheduling stalls; after a longer stall only the latest this many. 0: a late tick publishes its own instant only. Not while the simulation runs late or re-synchronises. The line-network node does the same", min=0, max=50)
    require_real_time: bool = param(True, doc="at start-up (wall clock only) the node times its solver in CPU time and refuses to start when it cannot keep up with the clock within tick_budget (the error names the measured real-time factor and a mesh that would); false: start anyway, late and marked degraded, re-synchronising")
    input_delay: float = param(0.2, unit="s", doc="the simulation runs this far behind the clock so pose inputs are interpolated, not extrapolated (>= 2 sample periods)", min=0.0, max=60.0)
    max_extrapolation: float = param(0.2, unit="s", doc="a pose input is extrapolated with its last velocity at most this long, then held", min=0.0, max=1e4)
    max_lag: float = param(1.0, unit="s", doc="simulation lag behind the node clock beyond this makes the node re-synchronise (cable state kept, ends blended onto their inputs, reported)", min=0.0, max=1e6)
    future_stamp_tolerance: float = param(0.25, unit="s", doc="a pose stamped later than the node clock plus this is rejected ('stamp in the future')", min=0.0, max=1e6)
    max_input_age: float = param(2.0, unit="s", doc="a pose stamped earlier than the node clock minus this is rejected ('stamp too old')", min=0.0, max=1e6)
    snapshot_interval: float = param(1.0, unit="s", doc="simulated time between recovery snapshots (restored after a solver divergence)", min=0.0, max=1e6)
    executor: str = param("single", doc="the executor that runs the node's timers and callbacks: single (rclpy's SingleThreadedExecutor, as rclpy.spin) or events (rclpy.experimental's EventsExecutor, in C++: ~1 ms less CPU per 50 Hz tick on a 2-core machine, BENCHMARKS.md); a line-network node always uses single", choices=("single", "events"))
    publish_tf: bool = param(True, doc="publish /tf (body frames of the ends, tether frames) and /tf_static (attachment frames)")
    tf_prescribed_ends: bool = param(True, doc="/tf also carries world -> body frame of pose-driven (prescribed) ends; false when the vehicle stack publishes those itself")
    tf_tether_frames: int = param(0, doc="frames <tf_tether_frame_prefix>/<k> on /tf at this many equally spaced points along the cable (x along the tangent)", min=0, max=1000)
    tf_tether_frame_prefix: str = param("tether", doc="name prefix of the frames along the cable")

    def __post_init__(self):
        names = {"node.world_frame": self.world_frame, "node.ship_frame": self.body_frame("ship"),
                 "node.vehicle_frame": self.body_frame("vehicle"),
                 "node.ship_attachment_frame": self.attachment_frame("ship"),
                 "node.vehicle_attachment_frame": self.attachment_frame("vehicle")}
        for key, name in names.items():
            if not name.strip("/") or any(c.isspace() for c in name):
                raise ConfigError(f"{key}: frame name {name!r} is empty or contains white space")
        seen = {}
        for key, name in names.items():  # a TF tree needs one frame per name
            if name.lstrip("/") in seen:
                raise ConfigError(f"{key} and {seen[name.lstrip('/')]} name the same frame {name!r}: "
                                  "body, attachment and world frames must differ")
            seen[name.lstrip("/")] = key

    def body_frame(self, end: str) -> str:
        """The body frame of ``end`` ('ship' or 'vehicle') as published: ``frame_prefix`` + ``<end>_frame``."""
        return self.frame_prefix + getattr(self, f"{end}_frame")

    def attachment_frame(self, end: str) -> str:
        """The attachment frame of ``end`` as published (``frame_prefix`` + ``<end>_attachment_frame``,
        or derived from the body frame: ``ship/base_link`` -> ``ship/tether_sheave``, ``rov/base_link``
        -> ``rov/tether_attach``, a name without ``/`` gets a suffix: ``boat`` -> ``boat_tether_sheave``)."""
        name = getattr(self, f"{end}_attachment_frame")
        if not name:
            body = getattr(self, f"{end}_frame")
            leaf = ATTACHMENT_LEAF[end]
            head, sep, _ = body.rpartition("/")
            name = f"{head}/{leaf}" if sep else f"{body}_{leaf}"
        return self.frame_prefix + name

    def tether_frame(self, k: int) -> str:
        """The k-th frame along the cable as published."""
        return f"{self.frame_prefix}{self.tf_tether_frame_prefix}/{k}"


ATTACHMENT_LEAF = {"ship": "tether_sheave", "vehicle": "tether_attach"}  # ros2-conventions note, 1.1


@dataclass(frozen=True)
class SimConfig:
    """Everything a run needs; the solvers receive this, never YAML or a Node."""

    solver: str = param("dg", doc="which solver: dg (Palm & Eskilsson) or hybrid (Goyal & Perkins)", choices=("dg", "hybrid"))
    duration: float = param(60.0, unit="s", doc="simulated duration of an offline run", min=0.0, max=1e7)
    work_limit: float = param(1000.0, unit="s", doc="a configuration whose estimated cost exceeds this many CPU seconds per simulated second is refused at load, naming the keys that set the substep (tether_sim/solvers/work.py: substep rule x mesh, CPU per update measured on the 2-core reference machine); 0 = no limit", min=0.0, max=1e12)
    cable: CableProperties = field(default_factory=CableProperties)
    environment: Environment = field(default_factory=Environment)
    ship_end: EndCondition = field(default_factory=EndCondition)
    vehicle_end: EndCondition = field(default_factory=lambda: EndCondition(kind="body", position=(0.0, 0.0, -200.0)))
    body: RigidBodyProperties = field(default_factory=RigidBodyProperties)
    dg: DGOptions = field(default_factory=DGOptions)
    hybrid: HybridOptions = field(default_factory=HybridOptions)
    initial: InitialState = field(default_factory=InitialState)
    motion: MotionConfig = field(default_factory=MotionConfig)
    snap: SnapConfig = field(default_factory=SnapConfig)
    node: NodeOptions = field(default_factory=NodeOptions)
    winch: WinchConfig = field(default_factory=WinchConfig)
    waves: WaveConfig = field(default_factory=WaveConfig)
    forecast: ForecastConfig = field(default_factory=ForecastConfig)
