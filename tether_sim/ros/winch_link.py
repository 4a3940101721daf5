"""The winch between the driver and the solver: the implementation is ``tether_sim/solvers/winch_link.py``
(it imports no ROS; line networks use it too); the node's modules import it from here."""

from tether_sim.solvers.winch_link import (  # noqa: F401
    END_TENSION, LengthReference, WinchedSolver, WinchLink, length_reference, link_of, wrap_factory,
)
