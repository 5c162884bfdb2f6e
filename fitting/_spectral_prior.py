"""A topography's prior in the coordinates its spectrum was fitted in.

`characterise` fits `ln C = intercept + slope · ln q` by weighted least squares: its uncertainty is
Gaussian in (slope, intercept), and (D, ln G) is a nonlinear map of them (ln G ∝ 1/(D − 1) at fixed
intercept). A Gaussian in (D, ln G), the delta method's linearisation at the estimate, is a straight
thin ridge where the true one bends: with D uncertain by ±0.3 (a small map) its ridge crosses a
stiffness curve's ridge at a point far from the truth, with a confident, wrong posterior. The prior
is therefore stated in the fit's own coordinates, decorrelated: the slope, and `ln C` at the
wavevector where its error is independent of the slope's (`q_ref`), each a smooth function of
(D, ln G) (the measurement kind's `spectral_slope` and `log_prefactor`), and the Laplace covariance
linearises it at the optimum (JAX's derivative of these functions, `_prior`).
"""

from __future__ import annotations

import numpy as np
from jax.scipy.special import gammaln


def decorrelated(power_law) -> tuple[np.ndarray, np.ndarray, float]:
    """`(mean, covariance, ln q_ref)` of (slope, ln C(q_ref)) from the fit's (slope, intercept, covariance)."""
    slope, intercept, covariance = power_law
    covariance = np.asarray(covariance, dtype=float)
    log_q = -covariance[0, 1] / covariance[0, 0]
    to_ref = np.array([[1.0, 0.0], [log_q, 1.0]])  # (slope, intercept) -> (slope, intercept + slope ln q)
    return np.array([slope, intercept + slope * log_q]), to_ref @ covariance @ to_ref.T, float(log_q)


def spectral_coordinates(kind, log_q, D, log_G):
    """(slope, ln C(q_ref)) of the W-M surface (D, ln G) in the spectrum of `kind` (a
    `topography.AbstractMeasurementKind`), as a JAX function of traced D and ln G."""
    slope = kind.spectral_slope(D)
    return slope, kind.log_prefactor(D, log_G, gammaln) + slope * log_q
