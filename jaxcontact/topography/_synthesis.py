"""Synthetic surfaces with known D, G and short cutoff, seeded (docs/model.md §8)."""

from __future__ import annotations

import math

import numpy as np

from ..numerics._validate import optional_import
from ._conventions import GAMMA, areal_prefactor, check_D, check_positive, profile_prefactor


def wm_profile(D, G, length, points, *, l_min=None, seed=0):
    """A Weierstrass–Mandelbrot profile with random phases, as a SurfaceTopography line scan.

    `z(x) = G^(D-1) Σ_n cos(2π γ^n x + φ_n) / γ^((2-D) n)` over the frequencies `γ^n` from
    `1/length` to `1/l_min` (default: two grid spacings), γ = 1.5, heights in m.

    **Arguments:** `D` (1 < D < 2), `G` (m, W-M convention), `length` (m), `points`, `l_min` (m),
    `seed`. **Returns:** a periodic-free `SurfaceTopography.UniformLineScan` in metres.
    """
    UniformLineScan = optional_import("SurfaceTopography", "synthesising a profile").UniformLineScan

    D = float(check_D(D))
    for name, value in (("G", G), ("length", length)):
        check_positive(name, value)
    if l_min is None:
        l_min = 2.0 * length / points
    check_positive("l_min", l_min)
    x = np.arange(points) * (length / points)
    n = np.arange(math.ceil(math.log(1.0 / length, GAMMA)), math.floor(math.log(1.0 / l_min, GAMMA)) + 1)
    phases = np.random.default_rng(seed).uniform(0.0, 2.0 * math.pi, n.size)
    frequencies = GAMMA**n
    heights = np.zeros(points)
    for w, a, phi in zip(frequencies, G ** (D - 1) * GAMMA ** (-(2 - D) * n), phases):
        heights += a * np.cos(2 * math.pi * w * x + phi)
    return UniformLineScan(heights, length, periodic=False, unit="m")


def _fourier(D, G, size_name, size, grid, l_min, seed, prefactor):
    """SurfaceTopography's Fourier synthesis of a self-affine surface, `grid` points per side."""
    fourier_synthesis = optional_import("SurfaceTopography.Generation", "synthesising a surface").fourier_synthesis

    D = float(check_D(D))
    for name, value in (("G", G), (size_name, size)):
        check_positive(name, value)
    if l_min is not None:
        check_positive("l_min", l_min)
    return fourier_synthesis(
        grid,
        (size,) * len(grid),
        hurst=2.0 - D,
        c0=float(prefactor(D, G)),
        short_cutoff=l_min,
        rng=np.random.default_rng(seed),
        unit="m",
    )


def areal_map(D, G, size, grid, *, l_min=None, seed=0):
    """An isotropic, periodic self-affine map with `C2D = C0 q^-(6-2D)` (docs/model.md §8): its line
    scans have the PSD of the W-M profile with this D and G. SurfaceTopography's Fourier
    synthesis, with a short cutoff `l_min` (default: the grid's Nyquist wavelength).

    **Arguments:** `D`, `G` (m, W-M), `size` (m, square), `grid` (points per side), `l_min` (m),
    `seed`. **Returns:** a periodic `SurfaceTopography.Topography` in metres.
    """
    return _fourier(D, G, "size", size, (grid, grid), l_min, seed, areal_prefactor)


def random_profile(D, G, length, points, *, l_min=None, seed=0):
    """A self-affine line scan with random phases and amplitudes and the W-M profile's mean PSD,
    `C1D = K1 q^-(5-2D)` (docs/model.md §8): the continuous-spectrum twin of `wm_profile`, whose
    spectrum is a comb of lines. SurfaceTopography's Fourier synthesis; periodic.

    **Arguments:** as `wm_profile`. **Returns:** a `SurfaceTopography.UniformLineScan` in metres.
    """
    return _fourier(D, G, "length", length, (points,), l_min, seed, profile_prefactor)
