"""Persson's theory of elastic contact (docs/model.md §9): the stiffness from the interfacial separation.

Persson (PRL 99, 125502, 2007) and Yang & Persson (J. Phys.: Condens. Matter 20, 215214, 2008):
with `C_P(q) = C2D(q)/(2π)²` on `[q0, q1] = [2π/L, 2π/l_min]` and `p = F/A_a`,

    K/A_a = -dp/du = p / ( √π ∫_{q0}^{q1} q² C_P(q) w(q) S(w(q) p/E) dq ),
    w(q) = (π ∫_{q0}^{q} q'³ C_P(q') dq')^(-1/2),   S(x) = [γ_P + 3(1 - γ_P) erf(x)²] e^(-x²),

and the real contact area `A_r/A_a = erf(w(q1) p/E)`. For the power-law PSD the inner integral
is a closed form, `Q(q) = C_P0 (q^(2D-2) - q0^(2D-2))/(2D-2)`, and it can be inverted, so the
outer integral is taken in `x = w(q) p/E` (`dQ = q³ C_P dq`, `w = (πQ)^(-1/2)`):

    K* = K/(E √A_a) = (√π/2) / ∫_{x1}^{∞} S(x) / (x² q*(x/F*)) dx,    x1 = w(q1) F*,

a smooth integrand in `ln x` over `[ln x1, ln 6]` (S(6) ≈ e^-36), done by Gauss–Legendre. The
stiffness is explicit in the load: no state is solved for. At small loads K ∝ p (the known law).
A measured spectrum (`MeasuredSpectrum`, a table of C2D) gives `Q(q)` and its inverse `q*(x/F*)`
exactly for the table's piecewise power law.
"""

from __future__ import annotations

import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jax.scipy.special import erf

from ..numerics import check_range, integrate_log_area
from ..numerics._validate import check_instance
from ..physics import MeasuredSpectrum
from ..physics._spectrum import log_areal_prefactor, log_band
from ..quantities import Status
from ._base import (
    CLOSED_INTERFACE,
    LINEAR_ELASTIC_LIMIT,
    AbstractContactModel,
    JointResponse,
    PointResult,
    without_single_spots,
)

LOG_X_END = math.log(6.0)


class Persson(AbstractContactModel):
    """Persson's theory (docs/model.md §9), elastic, with Yang & Persson's correction factor.

    **Arguments:** `gamma`, the correction factor γ_P of S(x) (0.45, the papers' value); `nodes`,
    Gauss–Legendre nodes of the integral in `ln x` (static); `spectrum`, None (the scene's
    self-affine C2D from D, G and l_min) or a `MeasuredSpectrum` (its table, in place of the
    scene's D, G and l_min, which are then not used). One regime, "e"; `Solution.a_l` is NaN (no
    largest spot).
    """

    name: ClassVar[str] = "persson"
    single_spots: ClassVar[bool] = False
    regimes: ClassVar[tuple[str, ...]] = ("e",)
    gamma: float = eqx.field(static=True, default=0.45)
    nodes: int = eqx.field(static=True, default=96)
    spectrum: MeasuredSpectrum | None = None

    def __check_init__(self):
        check_range("gamma", self.gamma, 0.0, 1.0, low_open=False, high_open=False)
        check_range("nodes", self.nodes, 8, 4096, low_open=False, high_open=False)
        if self.spectrum is not None:
            check_instance("spectrum", self.spectrum, MeasuredSpectrum)

    def unloads_as_it_loads(self):
        return True  # elastic: unloading retraces loading

    def spot_solver(self, s):
        raise without_single_spots(self)

    def kink_log_loads(self, s):
        return jnp.zeros((0,), jnp.result_type(s.D))

    def point_solver(self, s, unloading: bool = False):
        del unloading  # elastic: unloading retraces loading
        if self.spectrum is None:
            log_w1, log_q_of_w = _power_law_band(s)
        else:
            log_w1, log_q_of_w = _tabulated_band(self.spectrum, s.log_length)

        def one_point(F_star) -> PointResult:
            valid = jnp.isfinite(F_star) & (F_star > 0)
            log_load = jnp.log(jnp.where(valid, F_star, 1.0))
            log_x1 = log_w1 + log_load
            # Past x1 = 6 the whole interface is in contact to round-off: no separation is left;
            # past F* = 1, linear elasticity (`LINEAR_ELASTIC_LIMIT`).
            in_range = (log_x1 < LOG_X_END) & (F_star <= LINEAR_ELASTIC_LIMIT)
            log_x1 = jnp.where(in_range, log_x1, LOG_X_END - 1.0)

            def integrand(log_x):
                x = jnp.exp(log_x)
                factor = (self.gamma + 3.0 * (1.0 - self.gamma) * erf(x) ** 2) * jnp.exp(-x * x)
                return factor * jnp.exp(-log_x - log_q_of_w(log_x - log_load))

            integral = integrate_log_area(integrand, log_x1, jnp.full_like(log_x1, LOG_X_END), self.nodes)
            stiffness = 0.5 * math.sqrt(math.pi) / integral
            area = erf(jnp.exp(log_x1))
            in_range = in_range & (area < CLOSED_INTERFACE)
            status = jnp.select([~valid, ~in_range], [Status.INVALID_LOAD, Status.LOAD_OUT_OF_RANGE], Status.OK).astype(
                jnp.int32
            )
            response = JointResponse(jnp.exp(log_load)[None], stiffness[None], area, jnp.array(False))
            return PointResult(jnp.full_like(log_load, jnp.nan), response, status)

        return one_point


def _power_law_band(s):
    """`ln w(q1*)` and `ln w ↦ ln q*(w)` of the self-affine C2D on `[2π, 2π/l_min*]`, in closed form."""
    log_q0, log_q1 = log_band(s.log_a_min)
    exponent = 2.0 * s.D - 2.0  # of q in Q(q)
    log_c = log_areal_prefactor(s.D, s.log_G) - 2.0 * math.log(2.0 * math.pi) - jnp.log(exponent)
    log_Q1 = log_c + jnp.log(jnp.expm1(exponent * (log_q1 - log_q0))) + exponent * log_q0

    def log_q_of_w(log_w):
        # q^(2D-2) = q0^(2D-2) + 1/(π c w²)
        return jnp.logaddexp(exponent * log_q0, -math.log(math.pi) - log_c - 2.0 * log_w) / exponent

    return -0.5 * (math.log(math.pi) + log_Q1), log_q_of_w


def _tabulated_band(spectrum: MeasuredSpectrum, log_length):
    """The same from a measured spectrum: `q*(w)` by inverting its cumulative `Q*` exactly
    (`MeasuredSpectrum.cumulative`; `w = (πQ)^(-1/2)`)."""
    log_Q1, log_q_of_log_Q = spectrum.cumulative(log_length)

    def log_q_of_w(log_w):
        return log_q_of_log_Q(-math.log(math.pi) - 2.0 * log_w)

    return -0.5 * (math.log(math.pi) + log_Q1), log_q_of_w
