"""D, G and l_min from the spectrum of the whole measurement: the areal `C2D` of a map, `C1D` of a
profile, over a band found from the data (`_band`) or given (docs/topography.md)."""

from __future__ import annotations

import math

import numpy as np

from ..numerics._validate import InputError, spelled
from ._band import MIN_MODES, MIN_RATIO, PowerLaw, fit_band, select_band
from ._checks import widened_for_filling
from ._result import Characterisation
from ._separate import lowest_roughness_q
from ._whole import local_slopes, whole_spectrum


class NoBandError(InputError):
    """No power-law band was found: the message says why and suggests a band; `characterisation`-less,
    it carries the `spectrum` and its `local_slope` (q, local D) so that a caller can plot them."""

    def __init__(self, message: str, spectrum, local_slope, suggestion):
        super().__init__(message)
        self.spectrum, self.local_slope, self.suggestion = spectrum, local_slope, suggestion

    @property
    def band(self) -> tuple[float, float] | None:
        """The band suggested (short, long wavelength, m) as the message gives it, or None."""
        return _suggested_band(self.suggestion)


def _D_logG(spectrum, slope: float, intercept: float):
    D = float(spectrum.D_of(slope))
    return D, (spectrum.kind.log_G_of_prefactor(D, intercept) if 1 < D < 2 else math.nan)


def _covariance(spectrum, law) -> np.ndarray:
    """The covariance of (D, ln G) from that of (slope, intercept), by the delta method."""
    step = 1e-6
    base = np.array(_D_logG(spectrum, law.slope, law.intercept))
    columns = []
    for d_slope, d_intercept in ((step, 0.0), (0.0, step)):
        moved = np.array(_D_logG(spectrum, law.slope + d_slope, law.intercept + d_intercept))
        columns.append((moved - base) / step)
    jacobian = np.stack(columns, axis=1)
    return jacobian @ law.covariance @ jacobian.T


def _q_and_D(slopes):
    q, _, D = slopes
    return q, D


def _outward(value: float, up: bool) -> float:
    """`value` to 3 significant digits, rounded away from the band's inside: a band typed back as
    printed holds the same bins (rounded to nearest it could lose a bin at either end)."""
    scale = 10.0 ** (math.floor(math.log10(value)) - 2)
    return (math.ceil if up else math.floor)(value / scale) * scale


def _suggested_band(suggested) -> tuple[float, float] | None:
    """The closest window (short, long wavelength, m) rounded outward, or None."""
    return None if suggested is None else (_outward(suggested[0], up=False), _outward(suggested[1], up=True))


def _suggestion(spectrum, suggested) -> str:
    if suggested is None:
        return "no stretch of the spectrum has the slope of a self-affine surface (1 < D < 2)"
    short, long = _suggested_band(suggested)
    return "the closest to a power law is " + spelled(
        f"band=({short:.3g}, {long:.3g})", f"--band {short:.3g} {long:.3g}"
    )


def characterise_spectrum(topography, heights, spacing, periodic, kind, band, D, cutoff) -> Characterisation:
    """The PSD characterisation of `characterise` (its arguments, checked there)."""
    spectrum = whole_spectrum(heights, spacing, periodic)
    q_max = None if not cutoff else 2 * math.pi / cutoff
    usable = spectrum.q[spectrum.modes >= MIN_MODES]
    if usable.size < 5 or usable[-1] / usable[0] < MIN_RATIO:
        raise InputError(
            f"the {kind.noun} is too small for any power-law band: {heights.shape[-1]} points a side leave too few "
            f"Fourier modes (at least {MIN_MODES} per bin over a factor {MIN_RATIO:g} in wavelength are needed)"
        )
    if band is None:
        held = None if D is None else spectrum.slope_of(float(D))
        law = select_band(spectrum, q_max, held, lowest_roughness_q(topography))
        if not isinstance(law, PowerLaw):
            slopes = _q_and_D(local_slopes(spectrum))
            raise NoBandError(
                f"no power-law band: no window of the {kind.noun}'s spectrum spanning a factor 4 is a power law within "
                f"its scatter with 1 < D < 2; {_suggestion(spectrum, law)} (psd.png shows the local slope)",
                spectrum,
                slopes,
                law,
            )
    else:
        held = None if D is None else spectrum.slope_of(float(D))
        law = fit_band(spectrum, (2 * math.pi / band[1], 2 * math.pi / band[0]), held)
        if law is None:
            raise InputError(
                f"band = ({band[0]:.3g}, {band[1]:.3g}) m holds fewer than 4 spectral bins: too few to fit"
            )
    D_hat, log_G_hat = _D_logG(spectrum, law.slope, law.intercept)
    if not 1 < D_hat < 2:
        raise InputError(
            f"no power-law band: the slope over ({2 * math.pi / law.band[1]:.3g}, {2 * math.pi / law.band[0]:.3g}) m "
            f"gives D = {D_hat:.3g}, outside (1, 2); the surface is not self-affine there (another band may be: "
            f"{spelled('band=(short, long)', '--band SHORT LONG')})"
        )
    covariance = _covariance(spectrum, law)
    diagnostics = ()
    filled = float(topography.info.get("filled_fraction", 0.0))
    if filled > 0:
        covariance, note = widened_for_filling(covariance, filled, held=D is not None)
        diagnostics += (note,)
    dof = max(law.bins - 2, 2)
    fit_q = np.geomspace(*law.band, 50)
    return Characterisation.fitted(
        "psd",
        D_hat,
        log_G_hat,
        (2 * math.pi / law.band[1], 2 * math.pi / law.band[0]),
        covariance,
        dof,
        held=D is not None,
        groups=1,
        estimates=np.array([[D_hat, log_G_hat]]),
        spectrum=(spectrum.q, spectrum.C),
        spectrum_variance=spectrum.log_variance,
        fit=(fit_q, np.exp(law.intercept + law.slope * np.log(fit_q))),
        diagnostics=diagnostics,
        kind=kind,
        reliability_cutoff=cutoff,
        ends=law.ends,
        rolloff=law.rolloff,
        floor=law.floor,
        local_slope=_q_and_D(local_slopes(spectrum)),
        power_law=(law.slope, law.intercept, law.covariance),
    )
