"""tether_sim: real-time ROV tether dynamics (DG/LDG and hybrid rod-catenary), snap loads, MCAP.

Layers (no arrow points back): ``physics`` and ``numerics`` (leaves, no ROS) <- ``solvers`` <-
``config`` <- ``io``, ``scenarios`` <- ``ros`` (the only package that imports rclpy or *_msgs).
"""

__version__ = "0.1.0"
