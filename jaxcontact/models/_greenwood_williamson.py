"""Greenwood–Williamson with Gaussian summit heights (docs/model.md §9), from the scene's power spectrum.

The summits' density `η`, mean radius `R` and height deviation `σ_s` come from the spectral
moments `m0, m2, m4` of the surface's PSD on `[2π/L, 2π/l_min]` (`physics._spectrum`) by McCool's
relations for an isotropic surface, with Nayak's bandwidth correction of the summit heights
(McCool, Wear 107, 37, 1986):

    α = m0 m4 / m2²,   η = m4 / (6π√3 m2),   R = 0.375 √(π/m4),   σ_s = √(1 - 0.8968/α) √m0.

With `h = d/σ_s` the separation of the flat from the mean summit plane in units of `σ_s`, and
`I_n(h) = ∫_h^∞ (s-h)^n φ(s) ds` (φ the standard normal density),

    F = (4/3) E η A_a √R σ_s^(3/2) I_{3/2}(h),   K = 2 E η A_a √R σ_s^(1/2) I_{1/2}(h),
    A_r = π η A_a R σ_s I_1(h).

Load control solves `F(h) = F` for `h` (`dI_n/dh = -n I_{n-1}`, so `K = -dF/dd` holds exactly).
"""

from __future__ import annotations

import math
from typing import ClassVar

import jax.numpy as jnp
import numpy as np

from ..numerics import NewtonBisection, PowerLaw, cached, check_instance
from ..physics import MeasuredSpectrum
from ..physics._spectrum import profile_moments
from ..quantities import Status
from ._base import (
    CLOSED_INTERFACE,
    LINEAR_ELASTIC_LIMIT,
    AbstractContactModel,
    separated_point,
)
from ._spots import GaussianSummitCount, Separated, SpotFamilies, SpotState

# The separations solved for: above H_HIGHEST no load a float can hold is left; below H_LOWEST
# the flat presses past the mean summit plane, where GW's independent summits do not apply (and
# where `tail_moment`'s quadrature would lose accuracy). Loads whose summit contacts add up to
# more than the nominal area, or above `LINEAR_ELASTIC_LIMIT`, are out of range too.
H_LOWEST, H_HIGHEST = -1.0, 40.0
LAGUERRE_NODES = 96
# The summits resolved one by one (partial slip), in families of interference ŵ (in σ_s): eight
# geometric ones from 1e-8 to 0.5 (a summit's load goes as ŵ^(3/2): those below carry nothing a
# float sees), then bands of 0.5 up to 12 above the flat (φ(12) ≈ 1e-32). Each family spans a few
# units of ln ŵ at most, where 16 Gauss–Legendre nodes integrate its smooth integrand to round-off.
INTERFERENCE_EDGES = tuple(np.geomspace(1e-8, 0.5, 9)) + tuple(0.5 * np.arange(2, 25))


@cached
def _laguerre(order: float):
    from scipy import special  # only where GW is used: scipy.special takes ~0.3 s to import

    return special.roots_genlaguerre(LAGUERRE_NODES, order)


def log_tail_moment(order: float, h):
    """`ln I_n(h)`, `I_n(h) = ∫_0^∞ t^n φ(h + t) dt`, for `h ≥ -1` (relative error < 1e-10 there).

    `t = u/λ` with `λ = (h + √(h² + 4))/2` makes it a generalised Gauss–Laguerre integral
    (weight `u^n e^-u`) of the smooth, bounded `exp((1 - (u-1)²)/(2λ²))`; in logs, so that the
    tail `e^(-h²/2)` of a large separation underflows nothing.
    """
    nodes, weights = _laguerre(order)
    dtype = jnp.result_type(h)
    lam = 0.5 * (h + jnp.sqrt(h * h + 4.0))
    log_terms = jnp.log(jnp.asarray(weights, dtype)) + (1.0 - (jnp.asarray(nodes, dtype) - 1.0) ** 2) / (
        2.0 * lam[..., None] ** 2
    )
    log_sum = jnp.log(jnp.sum(jnp.exp(log_terms - jnp.max(log_terms, -1, keepdims=True)), -1)) + jnp.max(log_terms, -1)
    return -0.5 * h * h - 0.5 * math.log(2.0 * math.pi) - (order + 1.0) * jnp.log(lam) + log_sum


def summit_statistics(s, spectrum: MeasuredSpectrum | None = None):
    """`(ln η*, ln R*, ln σ_s*)` of the scene's surface by McCool's relations (module docstring);
    `η* = η A_a`, `R* = R/√A_a`, `σ_s* = σ_s/√A_a`; from a measured spectrum's moments where given.
    """
    if spectrum is None:
        m0, m2, m4 = profile_moments(s.D, s.log_G, s.log_a_min)
    else:
        m0, m2, m4 = spectrum.profile_moments(s.log_length)
    alpha = m0 * m4 / (m2 * m2)
    log_eta = jnp.log(m4 / m2) - math.log(6.0 * math.pi * math.sqrt(3.0))
    log_R = math.log(0.375) + 0.5 * (math.log(math.pi) - jnp.log(m4))
    log_sigma = 0.5 * (jnp.log1p(-0.8968 / alpha) + jnp.log(m0))
    return log_eta, log_R, log_sigma


