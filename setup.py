"""ament_python set-up of tether_sim (the repository root is the ROS 2 package).

Used by ``pip install -e .`` (tools/setup_env.sh, ``make``) and by ``colcon build`` in a ROS 2
workspace. Name, version and dependencies must agree with package.xml (test/test_packaging.py).
"""

import os
from glob import glob

from setuptools import find_packages, setup

PACKAGE = "tether_sim"

setup(
    name=PACKAGE,
    version="0.1.0",
    description="Real-time ROV tether simulation (DG/LDG and hybrid rod-catenary solvers), "
                "snap-load detection, MCAP record and replay, for ROS 2 Jazzy",
    license="Apache-2.0",
    maintainer="tether_sim maintainers",
    maintainer_email="tether-sim@example.com",
    packages=find_packages(exclude=["test", "test.*"]),
    python_requires=">=3.10",
    install_requires=[
        "setuptools",
        "numpy",
        "numba",
        "scipy",
        "matplotlib",
        "PyYAML",
        "tqdm",
        "mcap",
        "mcap-ros2-support",
        "rosbags",
    ],
    # tether-sim-study (tether_sim/studies): Parquet tables, Dask execution and its dashboard
    # tether-sim-vehicle (tether_sim/vehicle): the vehicle simulated in MuJoCo
    extras_require={"studies": ["dask[distributed]", "pyarrow", "bokeh"], "vehicle": ["mujoco>=3.3,<3.4"]},
    zip_safe=True,
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{PACKAGE}"]),
        (f"share/{PACKAGE}", ["package.xml"]),
        (f"share/{PACKAGE}/config", sorted(glob("config/*.yaml") + glob("config/*.txt"))),
        (f"share/{PACKAGE}/config/studies", sorted(glob("config/studies/*.yaml"))),  # their base: ../
        (f"share/{PACKAGE}/data", sorted(f for f in glob("data/*") if os.path.isfile(f))),
        (f"share/{PACKAGE}/launch", sorted(glob("launch/*.launch.py"))),
        (f"share/{PACKAGE}/rviz", sorted(glob("rviz/*.rviz"))),
        (f"share/{PACKAGE}/foxglove", sorted(glob("foxglove/*.json"))),
    ],
    entry_points={
        "console_scripts": [
            "tether-sim = tether_sim.ros.sim_node:main",
            "tether-sim-offline = tether_sim.ros.offline:main",
            "tether-sim-record = tether_sim.ros.recorder_node:main",
            "tether-sim-replay = tether_sim.ros.replay_node:main",
            "tether-sim-report = tether_sim.report:main",
            "tether-sim-study = tether_sim.studies.cli:main",
            "tether-sim-recover = tether_sim.io.mcap_recover:main",
            "tether-sim-poses = tether_sim.ros.pose_source:main",
            "tether-sim-vehicle = tether_sim.ros.vehicle_node:main",
            "tether-sim-rov-demo = tether_sim.ros.rov_demo:main",
        ],
    },
)
