"""The spectrum of a whole measurement: the areal `C2D(q)` of a map, radially averaged, or the `C1D(q)`
of a profile, in log-spaced bins with each bin's number of independent modes and the periodogram's
own scatter (docs/topography.md).

Conventions as SurfaceTopography's: `C2D(q) = |Δx Δy Σ h w e^(-i q·r)|² / A` and
`C1D(q) = |Δx Σ h w e^(-i q x)|² / L`, with `w` a Hann window of mean square 1 where the
measurement is not periodic (after removing a quadratic surface or a cubic per profile: wavelengths
longer than the measurement appear in it as trends, which the window would leak into the band).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ._kind import AbstractMeasurementKind, Areal, Profile
from ._separate import polynomial_fit
from ._spectra import DETREND_DEGREE

BINS_PER_DECADE = 20
# The variance of the mean of Hann-windowed periodogram values is this many times (per dimension)
# that of independent ones: adjacent DFT coefficients correlate by -2/3, next-adjacent by 1/6,
# so Σ ρ² = 1 + 2 (4/9 + 1/36).
HANN_VARIANCE_FACTOR = 1.0 + 2.0 * (4.0 / 9.0 + 1.0 / 36.0)


@dataclasses.dataclass(frozen=True)
class Spectrum:
    """A binned spectrum: `q` (rad/m, the bins' geometric means), `C` (mean periodogram, m⁴ areal
    or m³ profile), `modes` (independent Fourier modes per bin), `scatter` (per bin, the variance of one
    mode's periodogram relative to its mean², times the window's correlation factor: 1 for a periodic
    measurement of a Gaussian surface); `kind` (`Areal()` or `Profile()`); `spacing` (m, the coarser
    axis's); `q_squared` (the bins' mean q², where a roll-off `exp(-κ q²)` is evaluated: across a bin
    q² varies more than q); `q_squared_cumulants` (the 2nd to 4th cumulants of q² over each bin's
    modes, B × 3: a bin's mean of a strong roll-off departs from its value at the mean q²)."""

    q: np.ndarray
    C: np.ndarray
    modes: np.ndarray
    scatter: np.ndarray
    kind: AbstractMeasurementKind
    spacing: float
    q_squared: np.ndarray | None = None
    q_squared_cumulants: np.ndarray | None = None

    @property
    def log_variance(self) -> np.ndarray:
        """Each bin's variance of `ln C`: its mean of `modes` periodogram values of relative variance
        `scatter` is Gamma-distributed with shape `modes/scatter` (`_binned`), var ln = ψ'(shape);
        infinity for a bin without modes. On a windowed map's bins of fewer than 100 modes it is
        1.1–4.7 times the variance between realisations of a Gaussian surface (one mode's scatter
        alone would understate its lowest bins, which take in wavelengths longer than the map too),
        on wider bins 1.1–1.4 times (tests/test_measured_spectrum.py)."""
        from scipy import special

        shape = np.where(self.modes > 0, self.modes / np.where(self.scatter > 0, self.scatter, 1.0), 0.0)
        with np.errstate(divide="ignore"):
            return np.where(shape > 0, special.polygamma(1, np.where(shape > 0, shape, 1.0)), np.inf)

    def slope_of(self, D: float) -> float:
        """The log-log slope of the W-M power law: `-(6 - 2D)` areal, `-(5 - 2D)` profile."""
        return self.kind.spectral_slope(D)

    def D_of(self, slope):
        return (slope - self.kind.spectral_slope(0.0)) / 2.0


def _detrended(heights: np.ndarray) -> np.ndarray:
    """`heights` less a least-squares polynomial: a cubic for a profile, a quadric surface for a map."""
    return heights - polynomial_fit(heights, DETREND_DEGREE if heights.ndim == 1 else 2)


def whole_spectrum(heights, spacing, periodic: bool, per_decade: int = BINS_PER_DECADE) -> Spectrum:
    """The binned spectrum of a whole profile (1-D `heights`) or map (2-D), grid spacing `spacing` (m):
    one number, or one per axis of `heights` (a map's pixels need not be square)."""
    heights = np.asarray(heights, dtype=float)
    spacings = np.broadcast_to(np.asarray(spacing, dtype=float), (heights.ndim,))
    if periodic:
        windowed = heights - heights.mean()
    else:
        window = np.hanning(heights.shape[0])
        for n in heights.shape[1:]:
            window = np.multiply.outer(window, np.hanning(n))
        windowed = _detrended(heights) * window / math.sqrt(np.mean(window**2))
    transform = np.fft.rfftn(windowed)
    C = float(np.prod(spacings)) * np.abs(transform) ** 2 / heights.size
    axes = [2 * np.pi * np.fft.fftfreq(n, d) for n, d in zip(heights.shape[:-1], spacings[:-1])]
    axes.append(2 * np.pi * np.fft.rfftfreq(heights.shape[-1], spacings[-1]))
    q = np.sqrt(sum(a**2 for a in np.meshgrid(*axes, indexing="ij")))
    # A real field's transform is Hermitian: an inner column of the half-spectrum stands for itself
    # and its mirror image (one independent mode, weight 2); the first (and a Nyquist) column holds
    # both members of each pair (weight 1 each). Half the total weight counts independent modes.
    weight = np.full(q.shape, 2.0)
    weight[..., 0] = 1.0
    if heights.shape[-1] % 2 == 0:
        weight[..., -1] = 1.0
    # Rings are whole up to the coarser axis's Nyquist wavevector; beyond it only the finer axis has modes.
    lowest = 2 * np.pi / max(n * d for n, d in zip(heights.shape, spacings))
    highest = np.pi / float(spacings.max())
    count = int(math.ceil(per_decade * math.log10(highest / lowest)))
    edges = np.geomspace(lowest * (1 - 1e-9), highest, count + 1)
    index = np.digitize(q.ravel(), edges) - 1
    inside = (index >= 0) & (index < count) & (q.ravel() > 0)
    index, w, c = index[inside], weight.ravel()[inside], C.ravel()[inside]
    total = np.bincount(index, w, count)
    keep = total > 0
    mean = np.bincount(index, w * c, count)[keep] / total[keep]
    square = np.bincount(index, w * c * c, count)[keep] / total[keep]
    log_q = np.bincount(index, w * np.log(q.ravel()[inside]), count)[keep] / total[keep]
    q2 = q.ravel()[inside] ** 2
    q_squared = np.bincount(index, w * q2, count)[keep] / total[keep]
    centre = np.zeros(count)
    centre[keep] = q_squared
    d = q2 - centre[index]
    wd2 = w * d * d
    m2, m3, m4 = (np.bincount(index, x, count)[keep] / total[keep] for x in (wd2, wd2 * d, wd2 * d * d))
    modes = total[keep] / 2.0
    scatter = _running_scatter(square / np.maximum(mean, 1e-300) ** 2 - 1.0, modes)
    if not periodic:
        scatter = scatter * HANN_VARIANCE_FACTOR**heights.ndim
    return Spectrum(
        q=np.exp(log_q),
        C=mean,
        modes=modes,
        scatter=np.maximum(scatter, 1e-3),
        kind=Areal() if heights.ndim == 2 else Profile(),
        spacing=float(spacings.max()),
        q_squared=q_squared,
        q_squared_cumulants=np.stack([m2, m3, m4 - 3 * m2 * m2], axis=-1),
    )


def _running_scatter(relative: np.ndarray, modes: np.ndarray, half_width: int = BINS_PER_DECADE // 2) -> np.ndarray:
    """One mode's relative variance per bin, from the bins' own scatter: the median over ±half a decade
    of bins with enough modes to tell (1 for a Gaussian field's exponential periodogram; it differs
    where the spectrum is made otherwise, and can differ between a surface's band and its noise)."""
    populated = np.flatnonzero(modes >= 8)
    if populated.size == 0:
        return np.ones_like(relative)
    result = np.empty_like(relative)
    for k in range(relative.size):
        near = populated[np.abs(populated - k) <= half_width]
        if near.size == 0:  # few-mode bins at the long end: the nearest populated ones
            near = populated[np.argsort(np.abs(populated - k))[:half_width]]
        result[k] = np.median(relative[near])
    return result


def local_slopes(spectrum: Spectrum, half_width: float = 0.25):
    """The log-log slope of `spectrum` over ±`half_width` decades around each bin: (q, slope, D)."""
    x, y = np.log(spectrum.q), np.log(np.maximum(spectrum.C, 1e-300))
    w = spectrum.modes
    slopes = np.full(x.size, np.nan)
    for k in range(x.size):
        near = (np.abs(x - x[k]) <= half_width * math.log(10)) & (spectrum.C > 0)
        if near.sum() >= 3:
            slopes[k] = np.polyfit(x[near], y[near], 1, w=np.sqrt(w[near]))[0]
    return spectrum.q, slopes, spectrum.D_of(slopes)