def _residual(y, args):
    # Increasing in y = -h: ln F*(h) - ln F.
    log_scale, log_load = args
    return log_scale + log_tail_moment(1.5, -y) - log_load, None


def _residual_slope(y, args):
    return 1.5 * jnp.exp(log_tail_moment(0.5, -y) - log_tail_moment(1.5, -y))


class GreenwoodWilliamson(AbstractContactModel):
    """Greenwood & Williamson (1966) with Gaussian summits from the PSD's moments (docs/model.md §9);
    every summit elastic (Hertz). One regime, "e". `Solution.a_l` is NaN: the model has no largest spot.

    **Arguments:** `root_finder`, the solve for each load's separation (`NewtonBisection()`);
    `spectrum`, None (the scene's self-affine C2D from D, G and l_min) or a `MeasuredSpectrum`,
    whose moments then replace the scene's D, G and l_min.
    """

    name: ClassVar[str] = "gw"
    regimes: ClassVar[tuple[str, ...]] = ("e",)
    root_finder: NewtonBisection = NewtonBisection()
    spectrum: MeasuredSpectrum | None = None

    def __check_init__(self):
        check_instance("root_finder", self.root_finder, NewtonBisection)
        if self.spectrum is not None:
            check_instance("spectrum", self.spectrum, MeasuredSpectrum)

    def unloads_as_it_loads(self):
        return True  # elastic: unloading retraces loading

    def kink_log_loads(self, s):
        return jnp.zeros((0,), jnp.result_type(s.D))

    def point_solver(self, s, unloading: bool = False):
        del unloading  # elastic: unloading retraces loading
        solve = self._separation_solver(summit_statistics(s, self.spectrum))
        return lambda F_star: separated_point(solve(F_star))

    def spot_solver(self, s):
        """The separation solve, and the summits in contact in the families of `INTERFERENCE_EDGES`,
        in `t = ln ŵ` (ŵ the interference in units of σ_s)."""
        statistics = summit_statistics(s, self.spectrum)
        solve = self._separation_solver(statistics)
        log_eta, log_R, log_sigma = statistics

        def one(F_star) -> SpotState:
            state = solve(F_star)
            h = state.separation
            edges = jnp.asarray(INTERFERENCE_EDGES, h.dtype)
            low, high = edges[:-1], edges[1:]
            count = GaussianSummitCount(log_eta, h)
            log_law = jnp.full_like(low, 0.5 * log_R)
            load = PowerLaw(log_law + math.log(4.0 / 3.0) + 1.5 * log_sigma, jnp.full_like(low, 1.5))
            stiffness = PowerLaw(log_law + math.log(2.0) + 0.5 * log_sigma, jnp.full_like(low, 0.5))
            spots = SpotFamilies.without_interaction(count, load, stiffness, jnp.log(low), jnp.log(high))
            return SpotState(state.status, spots, state.stiffness, jnp.array(False))

        return one

    def _separation_solver(self, statistics):
        """`F* ↦ Separated`: the separation h (in σ_s) that carries the load, and the totals there,
        for the summits' `statistics` (`summit_statistics`)."""
        log_eta, log_R, log_sigma = statistics
        log_load_scale = math.log(4.0 / 3.0) + log_eta + 0.5 * log_R + 1.5 * log_sigma
        log_stiffness_scale = math.log(2.0) + log_eta + 0.5 * log_R + 0.5 * log_sigma
        log_area_scale = math.log(math.pi) + log_eta + log_R + log_sigma
        dtype = jnp.result_type(log_eta)
        highest = log_load_scale + log_tail_moment(1.5, jnp.asarray(H_LOWEST, dtype))
        lowest = log_load_scale + log_tail_moment(1.5, jnp.asarray(H_HIGHEST, dtype))
        valid_scene = jnp.isfinite(highest) & jnp.isfinite(lowest)

        def one(F_star) -> Separated:
            valid = jnp.isfinite(F_star) & (F_star > 0)
            log_load = jnp.log(jnp.where(valid, F_star, 1.0))
            in_range = (log_load > lowest) & (log_load <= highest) & (F_star <= LINEAR_ELASTIC_LIMIT)
            log_load = jnp.where(valid & in_range, log_load, 0.5 * (lowest + highest))
            y, converged = self.root_finder.find(
                _residual,
                jnp.zeros_like(log_load) - 2.0,
                (log_load_scale, log_load),
                -H_HIGHEST,
                -H_LOWEST,
                slope=_residual_slope,
            )
            h = -y
            load = jnp.exp(log_load_scale + log_tail_moment(1.5, h))
            stiffness = jnp.exp(log_stiffness_scale + log_tail_moment(0.5, h))
            area = jnp.exp(log_area_scale + log_tail_moment(1.0, h))
            # Summits whose contact areas add up to (nearly) the nominal area: a closed interface.
            in_range = in_range & (area < CLOSED_INTERFACE)
            status = jnp.select(
                [~valid_scene, ~valid, ~in_range, ~converged],
                [Status.INVALID_PARAMETERS, Status.INVALID_LOAD, Status.LOAD_OUT_OF_RANGE, Status.NOT_CONVERGED],
                Status.OK,
            ).astype(jnp.int32)
            return Separated(h, load, stiffness, area, status)

        return one
