"""A scene's surface synthesised in JAX: differentiable in D, G and l_min, with fixed random phases.

The isotropic self-affine surface of docs/model.md §8, `C2D(q) = C0(D, G) q^-(6-2D)` on
`[2π/L, 2π/l_min]`, as SurfaceTopography's `fourier_synthesis` makes it: Fourier coefficients
`√C0 q^-(3-D) a_q e^(iφ_q)` with the normal amplitudes and uniform phases it draws from the seed,
row by row, on a 512² grid (the reference's `SYNTHESIS_GRID`), truncated to the solve's grid. With
a sharp cutoff (`rolloff = 0`) the heights are those of `bem.realisation` to round-off, so that the
JAX solve and ContactMechanics can be compared surface by surface. On a grid a sharp cutoff makes
the surface, and so every result, piecewise constant in l_min (a mode is in or out); with
`rolloff = w > 0` the cutoff is `½ erfc((q − 2π/l_min)/(w Δq))`, smooth over a few modes
(`Δq = 2π/L`), and results have a derivative with respect to l_min.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np
from jax.scipy.special import erfc

from ..numerics import cached
from ..numerics._compat import complex_dtype
from ..physics._spectrum import log_areal_prefactor
from ._study import SYNTHESIS_GRID


@cached
def noise(seed: int, grid: int) -> np.ndarray:
    """The seed's white noise, as `fourier_synthesis` draws and symmetrises it on the synthesis grid,
    truncated to `grid` (complex, numpy's fft2 layout), times `grid²` (numpy's ifft2 normalisation)."""
    fine = max(grid, SYNTHESIS_GRID)
    rng = np.random.default_rng(seed)
    columns = fine // 2 + 1
    spectrum = np.empty((fine, columns), complex)
    for row in range(fine):
        phase = np.exp(2 * np.pi * rng.random(columns) * 1j)
        spectrum[row] = phase * rng.normal(size=columns)
    spectrum[0, 0] = 0.0
    for column in (0, -1):  # as fourier_synthesis makes the real field's redundant columns consistent
        spectrum[0, column] = spectrum[0, column].real
        spectrum[fine // 2, column] = spectrum[fine // 2, column].real
        spectrum[1 : fine // 2, column] = spectrum[-1 : fine // 2 : -1, column].conj()
    full = np.fft.fft2(np.fft.irfft2(spectrum, s=(fine, fine)))
    kept = np.r_[0 : (grid + 1) // 2, fine - grid // 2 : fine]
    return full[np.ix_(kept, kept)] * grid * grid


@cached
def _wavevectors(grid: int) -> np.ndarray:
    """|q| L on the grid's fft2 layout."""
    k = np.fft.fftfreq(grid, 1.0 / grid)
    return 2 * math.pi * np.sqrt(k[:, None] ** 2 + k[None, :] ** 2)


def _cutoff(q, q_max, rolloff: float, dtype):
    """The spectrum's short end at `q_max` (module docstring): sharp, or smooth over `rolloff` modes."""
    if rolloff > 0:
        return 0.5 * erfc((q - q_max) / (rolloff * 2 * math.pi))
    return (q <= q_max * (1 + 1e-9)).astype(dtype)  # a mode on the cutoff is kept, as SurfaceTopography keeps it


def _realised(amplitude, grid: int, seeds: tuple[int, ...]):
    """Heights (`realisations × grid × grid`) of the Fourier amplitudes `√C*` times each seed's noise."""
    noises = jnp.asarray(np.stack([noise(seed, grid) for seed in seeds]), complex_dtype(amplitude.dtype))
    return jnp.real(jnp.fft.ifft2(amplitude.astype(noises.dtype) * noises))


def synthesised_heights(D, log_G, log_a_min, grid: int, seeds: tuple[int, ...], rolloff: float, dtype):
    """Heights in units of L (`realisations × grid × grid`) of the scene's surface, for each seed.

    **Arguments:** the dimensionless groups `D`, `log_G` = ln(G/L), `log_a_min` = ln(l_min²/L²);
    `grid` points a side; `seeds`; `rolloff`, the cutoff's width in modes (0: sharp).
    """
    q = jnp.asarray(_wavevectors(grid), dtype)
    q_max = 2 * math.pi * jnp.exp(-0.5 * log_a_min)
    safe_q = jnp.where(q > 0, q, 1.0)
    amplitude = jnp.exp(0.5 * log_areal_prefactor(D, log_G) - (3.0 - D) * jnp.log(safe_q))
    return _realised(jnp.where(q > 0, amplitude * _cutoff(q, q_max, rolloff, dtype), 0.0), grid, seeds)


def spectrum_heights(spectrum, log_length, grid: int, seeds: tuple[int, ...], rolloff: float, dtype):
    """The same for a measured spectrum (`jaxcontact.MeasuredSpectrum`) on a joint of side
    `exp(log_length)` m: its piecewise power law from `2π/L` to the table's last point, the seeds'
    normal amplitudes and uniform phases on it."""
    q = jnp.asarray(_wavevectors(grid), dtype)
    log_q = jnp.log(jnp.where(q > 0, q, 2 * math.pi))
    amplitude = jnp.exp(0.5 * spectrum.log_C_at(log_q, log_length))
    q_max = jnp.exp(spectrum.log_q[-1] + log_length)
    return _realised(jnp.where(q > 0, amplitude * _cutoff(q, q_max, rolloff, dtype), 0.0), grid, seeds)
