"""Launch the tether simulation node, optionally with the MCAP recorder and a replay (colcon users).

    ros2 launch tether_sim tether_sim.launch.py
    ros2 launch tether_sim tether_sim.launch.py namespace:=rov1 params_file:=/path/to/params.yaml
    ros2 launch tether_sim tether_sim.launch.py record:=true output:=/tmp/run.mcap
    ros2 launch tether_sim tether_sim.launch.py replay:=true input:=/path/to/poses.mcap record:=true

Arguments (``ros2 launch tether_sim tether_sim.launch.py --show-args`` lists them):

- ``params_file``: parameter file of the node (default: the package's config/ropos_L200.yaml). The
  shipped files name their section ``/**/tether_sim:``, which rcl applies in any namespace (a
  plain ``tether_sim:`` section is renamed for rcl by tether-sim itself, which logs it:
  tether_sim/ros/namespacing.py). config/recorder.yaml's ``/**/tether_sim_recorder:`` applies in
  any namespace too; only ``output`` is given here.
- ``namespace``: namespace of every node started here. The node's topics are relative
  (``tether/state`` -> ``/<namespace>/tether/state``); /tf, /tf_static, /diagnostics and /clock
  stay global. Frames are not namespaced: see ``frame_prefix``.
- ``frame_prefix``: prefix of the node's frames (``node.frame_prefix``: body, attachment and tether
  frames, not the world frame); default ``<namespace>/`` in a namespace (``rov1/ship/base_link``...),
  none in the root namespace, so that two tethers launched in two namespaces never share a frame.
- ``use_sim_time``: run on /clock (default: true when ``replay`` is true, else false).
- ``record``, ``output``: also start tether-sim-record (config/recorder.yaml topics) writing ``output``.
- ``replay``, ``input``, ``rate``: also start tether-sim-replay of ``input`` (an MCAP file with
  ``/ship/pose`` and/or ``/vehicle/pose``), publishing /clock; the recorded pose topics are
  remapped into ``namespace``.

Checked without ROS 2's launch packages (none exists as a wheel on the package registry):
test/test_launch_and_layouts.py runs this file through a model of what ``ros2 launch`` does with
it (declarations evaluated in order, every substitution resolved, conditions parsed, executables
looked up in ``<prefix>/lib/tether_sim/`` through the ament index, parameter files opened); with a
ROS 2 install, ``--show-args`` checks it for real.
"""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution, PythonExpression
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare

PACKAGE = "tether_sim"
# (name, default, description); a default of None is computed below
ARGUMENTS = (
    ("params_file", None, "parameter file of tether-sim (default: config/ropos_L200.yaml of the package)"),
    ("namespace", "", "namespace of the nodes; topics are relative, /tf /tf_static /diagnostics /clock global"),
    ("frame_prefix", None, "prefix of the node's frames (node.frame_prefix; default '<namespace>/', none in the root namespace)"),
    # launch evaluates a default when its declaration runs: 'replay' is declared before
    # 'use_sim_time', whose default reads it
    ("replay", "false", "also start tether-sim-replay of 'input', publishing /clock"),
    ("use_sim_time", None, "run on /clock (default: true with replay:=true, else false)"),
    ("record", "false", "also start tether-sim-record (topics of config/recorder.yaml)"),
    ("output", "recording.mcap", "MCAP file the recorder writes"),
    ("input", "", "MCAP file to replay (PoseStamped on /ship/pose and/or /vehicle/pose)"),
    ("rate", "1.0", "replay speed factor"),
)


def generate_launch_description():
    share = FindPackageShare(PACKAGE)
    arg = LaunchConfiguration
    # the namespace without slashes, then '<namespace>/' (or '' in the root namespace)
    bare_ns = ["'", arg("namespace"), "'.strip('/')"]
    defaults = {
        "params_file": PathJoinSubstitution([share, "config", "ropos_L200.yaml"]),
        "frame_prefix": PythonExpression(bare_ns + [" + '/' if "] + bare_ns + [" else ''"]),
        "use_sim_time": arg("replay"),
    }
    declared = [DeclareLaunchArgument(name, default_value=defaults[name] if default is None else default,
                                      description=text) for name, default, text in ARGUMENTS]
    sim_time = PythonExpression(["'", arg("use_sim_time"), "'.lower() == 'true'"])
    # the replay publishes the recorded (absolute) names; move its pose topics into the namespace
    ns_prefix = PythonExpression(["'/' + '", arg("namespace"), "'.strip('/') if '", arg("namespace"),
                                  "'.strip('/') else ''"])
    simulation = Node(
        package=PACKAGE, executable="tether-sim", name="tether_sim", namespace=arg("namespace"),
        parameters=[arg("params_file"), {"use_sim_time": sim_time, "node.frame_prefix": arg("frame_prefix")}],
        output="screen", emulate_tty=True)
    recorder = Node(
        package=PACKAGE, executable="tether-sim-record", name="tether_sim_recorder",
        namespace=arg("namespace"), condition=IfCondition(arg("record")),
        parameters=[PathJoinSubstitution([share, "config", "recorder.yaml"]),
                    {"output": arg("output"), "use_sim_time": sim_time}],
        output="screen")
    replay = Node(
        package=PACKAGE, executable="tether-sim-replay", name="tether_sim_replay",
        condition=IfCondition(arg("replay")),
        parameters=[PathJoinSubstitution([share, "config", "replay.yaml"]),
                    {"input": arg("input"), "rate": arg("rate"), "use_sim_time": False}],
        remappings=[("/ship/pose", [ns_prefix, "/ship/pose"]),
                    ("/vehicle/pose", [ns_prefix, "/vehicle/pose"])],
        output="screen")
    return LaunchDescription(declared + [simulation, recorder, replay])
