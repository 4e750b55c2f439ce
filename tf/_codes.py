"""Internal error codes (tf2's TF2Error values) and graph limits shared by the core modules."""

from __future__ import annotations

from ._cache import BACKWARD, FORWARD, NO_DATA

__all__ = [
    "BACKWARD_EXTRAPOLATION",
    "CONNECTIVITY",
    "FORWARD_EXTRAPOLATION",
    "INVALID_ARGUMENT",
    "LOOKUP",
    "MAX_GRAPH_DEPTH",
    "NO_DATA_FOR_EXTRAPOLATION",
    "NO_ERROR",
]

NO_ERROR = 0
LOOKUP = 1
CONNECTIVITY = 2
FORWARD_EXTRAPOLATION = FORWARD
BACKWARD_EXTRAPOLATION = BACKWARD
NO_DATA_FOR_EXTRAPOLATION = NO_DATA
INVALID_ARGUMENT = 6

MAX_GRAPH_DEPTH = 1000  # tf2's MAX_GRAPH_DEPTH: deeper chains are reported as loops
