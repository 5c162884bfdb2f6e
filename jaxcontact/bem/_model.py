"""The boundary-element reference as a contact model: `Scene(..., model=BEM(...))` solves the scene's
own surface (synthesised from D, G, l_min with A_a = L², §8) with the JAX solve, through `jc.solve`,
`fitting.fit` and the command line like any model."""

from __future__ import annotations

import math
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp

from ..models import AbstractSweptModel, JointResponse, PathPoints, PointResult, without_single_spots
from ..numerics._validate import InputError, check_instance, check_range
from ..physics import MeasuredSpectrum
from ..quantities import Status, nondimensionalise
from ._checks import check_iteration, checked_status, stand_in_loads
from ._contact import DEFAULT_TOLERANCE, sweep_sides
from ._fft import AbstractFFT, LocalFFT, check_fft
from ._operator import Periodic
from ._path import solve_path_grid
from ._problem import GridProblem
from ._solver import secant_stiffness
from ._surfaces import PIXELS_PER_L_MIN, check_grid_points, check_realisations
from ._synthesis import spectrum_heights, synthesised_heights


class BEM(AbstractSweptModel):
    """The elastic (or perfectly plastic) boundary-element contact of the scene's surface (§10).

    **Arguments:**

    - `grid`: points a side, a power of two ≥ 8 (l_min must span 4 grid spacings, else the point
      is flagged `INVALID_PARAMETERS`).
    - `realisations`, `seed`: the surface's random realisations (seeds `seed`, `seed + 1`, ...: the
      surfaces of `bem.reference_curves`); K is their mean.
    - `plastic`: cap the pressure at the scene's hardness H.
    - `relative_step`: ε of the secant stiffness `2F sinh(ε)/(δ(F e^ε) − δ(F e^−ε))`, the mean
      compliance over loads within a factor e^±ε; 0 gives the exact tangent of the discretised
      contact, piecewise constant in D, G, l_min. The approach δ is continuous in the parameters
      but kinked wherever a grid point enters contact, so a secant over a wide step is what a
      gradient can fit: with the default 0.2, the local d ln K/dD over D ± 0.01 stays within 0.89–1.13
      of its mean slope on 256² (0.70–1.27 with the reference's ε = 0.02, 0–2.6 on 64²), and K lies
      within −0.3 % to +1.4 % of the exact tangent (0.8–22 % of the grid in contact, D = 1.3–1.7).
    - `rolloff`: the width, in modes, of the spectrum's cutoff at 2π/l_min (0: sharp, the reference's
      surfaces exactly, and results piecewise constant in l_min).
    - `tolerance` (in (0, 1e-5], None for the precision's default), `max_iterations` (≥ 1),
      `preconditioned`: of the constrained conjugate gradients (`bem.solve`).
    - `fft`: `bem.LocalFFT()`, or `bem.DistributedFFT(mesh, axis)` to split each realisation's
      rows over the devices of a mesh (`bem.solve`; `grid` a multiple of their count).
    - `spectrum`: None (the scene's self-affine C2D from D, G and l_min) or a `MeasuredSpectrum`,
      whose table (cut at its last point, which the grid must resolve as it resolves l_min) the
      realisations then have instead.

    One regime, "e"; `Solution.real_area` is the mean contact area, `Solution.a_l` NaN. Each load is
    its own solve (two for the secant) per realisation, all loads of a call in one increasing sweep
    from the last load's pressure: eager solves and fits do not pad the loads.
    """

    name: ClassVar[str] = "bem"
    regimes: ClassVar[tuple[str, ...]] = ("e",)
    pad_loads: ClassVar[bool] = False
    # The contact set moves a grid point at a time as D, G, l_min change: K is smooth only to ~1e-6.
    precision: ClassVar[float] = 1e-6
    single_spots: ClassVar[bool] = False
    grid: int = eqx.field(static=True, default=256)
    realisations: int = eqx.field(static=True, default=2)
    seed: int = eqx.field(static=True, default=0)
    plastic: bool = eqx.field(static=True, default=False)
    relative_step: float = eqx.field(static=True, default=0.2)
    rolloff: float = eqx.field(static=True, default=2.0)
    tolerance: float | None = eqx.field(static=True, default=None)
    max_iterations: int = eqx.field(static=True, default=2000)
    preconditioned: bool = eqx.field(static=True, default=True)
    fft: AbstractFFT = LocalFFT()
    spectrum: MeasuredSpectrum | None = None

    def __check_init__(self):
        check_grid_points(self.grid)
        check_realisations(self.realisations)
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise InputError(f"seed = {self.seed!r} must be an integer >= 0")
        check_range("relative_step", self.relative_step, 0.0, 0.5, low_open=False)
        check_range("rolloff", self.rolloff, 0.0, 64.0, low_open=False)
        check_iteration(self.tolerance, self.max_iterations)
        check_fft(self.fft, self.grid)
        if self.spectrum is not None:
            check_instance("spectrum", self.spectrum, MeasuredSpectrum)

    def unloads_as_it_loads(self):
        # Elastic: unloading retraces loading. A capped surface keeps its flattening (a load path).
        return not self.plastic

    def spot_solver(self, s):
        raise without_single_spots(self)

    def kink_log_loads(self, s):
        return jnp.zeros((0,), jnp.result_type(s.D))

    def _heights(self, s, dtype):
        """Each realisation's heights in units of L = sqrt(A_a), from the dimensionless scene `s`."""
        seeds = tuple(range(self.seed, self.seed + self.realisations))
        if self.spectrum is not None:
            return spectrum_heights(self.spectrum, s.log_length, self.grid, seeds, self.rolloff, dtype)
        return synthesised_heights(s.D, s.log_G, s.log_a_min, self.grid, seeds, self.rolloff, dtype)

    def heights(self, scene):
        """The surfaces this model solves for `scene`: `realisations × grid × grid` heights, m, on a
        square of side sqrt(A_a) (periodic), in JAX's default float precision."""
        dtype = jnp.result_type(1.0)
        return self._heights(nondimensionalise(scene), dtype) * jnp.sqrt(jnp.asarray(scene.area, dtype))

    def _resolved(self, s):
        """Whether l_min (a measured spectrum's shortest wavelength) spans `PIXELS_PER_L_MIN` grid
        spacings (else every point is flagged)."""
        if self.spectrum is None:
            log_l_min = 0.5 * s.log_a_min
        else:
            log_l_min = math.log(2 * math.pi) - self.spectrum.log_q[-1] - s.log_length
        return log_l_min >= math.log(PIXELS_PER_L_MIN / self.grid) - 1e-12

    def _cap_and_tolerance(self, s, dtype):
        """The hardness cap (None unless `plastic`, in units of E) and the iteration's tolerance."""
        hardness = jnp.exp(s.log_hardness) if self.plastic else None
        return hardness, self.tolerance or DEFAULT_TOLERANCE.get(jnp.dtype(dtype), 1e-5)

    def path_solver(self, s):
        dtype = jnp.result_type(s.D)
        heights = self._heights(s, dtype)
        hardness, tolerance = self._cap_and_tolerance(s, dtype)
        settings = (Periodic(), tolerance, self.max_iterations, self.preconditioned, self.fft)

        def follow(F_star) -> PathPoints:
            # One realisation after another, as `sweep_solver`'s capped curves.
            paths = jax.lax.map(lambda h: solve_path_grid(h, 1.0, 1.0, F_star, hardness, *settings), heights)
            status = jnp.where(self._resolved(s), jnp.max(paths.status, axis=0), Status.INVALID_PARAMETERS)
            ok = status == Status.OK
            mean = lambda x: jnp.where(ok, jnp.mean(x, axis=0), jnp.nan)  # noqa: E731
            return PathPoints(
                approach_star=mean(paths.approach),
                stiffness_star=mean(paths.stiffness),
                unloading_star=mean(paths.unloading_stiffness),
                real_area_star=jnp.mean(paths.contact_fraction, axis=0),
                status=status.astype(jnp.int32),
                residual_star=jnp.where(jnp.all(ok), jnp.mean(paths.residual_approach), jnp.nan),
            )

        return follow

    def sweep_solver(self, s):
        dtype = jnp.result_type(s.D)
        heights = self._heights(s, dtype)
        resolved = self._resolved(s)
        hardness, tolerance = self._cap_and_tolerance(s, dtype)

        # Lengths in L = sqrt(A_a), pressures in E: a load is F*, a stiffness K*.
        def problem(h):
            return GridProblem.build(h, 1.0, 1.0, hardness, Periodic(), self.preconditioned, None, self.fft)

        problems = jax.vmap(problem)(heights)
        step = self.relative_step
        sides = (-step, step) if step > 0 else (0.0,)

        def one_realisation(problem, loads):
            # All loads (and both sides of each secant) in one increasing sweep, warm-started.
            out = sweep_sides(problem, loads, sides, tolerance, self.max_iterations)
            status = jnp.max(out["status"], axis=0)
            if step > 0:
                rise = (out["offset"][1] - out["offset"][0]) * problem.scale
                stiffness = secant_stiffness(loads, step, jnp.where(status == Status.OK, rise, 1.0))
            else:
                stiffness = out["stiffness"][0] * problem.stiffness_unit
            return stiffness, jnp.mean(out["contact_fraction"], axis=0), checked_status(status, (stiffness,))

        def curve(F_star) -> PointResult:
            loads, valid = stand_in_loads(F_star, 1e-4)
            if self.plastic:
                # One realisation after another: under `vmap` the iteration's `lax.cond` would compute
                # its plastic mixing step (a sort of the grid) at every step of every realisation.
                stiffness, fraction, status = jax.lax.map(lambda problem: one_realisation(problem, loads), problems)
            else:
                stiffness, fraction, status = jax.vmap(one_realisation, in_axes=(0, None))(problems, loads)
            status = jnp.select(
                [~resolved, ~valid],
                [Status.INVALID_PARAMETERS, Status.INVALID_LOAD],
                jnp.max(status, axis=0),
            ).astype(jnp.int32)
            ok = status == Status.OK
            mean = jnp.mean(jnp.where(ok, stiffness, 1.0), axis=0)
            response = JointResponse(loads[:, None], mean[:, None], jnp.mean(fraction, axis=0), jnp.zeros_like(ok))
            return PointResult(jnp.full_like(loads, jnp.nan), response, status)

        return curve
