"""jaxcontact.fitting: recover fractal surface parameters (D, G, ...) from measured stiffness curves.

`fit(loads, stiffness, scene, params=("D", "G"), method=BFGS(), prior=None)` returns a `FitResult`
with estimates, standard errors, 95 % intervals, correlations and what the curve determines;
`fit_batch(...)` many curves at once; `sample(...)` (the `bayes` extra) a `Posterior` by NUTS. All
three drive one `Problem` per curve (`Problem.of(...)`), whose `misfit(σ)` is the loss in JAX.
"""

from ._batch import BatchResult, fit_batch
from ._data import COLUMN_SETS, Curve, DataError, load_curve, parse_curve, write_curve
from ._fit import fit, model_stiffness
from ._identifiability import Combination, Profile
from ._observables import FLAGGED_RESIDUAL
from ._optimise import BFGS, METHODS, AbstractMethod, LevenbergMarquardt
from ._parameters import PARAMETERS, FitParameter, resolve
from ._posterior import Posterior, sample
from ._prior import AbstractPrior, Bounds, Normal
from ._problem import Problem, starting_points
from ._residuals import log_residuals
from ._resonance import fit_resonance
from ._result import FitResult

__all__ = [
    "fit",
    "Problem",
    "fit_batch",
    "BatchResult",
    "model_stiffness",
    "fit_resonance",
    "FitResult",
    "sample",
    "Posterior",
    "Combination",
    "Profile",
    "METHODS",
    "AbstractMethod",
    "AbstractPrior",
    "Bounds",
    "Normal",
    "BFGS",
    "LevenbergMarquardt",
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
