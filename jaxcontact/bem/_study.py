"""The boundary-element reference of a scene: several synthesised realisations of its surface,
their mean and spread, and the grid's convergence (docs/model.md §10)."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from ..numerics._validate import InputError, check_choice
from ._cache import ResultCache
from ._solver import BEMResult, BEMSettings, bem_stiffness
from ._surfaces import check_grid, check_grid_points, check_realisations, coarsened, synthesised_surface

# Surfaces are synthesised on at least this grid and coarsened to the solve's grid by Fourier
# truncation, so that a realisation (a seed) is the same surface whatever grid solves it.
SYNTHESIS_GRID = 512


@dataclasses.dataclass(frozen=True)
class ReferenceCurves:
    """K(F) of a scene's surface by the BEM over `realisations` seeds.

    **Fields:** `results` (one `BEMResult` per realisation), `seeds`, `grid`; `convergence`, the
    `BEMResult` of the first realisation on the grid `grid/2` (None if not asked for).
    **Properties:** `stiffness` (realisations × loads), `mean`, `low`, `high` (over realisations,
    NaN where any is flagged), `grid_change` (K at grid/2 over K at grid, minus 1).
    """

    results: tuple[BEMResult, ...]
    seeds: tuple[int, ...]
    grid: int
    convergence: BEMResult | None

    @property
    def loads(self):
        return self.results[0].loads

    @property
    def stiffness(self):
        return np.array([r.stiffness for r in self.results])

    @property
    def contact_fraction(self):
        return np.mean([r.contact_fraction for r in self.results], axis=0)

    @property
    def ok(self):
        return np.all([r.status == 0 for r in self.results], axis=0)

    @property
    def mean(self):
        return np.where(self.ok, np.mean(self.stiffness, axis=0), np.nan)

    @property
    def low(self):
        return np.where(self.ok, np.min(self.stiffness, axis=0), np.nan)

    @property
    def high(self):
        return np.where(self.ok, np.max(self.stiffness, axis=0), np.nan)

    @property
    def grid_change(self):
        if self.convergence is None:
            return None
        return self.convergence.stiffness / self.results[0].stiffness - 1.0


def realisation(D, G, l_min, size, grid, seed):
    """Realisation `seed` of the surface, synthesised on `max(grid, SYNTHESIS_GRID)` points per side
    and coarsened to `grid` (the same surface on every grid that resolves `l_min`)."""
    check_grid_points(grid)
    check_grid(l_min, size, grid)
    fine = max(grid, SYNTHESIS_GRID)
    surface = synthesised_surface(D, G, l_min, size, fine, seed)
    return coarsened(surface, fine // grid) if fine > grid else surface


REFERENCES = ("jax", "contactmechanics")


def jax_curve(topography, modulus: float, loads, settings: BEMSettings = BEMSettings()) -> BEMResult:
    """`bem_stiffness`'s result by the JAX solve (`solve`) on a periodic map: the same secant in ln F
    (`settings.relative_step`), the same status codes.

    **Raises:** `ValueError` for a map that is not square or whose pixels are not (`bem_stiffness`
    takes those)."""
    import jax.numpy as jnp

    from ._contact import solve

    (nx, ny), (lx, ly) = topography.nb_grid_pts, (float(s) for s in topography.physical_sizes)
    # The JAX solve's kernel is that of a square of square pixels: on any other map its K is wrong.
    if nx != ny or abs(lx - ly) > 1e-9 * lx:
        raise InputError(
            f"the map has {nx} x {ny} points over {lx:.6g} x {ly:.6g} m: the JAX solve takes a square map of "
            "square pixels (equal points and sides); bem_stiffness (ContactMechanics) takes any"
        )
    heights = jnp.asarray(topography.heights())
    size = lx
    loads = np.atleast_1d(np.asarray(loads, dtype=float))
    sol = solve(heights, size, modulus, jnp.asarray(loads, heights.dtype), secant=settings.relative_step)
    return BEMResult(
        loads=loads,
        stiffness=np.asarray(sol.secant_stiffness, dtype=float),
        offset=np.asarray(sol.offset, dtype=float),
        contact_fraction=np.asarray(sol.contact_fraction, dtype=float),
        status=np.asarray(sol.status, dtype=np.int32),
        iterations=np.asarray(sol.iterations, dtype=int),
        grid=tuple(int(n) for n in topography.nb_grid_pts),
        size=tuple(float(s) for s in topography.physical_sizes),
        modulus=float(modulus),
    )


def reference_curves(
    scene,
    loads,
    *,
    grid: int = 512,
    realisations: int = 3,
    seed: int = 0,
    convergence: bool = True,
    settings: BEMSettings = BEMSettings(),
    cache: ResultCache | None = None,
    progress: Callable[[int, int], None] | None = None,
    reference: str = "jax",
) -> ReferenceCurves:
    """The BEM K(F) of a scene's surface (D, G, l_min; `A_a = L²`) and modulus, over realisations.

    **Arguments:** `scene` (a `jaxcontact.Scene`; its E is the contact modulus), `loads` (N),
    `grid` (points per side, a power of two that gives `l_min` ≥ 4 grid spacings),
    `realisations` (seeds `seed`, `seed + 1`, ...), `convergence` (also solve the first realisation
    on `grid/2`), `settings`, `cache` (ContactMechanics's results), `progress` (called as
    `progress(done, total)` over all loads), `reference`: "jax" (`solve`, the default) or
    "contactmechanics" (`bem_stiffness`, the independent check); both solve the same discretisation
    and agree to their tolerances.
    """
    check_choice("reference", reference, REFERENCES)
    check_realisations(realisations)
    D, G, l_min = (float(x) for x in (scene.surface.D, scene.surface.G, scene.surface.l_min))
    size, modulus = math.sqrt(float(scene.area)), float(scene.material.E)
    loads = np.atleast_1d(np.asarray(loads, dtype=float))
    seeds = tuple(range(seed, seed + realisations))
    surfaces = [realisation(D, G, l_min, size, grid, s) for s in seeds]
    total = len(loads) * (len(seeds) + (1 if convergence else 0))
    done = [0]

    def advance(step, _):
        if progress is not None:
            progress(done[0] + step, total)

    def curve(surface):
        if reference == "jax":
            result = jax_curve(surface, modulus, loads, settings)
            advance(len(loads), None)
            return result
        return bem_stiffness(surface, modulus, loads, settings=settings, cache=cache, progress=advance)

    results = []
    for surface in surfaces:
        results.append(curve(surface))
        done[0] += len(loads)
    coarse = curve(coarsened(surfaces[0])) if convergence else None
    return ReferenceCurves(tuple(results), seeds, grid, coarse)
