"""K(F) of a rough surface by the elastic boundary-element method (docs/model.md §10).

A rigid flat pressed on an elastic half-space (contact modulus E) with the rough surface's
heights, frictionless and non-adhesive, solved by ContactMechanics (MIT; the `bem` extra): the
FFT boundary-element system of `make_system` and Polonsky & Keer's constrained conjugate
gradients under load control. The stiffness is `K = dF/dδ` by a central difference in `ln F`,
`K = 2F sinh(ε) / (δ(F e^ε) - δ(F e^-ε))`, from the rigid offset δ of three solves. A periodic
half-space has an arbitrary q = 0 compliance; `stiffness_q0 = 0` removes it, so that the offset
is the mean separation's change.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import equinox as eqx
import numpy as np

from ..models import CLOSED_INTERFACE
from ..numerics._validate import InputError, check_range, check_strategy, optional_import, spelled
from ..quantities import Status
from ._cache import ResultCache
from ._operator import REFERENCE, SUBSTRATES, AbstractSubstrate, Periodic

# The reference's secant step: within 0.1–0.3 % of the exact tangent on fractal surfaces (validation.md).
REFERENCE_STEP = 0.02


class BEMSettings(eqx.Module):
    """How the boundary-element reference is solved.

    **Arguments:** `relative_step`, ε of the central difference in `ln F` (its truncation error is
    `O(ε²)`: 5e-5 at 0.02); `penetration_tolerance`, Polonsky–Keer's tolerance on penetration, as a
    fraction of `rms height / n` (1e-4 resolves the offsets' differences to ~1e-6 of K);
    `max_iterations`, the cap on each solve's iterations (a solve that reaches it is reported
    `NOT_CONVERGED`, never waited on).
    """

    relative_step: float = eqx.field(static=True, default=REFERENCE_STEP)
    penetration_tolerance: float = eqx.field(static=True, default=1e-4)
    max_iterations: int = eqx.field(static=True, default=5000)

    def __check_init__(self):
        check_range("relative_step", self.relative_step, 0.0, 0.5)
        check_range("penetration_tolerance", self.penetration_tolerance, 0.0, 1.0)
        check_range("max_iterations", self.max_iterations, 1, 10**7, low_open=False, high_open=False)


@dataclasses.dataclass(frozen=True)
class BEMResult:
    """The boundary-element K(F) of one surface, one entry per load.

    **Fields:** `loads` (N), `stiffness` (N/m; NaN unless `status == 0`), `offset` (the rigid
    offset δ at F, m), `contact_fraction` (A_r/A_a), `status` (`jaxcontact.Status`: OK,
    NOT_CONVERGED, LOAD_OUT_OF_RANGE for a closed interface), `iterations` (of the three solves),
    `grid` (points per side), `size` (m per side), `modulus` (Pa).
    """

    loads: np.ndarray
    stiffness: np.ndarray
    offset: np.ndarray
    contact_fraction: np.ndarray
    status: np.ndarray
    iterations: np.ndarray
    grid: tuple[int, ...]
    size: tuple[float, ...]
    modulus: float


def secant_stiffness(load, step: float, rise):
    """`2F sinh(ε) / (δ(F e^ε) − δ(F e^−ε))`: the stiffness from the rise `rise` of the offset between
    the loads `F e^±ε` (numpy or JAX)."""
    return 2.0 * load * math.sinh(step) / rise


def _substrate(topography, substrate: AbstractSubstrate | None) -> AbstractSubstrate:
    if substrate is None:
        if not topography.is_periodic:
            free = spelled("substrate = bem.Free()", "--substrate free")
            periodic = spelled("substrate = bem.Periodic()", "--substrate periodic")
            raise InputError(
                f"the topography is not periodic: choose {free} (an isolated half-space; the grid is doubled) "
                f"or {periodic} (the map repeated; its edges then meet as a step)"
            )
        return Periodic()
    check_strategy("substrate", substrate, AbstractSubstrate, SUBSTRATES, "bem")
    return substrate


class _Unlogged:
    """A logger for ContactMechanics's solver that keeps nothing. Its default (`Logger(None)`, one
    object for the process) keeps every line it is given in memory, and finds each message's caller
    by walking the whole call stack (`inspect.stack`, which reads every frame's source file)."""

    def pr(self, *args, **kwargs) -> None:
        pass

    def st(self, *args, **kwargs) -> None:
        pass


_UNLOGGED = _Unlogged()


def _one_load(system, topography, load, pentol: float, settings: BEMSettings):
    options = dict(pentol=pentol, forcetol=1e-12 * load, maxiter=settings.max_iterations, logger=_UNLOGGED)
    centre = system.minimize_proxy(external_force=load, **options)
    iterations = int(centre.nit)
    # Counted over the surface's own grid: a free half-space's force array is the padded one.
    fraction = float(np.count_nonzero(centre.jac > 0) / np.prod(topography.nb_grid_pts)) if centre.success else math.nan
    if not centre.success:
        return dict(
            stiffness=math.nan, offset=math.nan, fraction=fraction, status=Status.NOT_CONVERGED, iterations=iterations
        )
    if fraction >= CLOSED_INTERFACE:
        return dict(
            stiffness=math.nan,
            offset=float(centre.offset),
            fraction=fraction,
            status=Status.LOAD_OUT_OF_RANGE,
            iterations=iterations,
        )
    offsets, status = [], Status.OK
    for sign in (-1.0, 1.0):
        factor = math.exp(sign * settings.relative_step)
        side = system.minimize_proxy(external_force=load * factor, **options)
        iterations += int(side.nit)
        offsets.append(float(side.offset))
        status = status if side.success else Status.NOT_CONVERGED
    stiffness = secant_stiffness(load, settings.relative_step, offsets[1] - offsets[0])
    if status != Status.OK or not stiffness > 0:
        stiffness, status = math.nan, Status.NOT_CONVERGED
    return dict(
        stiffness=stiffness, offset=float(centre.offset), fraction=fraction, status=status, iterations=iterations
    )


def bem_stiffness(
    topography,
    modulus: float,
    loads,
    *,
    substrate: AbstractSubstrate | None = None,
    settings: BEMSettings = BEMSettings(),
    cache: ResultCache | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> BEMResult:
    """The boundary-element K(F) of an areal topography (docs/model.md §10).

    **Arguments:**

    - `topography`: a SurfaceTopography areal topography in metres (`jaxcontact.topography._read`,
      `synthesised_surface`).
    - `modulus`: the contact modulus E, Pa (`young` of ContactMechanics).
    - `loads`: total normal loads, N, each finite and > 0.
    - `substrate`: `Periodic()` (the map repeats; `stiffness_q0 = 0`) or `Free()` (an isolated
      half-space). None takes `Periodic()` for a periodic map and refuses a non-periodic one.
    - `settings`: `BEMSettings` (difference step, tolerance, iteration cap).
    - `cache`: a `ResultCache`; each load's result is kept on disk keyed by every input, and an
      entry that fails its check is recomputed (with a `CacheWarning`), never used.
    - `progress`: called as `progress(done, total)` after each load.

    **Returns:** a `BEMResult`. A solve that reaches the iteration cap gives `NOT_CONVERGED`; a
    load that closes the interface (contact fraction ≥ 0.99) gives `LOAD_OUT_OF_RANGE`.
    """
    make_system = optional_import("ContactMechanics", REFERENCE).make_system

    check_range("modulus", modulus, 0.0)
    loads = np.atleast_1d(np.asarray(loads, dtype=float))
    if loads.size == 0:
        raise InputError("loads is empty: give at least one load (valid range (0, inf) N)")
    check_range("loads", loads, 0.0)
    substrate = _substrate(topography, substrate)
    system = make_system(substrate=substrate.reference(topography, float(modulus)), surface=topography)
    heights = topography.heights()
    pentol = settings.penetration_tolerance * float(np.std(heights)) / float(np.mean(topography.nb_grid_pts))
    rows = []
    if cache is not None:
        surface_key = cache.surface_key(heights, topography.physical_sizes, modulus, substrate, settings)
    for done, load in enumerate(loads, start=1):
        key, row, invalid = None, None, None
        if cache is not None:
            key = cache.key(surface_key, load)
            row, invalid = cache.lookup(key)
        if row is None:
            row = _one_load(system, topography, float(load), pentol, settings)
            if cache is not None:
                cache.put(key, row)
                if invalid:
                    cache.report_invalid(key, invalid)
        rows.append(row)
        if progress is not None:
            progress(done, len(loads))
    column = {name: np.array([row[name] for row in rows]) for name in rows[0]}
    return BEMResult(
        loads=loads,
        stiffness=column["stiffness"].astype(float),
        offset=column["offset"].astype(float),
        contact_fraction=column["fraction"].astype(float),
        status=column["status"].astype(np.int32),
        iterations=column["iterations"].astype(int),
        grid=tuple(int(n) for n in topography.nb_grid_pts),
        size=tuple(float(s) for s in topography.physical_sizes),
        modulus=float(modulus),
    )
