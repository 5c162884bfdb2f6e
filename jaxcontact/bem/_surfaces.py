"""The surfaces the boundary-element reference solves: synthesised from (D, G, l_min) or measured."""

from __future__ import annotations

import numpy as np

from ..numerics._validate import InputError, assigned, check_range, optional_import, spelled

# The shortest wavelength l_min must span this many grid spacings: then the surface is also
# exact on the half grid (2 points per l_min, its Nyquist limit), which the convergence check uses.
PIXELS_PER_L_MIN = 4
# The largest grid: 8192² in float64 is half a GiB a field, and the solve holds several.
MAX_GRID = 8192


def check_grid_points(grid) -> None:
    """Raise `InputError` unless `grid` is a power of two ≥ 8 (surfaces are coarsened by halving)."""
    if isinstance(grid, bool) or not isinstance(grid, int) or not 8 <= grid <= MAX_GRID or grid & (grid - 1):
        raise InputError(
            f"{assigned('grid', repr(grid))} must be a power of two in [8, {MAX_GRID}] (surfaces are coarsened by "
            "halving)"
        )


def check_realisations(count) -> None:
    """Raise `InputError` unless `count` is an integer in [1, 64]."""
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= 64:
        raise InputError(f"{assigned('realisations', repr(count))} must be an integer in [1, 64]")


def check_grid(l_min: float, size: float, grid: int) -> None:
    """Raise `InputError` unless `l_min` spans at least `PIXELS_PER_L_MIN` grid spacings."""
    check_range("grid", grid, 8, 8192, low_open=False, high_open=False)
    spacing = size / grid
    if not l_min >= PIXELS_PER_L_MIN * spacing * (1 - 1e-12):
        needed = int(np.ceil(PIXELS_PER_L_MIN * size / l_min))
        raise InputError(
            f"{assigned('grid', str(grid))} is too coarse for l_min = {l_min:.4g} m on a {size:.4g} m surface: "
            f"l_min spans {l_min / spacing:.3g} grid spacings and needs at least {PIXELS_PER_L_MIN} "
            f"({spelled('grid >= ', '--grid ')}{needed}{spelled('', ' or more')}, or "
            f"l_min >= {PIXELS_PER_L_MIN * spacing:.4g} m)"
        )


def synthesised_surface(D, G, l_min, size, grid, seed=0):
    """A periodic, isotropic self-affine surface with the `C2D` of docs/model.md §8 on `[2π/size, 2π/l_min]`.

    **Arguments:** `D` (1 < D < 2), `G` (m, W-M convention), `l_min` (m), `size` (m, the square's
    side, so A_a = size²), `grid` (points per side), `seed`.
    **Returns:** a SurfaceTopography `Topography` in metres. **Raises:** `ValueError` if `grid` does
    not resolve `l_min` (`check_grid`).
    """
    from ..topography import areal_map

    check_range("size", size, 0.0)
    check_range("l_min", l_min, 0.0, size)
    check_grid(l_min, size, grid)
    return areal_map(D, G, size, grid, l_min=l_min, seed=seed)


def coarsened(topography, factor: int = 2):
    """The same periodic surface on a grid `factor` times coarser, by truncating its Fourier series.

    For a synthesised surface whose spectrum ends at `l_min` (≥ `factor` · 2 grid spacings) this is
    the same surface exactly; for a measured one it drops the wavelengths the coarse grid cannot hold.
    """
    Topography = optional_import("SurfaceTopography", "the boundary-element reference").Topography

    nx, ny = topography.nb_grid_pts
    if nx % factor or ny % factor:
        raise InputError(f"the grid {nx} x {ny} is not divisible by {factor}")
    mx, my = nx // factor, ny // factor
    spectrum = np.fft.fft2(topography.heights())
    kept = np.zeros((mx, my), dtype=complex)
    # The lowest wavevectors, non-negative then negative, as numpy orders them on the coarse grid.
    ix = np.r_[0 : (mx + 1) // 2, nx - mx // 2 : nx]
    iy = np.r_[0 : (my + 1) // 2, ny - my // 2 : ny]
    kept[:, :] = spectrum[np.ix_(ix, iy)]
    heights = np.real(np.fft.ifft2(kept)) / (factor * factor)
    return Topography(heights, topography.physical_sizes, periodic=topography.is_periodic, unit="m")
