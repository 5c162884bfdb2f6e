"""jaxcontact: differentiable normal contact stiffness of rough mechanical joints.

The fractal model of Xia, Qu & Liu (Aerospace 11, 472, 2024) (docs/model.md): Kogut–Etsion
asperity regimes over a Majumdar–Bhushan size distribution, with interaction between asperities,
solved under load control and differentiable end to end; and the models to compare it with,
chosen by passing them (`Scene(..., model=JZZ2010())`).

The package never enables float64 itself: call `jax.config.update("jax_enable_x64", True)`
for double precision (the command line does). Its public names are listed in
docs/architecture.md; the subpackages (`jaxcontact.models`, `jaxcontact.physics`,
`jaxcontact.numerics`, ...) export the pieces a new model is built from.
"""

from .bem import BEM
from .core import (
    Outputs,
    Scene,
    Solution,
    TangentialCycle,
    dynamic_stiffness,
    solve,
    stack_scenes,
    table1_scene,
    tangential_cycle,
    tangential_stiffness,
)
from .models import (
    DISTRIBUTIONS,
    INTERACTIONS,
    JZZ2010,
    MODELS,
    QUADRATURES,
    SPOT_STIFFNESSES,
    AbstractContactModel,
    AbstractJoint,
    AbstractLargestSpotModel,
    AbstractLoadPieces,
    AbstractPathModel,
    AbstractSweptModel,
    GaussianSummitCount,
    GenericLoadPieces,
    GreenwoodWilliamson,
    JointResponse,
    MeasuredAsperities,
    Persson,
    PointResult,
    SpotFamilies,
    SpotState,
    SummitCount,
    Xia2024,
    build_model,
    register_model,
)
from .numerics import (
    AbstractQuadrature,
    AbstractRowQuadrature,
    Adaptive,
    GaussLegendre,
    InputError,
    JaxcontactWarning,
    MissingExtraError,
    NewtonBisection,
    PlausibilityWarning,
    PowerLaw,
    PowerSeries,
    clear_caches,
    solve_increasing,
)
from .physics import (
    AbstractDistribution,
    AbstractInteraction,
    AbstractLongEnd,
    AbstractSpotStiffness,
    AbstractStiffness,
    AbstractSummitLaw,
    FamilyDerivative,
    HertzSummits,
    KogutEtsionSummits,
    Loading,
    MajumdarBhushan,
    MeasuredSpectrum,
    NoInteraction,
    PaperInteraction,
    PowerLawEnd,
    Rolloff,
    SeriesInteraction,
    Sneddon,
    TangentialStick,
    Unloading,
    WangKomvopoulos,
    hertz_stiffness,
    kogut_etsion_laws,
    mindlin_ratio,
    size_distribution,
)
from .quantities import (
    PARAMETERS,
    Branch,
    DimensionlessScene,
    Material,
    ParameterSpec,
    Scales,
    Status,
    StatusError,
    Surface,
    contact_modulus,
    status_message,
    tangential_contact_modulus,
)

__version__ = "0.5.0"

# The applications, imported when first used (`jaxcontact.applications`; most integrate with diffrax).
_LAZY = (
    "Approach",
    "Drive",
    "InterfaceLaw",
    "LoadPath",
    "approach",
    "approach_quadrature",
    "frequency_response",
    "interface_law",
    "resonance_frequency",
    "solve_path",
    "simulate",
    "steady_amplitude",
)

__all__ = [
    # The joint and its solve
    "Surface",
    "MeasuredSpectrum",
    "AbstractLongEnd",
    "Rolloff",
    "PowerLawEnd",
    "Material",
    "contact_modulus",
    "tangential_contact_modulus",
    "Scene",
    "stack_scenes",
    "table1_scene",
    "solve",
    "Outputs",
    "AbstractStiffness",
    "Loading",
    "Unloading",
    "TangentialStick",
    "dynamic_stiffness",
    "tangential_stiffness",
    "tangential_cycle",
    "TangentialCycle",
    "mindlin_ratio",
    "NewtonBisection",
    "Solution",
    "Status",
    "StatusError",
    "Branch",
    "status_message",
    "Scales",
    "PARAMETERS",
    "ParameterSpec",
    "InputError",
    "MissingExtraError",
    "JaxcontactWarning",
    "PlausibilityWarning",
    # Models and their choices
    "Xia2024",
    "JZZ2010",
    "GreenwoodWilliamson",
    "MeasuredAsperities",
    "Persson",
    "BEM",
    "AbstractInteraction",
    "NoInteraction",
    "PaperInteraction",
    "SeriesInteraction",
    "AbstractDistribution",
    "MajumdarBhushan",
    "WangKomvopoulos",
    "AbstractSpotStiffness",
    "FamilyDerivative",
    "Sneddon",
    "AbstractSummitLaw",
    "HertzSummits",
    "KogutEtsionSummits",
    "AbstractQuadrature",
    "AbstractRowQuadrature",
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
    # What a new model is built from
    "AbstractContactModel",
    "AbstractLargestSpotModel",
    "AbstractPathModel",
    "AbstractSweptModel",
    "AbstractJoint",
    "AbstractLoadPieces",
    "GenericLoadPieces",
    "JointResponse",
    "SpotFamilies",
    "SpotState",
    "SummitCount",
    "GaussianSummitCount",
    "PointResult",
    "DimensionlessScene",
    "PowerLaw",
    "kogut_etsion_laws",
    "size_distribution",
    "hertz_stiffness",
    "solve_increasing",
    # Built on the stiffness
    *_LAZY,
    "clear_caches",
]


def __getattr__(name):
    if name in _LAZY:
        from . import applications

        value = getattr(applications, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
