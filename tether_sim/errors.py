"""Exceptions shared by every layer (no dependencies)."""


class TetherSimError(Exception):
    """Base class of the package's own errors."""


class ConfigError(TetherSimError, ValueError):
    """A parameter file or value is malformed; the message names the key (and the file)."""


class SolverDivergedError(TetherSimError, FloatingPointError):
    """The solver state became non-finite or left its physical bounds."""


class UnstableTimeStepError(TetherSimError, ValueError):
    """A fixed time step larger than the stability limit was asked for."""
