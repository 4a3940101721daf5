"""Body-frame queries of :class:`tether_sim.ros.driver.SimulationDriver`: attachment offsets, end
orientations and the tether's wrench on each end body, as the node publishes them (no rclpy here).

:class:`BodyFrame` is a mixin of the driver: it reads ``config``, ``solver``, ``sources`` and
``stamp``.
"""

import numpy as np


class BodyFrame:
    """Frames and wrenches of the two ends (module doc)."""

    def offset(self, end):
        """Attachment offset in the body frame of an end: ``body.attachment`` (from the centre of
        gravity) for a simulated body, else ``node.ship_attachment`` / ``node.vehicle_attachment``."""
        if getattr(self.config, f"{end}_end").kind == "body":
            return self.config.body.attachment
        return getattr(self.config.node, f"{end}_attachment")

    def end_orientation(self, end, body=None):
        """Quaternion (x, y, z, w) of the body frame of an end at the current state: a simulated
        body's own (``body``: its BodyState if the caller already has it), a pose input's
        interpolated one, otherwise aligned with the world."""
        if getattr(self.config, f"{end}_end").kind == "body":
            body = body if body is not None else self.solver.body_state(end)
            if body is not None:
                return np.asarray(body.orientation, float)
        src = self.sources.get(end)
        if src is not None and getattr(src, "has_data", True):
            return np.asarray(src.orientation_at(self.stamp), float)
        return np.array([0.0, 0.0, 0.0, 1.0])

    def body_wrench(self, end, forces, body=None, orientation=None):
        """Force and torque BY the tether ON the body of ``end``, in its body frame, about its origin
        (``body``: the BodyState of a simulated body end, ``orientation``: the end's
        :meth:`end_orientation`, if the caller already has them):
        ``f = R^T F``, ``torque = r x f + R^T M`` (world force F and moment M, offset r)."""
        f, torque = self.body_wrench_floats(end, forces, body, orientation)
        return np.array(f), np.array(torque)

    def body_wrench_floats(self, end, forces, body=None, orientation=None, offset=None):
        """:meth:`body_wrench` as two tuples of 3 floats (the same numbers, no arrays: the node's
        tick writes them straight into its messages; ``offset``: the end's :meth:`offset`, if the caller
        has it)."""
        q = (self.end_orientation(end, body) if orientation is None else orientation).tolist()
        f = _to_body(q, getattr(forces, f"{end}_force"))
        m = _to_body(q, getattr(forces, f"{end}_moment"))
        (rx, ry, rz), (fx, fy, fz) = self.offset(end) if offset is None else offset, f
        return f, (ry * fz - rz * fy + m[0], rz * fx - rx * fz + m[1], rx * fy - ry * fx + m[2])


def _to_body(q, v):
    """``R(q)^T v`` for a unit quaternion (x, y, z, w) and a 3-vector, in plain floats (a few
    microseconds instead of tens for the numpy version with its small-array overheads)."""
    x, y, z, w = q
    a, b, c = v.tolist() if type(v) is np.ndarray and v.dtype == np.float64 else (float(e) for e in v)
    return ((1 - 2 * (y * y + z * z)) * a + 2 * (x * y + z * w) * b + 2 * (x * z - y * w) * c,
            2 * (x * y - z * w) * a + (1 - 2 * (x * x + z * z)) * b + 2 * (y * z + x * w) * c,
            2 * (x * z + y * w) * a + 2 * (y * z - x * w) * b + (1 - 2 * (x * x + y * y)) * c)
