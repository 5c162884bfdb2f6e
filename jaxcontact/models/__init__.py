"""Contact models of the whole joint: the abstract interface and the load-controlled solve of
largest-spot models, the seed model (`Xia2024`) and its comparators, and the registry from names to
objects. A new model is one file here plus one line in `_registry.py` (or `register_model`)."""

from ._base import (
    CLOSED_INTERFACE,
    AbstractContactModel,
    AbstractPathModel,
    AbstractSweptModel,
    JointResponse,
    PathPoints,
    PointResult,
    without_single_spots,
)
from ._greenwood_williamson import GreenwoodWilliamson
from ._jzz2010 import JZZ2010
from ._largest_spot import AbstractJoint, AbstractLargestSpotModel, curve_solver
from ._load_pieces import AbstractLoadPieces, GenericLoadPieces, PowerLawLoadPieces
from ._measured_asperities import MeasuredAsperities
from ._persson import Persson
from ._registry import DISTRIBUTIONS, INTERACTIONS, MODELS, QUADRATURES, SPOT_STIFFNESSES, build_model, register_model
from ._spots import GaussianSummitCount, SpotFamilies, SpotState, SummitCount
from ._xia2024 import Xia2024

__all__ = [
    "AbstractContactModel",
    "AbstractJoint",
    "AbstractLargestSpotModel",
    "AbstractPathModel",
    "AbstractSweptModel",
    "CLOSED_INTERFACE",
    "curve_solver",
    "AbstractLoadPieces",
    "build_model",
    "DISTRIBUTIONS",
    "GenericLoadPieces",
    "GreenwoodWilliamson",
    "INTERACTIONS",
    "JointResponse",
    "PathPoints",
    "SpotFamilies",
    "SpotState",
    "SummitCount",
    "GaussianSummitCount",
    "JZZ2010",
    "MeasuredAsperities",
    "MODELS",
    "Persson",
    "PointResult",
    "PowerLawLoadPieces",
    "QUADRATURES",
    "register_model",
    "SPOT_STIFFNESSES",
    "Xia2024",
    "without_single_spots",
]
