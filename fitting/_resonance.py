"""A second fitting target: resonance frequency of a mass on the joint against preload.

At small amplitude the mass–joint system resonates at f = sqrt(K(F0)/m)/(2π) (checked against
the full nonlinear diffrax simulation in `tests/test_dynamics.py`), so a measured f(F0) curve is
a stiffness curve `K = m (2π f)²`. The loss stays on log scale: ln K = 2 ln f + const, so the
optimum and the (residual-variance-scaled) intervals are those of the frequency fit.
"""

from __future__ import annotations

import math

import numpy as np

import jaxcontact as jc
from jaxcontact import InputError

from ._fit import FitResult, fit


def fit_resonance(preloads, frequencies, mass: float, scene: jc.Scene, params=("D", "G"), **kw) -> FitResult:
    """Fit scene parameters to small-amplitude resonance frequencies (Hz) measured at preloads (N),
    read as the joint's loading tangent (`resonance_frequency(..., stiffness=Loading())`); a fit to
    the dynamic stiffness, which a vibrating joint pressed once has, is not built.

    **Arguments:** as `fit`, with `frequencies` in Hz and `mass` the vibrating mass in kg (> 0).
    **Returns:** a `FitResult` (its residuals are in ln K = 2 ln f + const).
    """
    if not (isinstance(mass, (int, float)) and math.isfinite(mass) and mass > 0):
        raise InputError(f"mass = {mass!r} kg must be positive and finite (valid range (0, inf))")
    frequencies = np.asarray(frequencies, dtype=float)
    if not np.all(np.isfinite(frequencies) & (frequencies > 0)):
        raise InputError("frequencies must be positive and finite (valid range (0, inf) Hz)")
    return fit(preloads, mass * (2 * math.pi * frequencies) ** 2, scene, params=params, **kw)
