"""Greenwood–Williamson with *measured* asperity statistics (docs/model.md §9): a radius R, an areal
density η and a tabulated summit-height PDF φ(z), as identified from profilometer scans (e.g. the
Brake–Reuss beam interface, Porter & Brake, MSSP 192, 110210, 2023).

With a rigid flat at height d over the heights' origin, every summit above d is a Hertz contact of
interference `z − d`, independent of the others (GW 1966):

    F/A_a = (4/3) E η √R J_{3/2}(d),   K/A_a = 2 E η √R J_{1/2}(d),   A_r/A_a = π η R J_1(d),
    J_n(d) = ∫_d^{z_max} (z − d)^n φ(z) dz,

`K = -dF/dd` exactly (`dJ_{3/2}/dd = −(3/2) J_{1/2}`). φ is linear between its table's points, so each
`J_n` is a sum of closed forms, one per interval: exact, and differentiable with respect to d, R, η and
every value of the table. Load control solves `F(d) = F` for d between the lowest tabulated height
(every summit in contact: beyond it the independent summits of GW no longer apply) and the highest.
"""

from __future__ import annotations

import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from ..numerics import InputError, NewtonBisection, PowerLaw, check_instance
from ..quantities import Status
from ._base import (
    CLOSED_INTERFACE,
    LINEAR_ELASTIC_LIMIT,
    AbstractContactModel,
    separated_point,
)
from ._spots import Separated, SpotFamilies, SpotState, SummitCount

# The highest separation solved for, as a fraction of the heights' span below the top: loads lower
# than the one it carries are out of range (near the top the load falls to zero as (z_max − d)^(7/2)).
TOP_MARGIN = 1e-6
# The smallest interference of the summits resolved one by one, as a fraction of the largest: a
# summit's load goes as w^(3/2) and the count of the lowest ones as w, so those below carry ~1e-15.
SPOT_FLOOR = 1e-6


def _power(t, p):
    """`t^p` for `t ≥ 0`, 0 at 0 with a finite derivative (a kink of the integrand, not a NaN)."""
    positive = t > 0
    return jnp.where(positive, jnp.where(positive, t, 1.0) ** p, 0.0)


def tail_integral(order: float, d, heights, pdf):
    """`J_n(d) = ∫_d^{z_max} (z − d)^n φ(z) dz` for φ linear between `(heights, pdf)`, summed over the
    intervals in closed form: on each, φ = φ(t0) + s (t − t0) in `t = z − d ∈ [t0, t1]`, and
    `∫ t^n (φ0 + s (t − t0)) dt = φ0 [t^(n+1)/(n+1)] + s ([t^(n+2)/(n+2)] − t0 [t^(n+1)/(n+1)])`."""
    t_low, t_high = jnp.maximum(heights[:-1] - d, 0.0), jnp.maximum(heights[1:] - d, 0.0)
    slope = (pdf[1:] - pdf[:-1]) / (heights[1:] - heights[:-1])
    phi_low = pdf[:-1] + slope * (d + t_low - heights[:-1])
    first = (_power(t_high, order + 1.0) - _power(t_low, order + 1.0)) / (order + 1.0)
    second = (_power(t_high, order + 2.0) - _power(t_low, order + 2.0)) / (order + 2.0)
    return jnp.sum(phi_low * first + slope * (second - t_low * first))


def _log_load(d, log_load_scale, heights, pdf):
    return log_load_scale + jnp.log(tail_integral(1.5, d, heights, pdf))


# The root finder's residual and slope take every traced value as an argument (it differentiates the
# root implicitly, and a closure would hide them from it); increasing in y = −d.
def _residual(y, args):
    log_load_scale, heights, pdf, target = args
    return _log_load(-y, log_load_scale, heights, pdf) - target, None


def _residual_slope(y, args):
    _, heights, pdf, _ = args
    return 1.5 * tail_integral(0.5, -y, heights, pdf) / tail_integral(1.5, -y, heights, pdf)


