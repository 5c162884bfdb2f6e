"""Numerics the models are built from: power laws and their exact integrals, quadrature, the
"paper" interaction's pole integral, a safeguarded monotone root-finder, input validation, and
what differs between the JAX versions supported."""

from ._caches import cached, clear_caches, register_cache
from ._compat import standard_promotion, x64
from ._powerlaw import PowerLaw, exponential_integral
from ._quadrature import (
    AbstractQuadrature,
    AbstractRowQuadrature,
    Adaptive,
    GaussLegendre,
    PowerSeries,
    integrate_log_area,
)
from ._rootfind import NewtonBisection, solve_increasing
from ._validate import (
    InputError,
    JaxcontactWarning,
    LoadsLike,
    MissingExtraError,
    PlausibilityWarning,
    check_choice,
    check_instance,
    check_positive,
    check_range,
    check_strategy,
    decoded_text,
    float_array,
    optional_import,
)

__all__ = [
    "AbstractQuadrature",
    "AbstractRowQuadrature",
    "Adaptive",
    "check_choice",
    "check_instance",
    "check_positive",
    "check_range",
    "decoded_text",
    "LoadsLike",
    "check_strategy",
    "cached",
    "clear_caches",
    "register_cache",
    "float_array",
    "optional_import",
    "exponential_integral",
    "GaussLegendre",
    "InputError",
    "integrate_log_area",
    "JaxcontactWarning",
    "MissingExtraError",
    "NewtonBisection",
    "PlausibilityWarning",
    "PowerLaw",
    "PowerSeries",
    "solve_increasing",
    "standard_promotion",
    "x64",
]
