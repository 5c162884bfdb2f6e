"""fitting: recover fractal surface parameters (D, G, ...) from measured stiffness curves.

`fit(loads, stiffness, scene, params=("D", "G"), method="bfgs")` returns a `FitResult` with
estimates, standard errors, 95 % intervals, correlations and identifiability warnings.
"""

from ._data import COLUMN_SETS, Curve, DataError, load_curve, parse_curve, write_curve
from ._fit import METHODS, FitResult, fit, model_stiffness, starting_points
from ._parameters import PARAMETERS, FitParameter, resolve
from ._residuals import FLAGGED_RESIDUAL, log_residuals
from ._resonance import fit_resonance

__all__ = [
    "fit",
    "model_stiffness",
    "fit_resonance",
    "FitResult",
    "METHODS",
    "FLAGGED_RESIDUAL",
    "log_residuals",
    "starting_points",
    "PARAMETERS",
    "FitParameter",
    "resolve",
    "Curve",
    "DataError",
    "load_curve",
    "parse_curve",
    "write_curve",
    "COLUMN_SETS",
]
