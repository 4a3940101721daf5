"""Line networks: several tether lines joined at points and rigid bodies (a ship, a main tether, a
cage with its drum, an excursion tether, a vehicle), built on top of the one solver interface
(``tether_sim/solvers/base.py``). See docs/network.md."""
