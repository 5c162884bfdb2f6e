"""jaxcontact: differentiable normal contact stiffness of rough mechanical joints.

The fractal model of Xia, Qu & Liu (Aerospace 11, 472, 2024) as specified in MODEL.md:
Kogut–Etsion asperity regimes over a Majumdar–Bhushan size distribution, with interaction
between asperities, solved under load control and differentiable end to end; and the models to
compare it with, chosen by passing them (`Scene(..., model=JZZ2010())`).

The package never enables float64 itself: call `jax.config.update("jax_enable_x64", True)`
for double precision (the command line does).
"""

from .core.defaults import table1_scene
from .core.domain import PARAMETERS, ParameterSpec
from .core.loadcontrol import point_solver, solve
from .core.parameters import Material, Surface
from .core.scales import DimensionlessScene, Scales, nondimensionalise
from .core.scene import Scene, stack_scenes
from .core.settings import NewtonBisection, Outputs
from .core.solution import Solution
from .core.status import Status, status_message
from .models.base import AbstractContactModel, AbstractJoint, AbstractLargestSpotModel, JointResponse, PointResult
from .models.greenwood_williamson import GreenwoodWilliamson
from .models.jzz2010 import JZZ2010
from .models.persson import Persson
from .models.xia2024 import Xia2024
from .numerics.quadrature import AbstractQuadrature, Adaptive, GaussLegendre, PowerSeries
from .numerics.validate import InputError, JaxcontactWarning, MissingExtraError, PlausibilityWarning
from .physics.distribution import AbstractDistribution, MajumdarBhushan, WangKomvopoulos, wang_komvopoulos_psi
from .physics.interaction import AbstractInteraction, NoInteraction, PaperInteraction, SeriesInteraction
from .physics.spot_stiffness import AbstractSpotStiffness, FamilyDerivative, Sneddon
from .registry import (
    DISTRIBUTIONS,
    INTERACTIONS,
    MODELS,
    QUADRATURES,
    SPOT_STIFFNESSES,
    build_model,
    register_model,
)

__all__ = [
    "Surface",
    "Material",
    "Scene",
    "Solution",
    "InputError",
    "MissingExtraError",
    "JaxcontactWarning",
    "PlausibilityWarning",
    "Status",
    "status_message",
    "Scales",
    "PARAMETERS",
    "ParameterSpec",
    "table1_scene",
    "stack_scenes",
    "solve",
    "Outputs",
    "NewtonBisection",
    "point_solver",
    "approach",
    "Approach",
    "Drive",
    "simulate",
    "steady_amplitude",
    "frequency_response",
    "resonance_frequency",
    "AbstractContactModel",
    "AbstractLargestSpotModel",
    "AbstractJoint",
    "JointResponse",
    "PointResult",
    "DimensionlessScene",
    "nondimensionalise",
    "Xia2024",
    "JZZ2010",
    "GreenwoodWilliamson",
    "Persson",
    "AbstractSpotStiffness",
    "FamilyDerivative",
    "Sneddon",
    "AbstractInteraction",
    "NoInteraction",
    "PaperInteraction",
    "SeriesInteraction",
    "AbstractDistribution",
    "MajumdarBhushan",
    "WangKomvopoulos",
    "wang_komvopoulos_psi",
    "AbstractQuadrature",
    "PowerSeries",
    "GaussLegendre",
    "Adaptive",
    "MODELS",
    "INTERACTIONS",
    "DISTRIBUTIONS",
    "QUADRATURES",
    "SPOT_STIFFNESSES",
    "build_model",
    "register_model",
]
__version__ = "0.4.0"

# The applications that integrate with diffrax are imported when first used: diffrax's import
# (0.2 s beyond the equinox and optimistix that `solve` needs anyway) is not needed by `solve`
# or the command line's `run`.
_LAZY = {
    "Drive": "dynamics",
    "frequency_response": "dynamics",
    "resonance_frequency": "dynamics",
    "simulate": "dynamics",
    "steady_amplitude": "dynamics",
    "Approach": "loadapproach",
    "approach": "loadapproach",
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".applications.{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
