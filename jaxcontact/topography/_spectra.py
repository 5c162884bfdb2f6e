"""Line-scan spectra and structure functions of a topography, per group of line scans.

Uncertainty comes from the scatter between independent groups (contiguous blocks of line scans
of an areal map, or segments of one profile), never from the formal error of one averaged
spectrum (docs/model.md §8). The periodogram follows SurfaceTopography's convention,
`C1D(q_k) = |Δx Σ h_i w_i e^(-i q_k x_i)|² / L` with a Hann window `w` (mean square 1) where the
scan is not periodic; `tests/test_topography.py` checks it against
`SurfaceTopography`'s `power_spectrum_from_profile`.
"""

from __future__ import annotations

import numpy as np

from ._kind import Areal, Profile

DETREND_DEGREE = 3


def periodograms(rows, dx, periodic: bool):
    """`q` (rad/m, without 0) and `C1D` of each row of `rows` (heights in m, spacing `dx`)."""
    rows = np.asarray(rows, dtype=float)
    n = rows.shape[-1]
    if periodic:
        windowed = rows - rows.mean(axis=-1, keepdims=True)
    else:
        # Wavelengths longer than the scan appear in it as smooth trends; a Hann window leaks
        # them into the band as ~q^-6, above a steep spectrum (D near 1). A cubic per scan
        # removes them first.
        x = np.linspace(-1.0, 1.0, n)
        basis = np.polynomial.legendre.legvander(x, DETREND_DEGREE)
        coefficients, *_ = np.linalg.lstsq(basis, rows.reshape(-1, n).T, rcond=None)
        detrended = rows - (basis @ coefficients).T.reshape(rows.shape)
        window = np.hanning(n)
        windowed = detrended * window / np.sqrt(np.mean(window**2))
    spectrum = np.fft.rfft(windowed, axis=-1)
    q = 2 * np.pi * np.arange(spectrum.shape[-1]) / (n * dx)
    C = dx * np.abs(spectrum) ** 2 / n
    keep = (q > 0) & (q < np.pi / dx)
    return q[keep], C[..., keep]


def structure_functions(rows, dx, max_lag: int):
    """`τ` (m) and `S(τ) = <(h(x+τ) - h(x))²>` of each row, lags 1 … `max_lag` (non-periodic pairs)."""
    rows = np.asarray(rows, dtype=float)
    n = rows.shape[-1]
    # Wavelengths longer than the scan add a tilt, and a tilt adds (slope τ)² to S(τ).
    x = np.arange(n) - (n - 1) / 2
    rows = rows - rows.mean(axis=-1, keepdims=True)
    rows = rows - (rows * x).sum(axis=-1, keepdims=True) / (x * x).sum() * x
    padded = np.fft.rfft(rows, 2 * n, axis=-1)
    products = np.fft.irfft(np.abs(padded) ** 2, 2 * n, axis=-1)[..., : max_lag + 1]
    squares = np.cumsum(rows**2, axis=-1)
    lags = np.arange(1, max_lag + 1)
    # Σ_{i<n-k} h_i² + h_{i+k}², from the cumulative sums.
    head = squares[..., n - 1 - lags]
    tail = squares[..., -1:] - np.concatenate([np.zeros(rows.shape[:-1] + (1,)), squares], axis=-1)[..., lags]
    S = (head + tail - 2 * products[..., 1:]) / (n - lags)
    return lags * dx, S


def log_bins(x, values, lower, upper, per_decade: int = 10, counts: bool = False):
    """Averages of `values` (last axis along `x`) in log-spaced bins of `x` within [lower, upper]:
    `(bin centres (geometric mean of x), mean values)`, and with `counts` the number of values
    in each bin; empty bins dropped."""
    count = max(int(np.ceil(per_decade * np.log10(upper / lower))), 1)
    edges = np.geomspace(lower, upper, count + 1)
    index = np.digitize(x, edges) - 1
    centres, means, sizes = [], [], []
    for k in range(count):
        inside = index == k
        if inside.any():
            centres.append(np.exp(np.mean(np.log(x[inside]))))
            means.append(values[..., inside].mean(axis=-1))
            sizes.append(inside.sum())
    if not centres:
        result = np.zeros(0), np.zeros(values.shape[:-1] + (0,))
    else:
        result = np.array(centres), np.stack(means, axis=-1)
    return (*result, np.array(sizes, dtype=float)) if counts else result


def line_fit(log_x, log_y, weights=None):
    """Weighted least-squares `log_y = intercept + slope · log_x` along the last axis: `(slope, intercept)`."""
    log_x = np.asarray(log_x)
    w = np.ones_like(log_x) if weights is None else np.asarray(weights, dtype=float)
    w = w / w.sum()
    x_mean = (w * log_x).sum()
    y_mean = (np.asarray(log_y) * w).sum(axis=-1)
    centred = log_x - x_mean
    slope = (np.asarray(log_y) * w * centred).sum(axis=-1) / (w * centred * centred).sum()
    return slope, y_mean - slope * x_mean


def curvature(log_x, log_y):
    """The quadratic coefficient of a least-squares parabola in log-log (0 for a power law)."""
    return np.polyfit(np.asarray(log_x), np.asarray(log_y).T, 2)[0]


def grid_spacing(topography):
    """The spacing (m) of a profile, or a map's per axis of its heights (pixels need not be square)."""
    sizes = np.atleast_1d(np.asarray(topography.physical_sizes, dtype=float))
    spacings = sizes / np.atleast_1d(topography.nb_grid_pts)
    return float(spacings[0]) if spacings.size == 1 else tuple(float(x) for x in spacings)


def rows_of(topography):
    """Line scans (along x) as rows, the spacing, the scan length, whether periodic, and the kind."""
    heights = np.asarray(topography.heights(), dtype=float)
    length = float(np.atleast_1d(topography.physical_sizes)[0])
    dx = float(np.atleast_1d(grid_spacing(topography))[0])
    if heights.ndim == 1:
        return heights[None, :], dx, length, bool(topography.is_periodic), Profile()
    return heights.T, dx, length, bool(topography.is_periodic), Areal()


def binned_structure_function(blocks, dx, band):
    binned = []
    for block in blocks:
        tau, S = structure_functions(block, dx, int(band[1] / dx))
        centres, means = log_bins(tau, S.mean(axis=0), band[0], band[1])
        binned.append(means)
    return centres, np.array(binned), np.ones(len(centres))


def full_structure_function(blocks, dx):
    """The groups' mean structure function up to half a group's scan."""
    lag = blocks[0].shape[1] // 2
    curves = [structure_functions(block, dx, lag) for block in blocks]
    return curves[0][0], np.mean([S.mean(axis=0) for _, S in curves], axis=0)
