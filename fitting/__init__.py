"""fitting: recover fractal surface parameters (D, G, ...) from measured stiffness curves.

`fit(loads, stiffness, scene, params=("D", "G"), method="bfgs")` returns a `FitResult` with
estimates, standard errors, 95 % intervals, correlations and identifiability warnings.
"""

from .data import COLUMN_SETS, Curve, DataError, load_curve, parse_curve, write_curve
from .fit import METHODS, FitResult, fit, model_stiffness, starting_points
from .parameters import PARAMETERS, FitParameter, resolve
from .residuals import FLAGGED_RESIDUAL, log_residuals
from .resonance import fit_resonance

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