class MeasuredAsperities(AbstractContactModel):
    """Greenwood–Williamson with measured statistics (module docstring): every summit elastic (Hertz),
    as GW; the surface's D, G and l_min are not used. One regime, "e"; `Solution.a_l` is NaN.

    **Arguments:**

    - `radius`: the summits' radius R, m (> 0).
    - `density`: summits per unit nominal area η, 1/m² (> 0).
    - `heights`: the summit heights z at which the PDF is tabulated, m, increasing (≥ 2 points).
    - `pdf`: φ(z) there, 1/m, ≥ 0; it is normalised to ∫φ dz = 1 (trapezoidal, φ being linear between points).
    - `root_finder`: the solve for each load's separation (`NewtonBisection()`).

    The fields are arrays: `jax.grad` reaches them through `eqx.tree_at` as it reaches the scene's
    parameters.
    """

    name: ClassVar[str] = "measured-asperities"
    regimes: ClassVar[tuple[str, ...]] = ("e",)
    radius: Float[Array, ""]
    density: Float[Array, ""]
    heights: Float[Array, " table"]
    pdf: Float[Array, " table"]
    root_finder: NewtonBisection = NewtonBisection()

    def __init__(self, radius, density, heights, pdf, root_finder: NewtonBisection = NewtonBisection()):
        self.radius, self.density = jnp.asarray(radius), jnp.asarray(density)
        self.heights, self.pdf = jnp.asarray(heights), jnp.asarray(pdf)
        self.root_finder = root_finder

    def __check_init__(self):
        check_instance("root_finder", self.root_finder, NewtonBisection)
        if self.heights.ndim != 1 or self.heights.shape != self.pdf.shape or self.heights.size < 2:
            raise InputError(
                f"heights and pdf have shapes {self.heights.shape} and {self.pdf.shape}: give two 1-D tables of one "
                "length (2 points at least)"
            )
        for name in ("radius", "density"):
            value = getattr(self, name)
            if not isinstance(value, jnp.ndarray) or value.ndim != 0:
                raise InputError(f"{name} has shape {jnp.shape(value)}: give one number")
        _check_concrete(self)

    def unloads_as_it_loads(self):
        return True  # elastic (Hertz) summits: unloading retraces loading

    def kink_log_loads(self, s):
        return jnp.zeros((0,), jnp.result_type(s.D))

    def point_solver(self, s):
        solve = self._separation_solver(self._table(s))
        return lambda F_star: separated_point(solve(F_star))

    def spot_solver(self, s):
        """The separation solve, and the summits in contact one interval of the table at a time, in
        `t = ln w*` from `w* = SPOT_FLOOR · (z_top − d)` (the summits below carry 1e-15 of a family's load)."""
        table = self._table(s)
        solve = self._separation_solver(table)

        def one(F_star) -> SpotState:
            state = solve(F_star)
            z = table.heights * table.span  # in √A_a from the table's lowest point
            d = state.separation * table.span
            phi = table.pdf / table.span
            top = z[-1] - d
            low = jnp.maximum(z[:-1] - d, SPOT_FLOOR * top)
            high = jnp.maximum(z[1:] - d, SPOT_FLOOR * top)
            slope = (phi[1:] - phi[:-1]) / (z[1:] - z[:-1])
            count = SummitCount(table.log_eta, d, phi[:-1], slope, z[:-1])
            log_root_R = jnp.full_like(low, 0.5 * table.log_R)
            load = PowerLaw(log_root_R + math.log(4.0 / 3.0), jnp.full_like(low, 1.5))
            stiffness = PowerLaw(log_root_R + math.log(2.0), jnp.full_like(low, 0.5))
            spots = SpotFamilies.without_interaction(count, load, stiffness, jnp.log(low), jnp.log(high))
            return SpotState(state.status, spots, state.stiffness, jnp.array(False))

        return one

    def _table(self, s) -> _Table:
        """The statistics in the scene's units (lengths in √A_a), heights from the table's lowest
        point in units of its span (u in [0, 1]: the root finder's tolerance is absolute in u), and
        the PDF normalised over u."""
        length = jnp.exp(s.log_length)
        span = (self.heights[-1] - self.heights[0]) / length
        heights = (self.heights - self.heights[0]) / (self.heights[-1] - self.heights[0])
        pdf = self.pdf / jnp.sum(0.5 * (self.pdf[1:] + self.pdf[:-1]) * jnp.diff(heights))
        log_eta, log_R = jnp.log(self.density) + 2.0 * s.log_length, jnp.log(self.radius) - s.log_length
        return _Table(span, heights, pdf, log_eta, log_R)

    def _separation_solver(self, table: _Table):
        """`F* ↦ Separated`: the flat's separation d (in u) that carries the load, and the totals
        there, for the statistics of `_table`. J_n(d) = span^n Ĵ_n(u), Ĵ of the table's density in u."""
        heights, pdf, log_span = table.heights, table.pdf, jnp.log(table.span)
        log_load_scale = math.log(4.0 / 3.0) + table.log_eta + 0.5 * table.log_R + 1.5 * log_span
        log_stiffness_scale = math.log(2.0) + table.log_eta + 0.5 * table.log_R + 0.5 * log_span
        log_area_scale = math.log(math.pi) + table.log_eta + table.log_R + log_span
        lowest, top = jnp.zeros_like(table.span), jnp.full_like(table.span, 1.0 - TOP_MARGIN)
        highest_load = _log_load(lowest, log_load_scale, heights, pdf)
        lowest_load = _log_load(top, log_load_scale, heights, pdf)

        def one(F_star) -> Separated:
            valid = jnp.isfinite(F_star) & (F_star > 0)
            target = jnp.log(jnp.where(valid, F_star, 1.0))
            in_range = (target > lowest_load) & (target <= highest_load) & (F_star <= LINEAR_ELASTIC_LIMIT)
            target = jnp.where(valid & in_range, target, 0.5 * (lowest_load + highest_load))
            guess = -0.5 * (lowest + top)
            args = (log_load_scale, heights, pdf, target)
            y, converged = self.root_finder.find(_residual, guess, args, -top, -lowest, slope=_residual_slope)
            d = -y
            load = jnp.exp(_log_load(d, log_load_scale, heights, pdf))
            stiffness = jnp.exp(log_stiffness_scale) * tail_integral(0.5, d, heights, pdf)
            area = jnp.exp(log_area_scale) * tail_integral(1.0, d, heights, pdf)
            in_range = in_range & (area < CLOSED_INTERFACE)
            status = jnp.select(
                [~valid, ~in_range, ~converged],
                [Status.INVALID_LOAD, Status.LOAD_OUT_OF_RANGE, Status.NOT_CONVERGED],
                Status.OK,
            ).astype(jnp.int32)
            return Separated(d, load, stiffness, area, status)

        return one


class _Table(eqx.Module):
    span: Float[Array, ""]
    heights: Float[Array, " table"]
    pdf: Float[Array, " table"]
    log_eta: Float[Array, ""]
    log_R: Float[Array, ""]


def _check_concrete(model: MeasuredAsperities) -> None:
    """The tables' and the statistics' values where they are concrete (not traced)."""
    import jax
    import numpy as np

    if any(isinstance(x, jax.core.Tracer) for x in (model.radius, model.density, model.heights, model.pdf)):
        return
    for name in ("radius", "density"):
        value = float(getattr(model, name))
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{name} = {value!r} must be in (0, inf)")
    heights, pdf = np.asarray(model.heights), np.asarray(model.pdf)
    if not (np.all(np.isfinite(heights)) and np.all(np.diff(heights) > 0)):
        raise InputError("heights must be finite and increasing (the summit heights of the PDF's table, m)")
    if not (np.all(np.isfinite(pdf)) and np.all(pdf >= 0) and np.any(pdf > 0)):
        raise InputError("pdf must be finite, >= 0 and not all 0 (the summit-height PDF, 1/m)")
