"""A vehicle for the tether's far end, simulated in MuJoCo (no ROS here).

- ``model``: an ROV's rigid-body and hydrodynamic parameters (BlueROV2 Heavy, von Benzon et al. 2022)
  and its thruster layout, as data;
- ``sim``: the vehicle in MuJoCo with the hydrodynamic, hydrostatic, thrust and tether loads, and a
  station-keeping controller with thrust allocation.

The ROS node around it is ``tether_sim.ros.vehicle_node``.
"""
