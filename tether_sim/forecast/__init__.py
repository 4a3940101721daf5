"""Snap forecast: look-ahead runs of the tether from the current state, driven by a forecast of the
ship motion (docs/forecast.md). No ROS here; the node and the offline runner drive it."""
