"""Greenwood–Williamson with *measured* asperity statistics (docs/model.md §9): a radius R, an areal
density η and a tabulated summit-height PDF φ(z), as identified from profilometer scans (e.g. the
Brake–Reuss beam interface, Porter & Brake, MSSP 192, 110210, 2023).

With a rigid flat at height d over the heights' origin, every summit above d is a contact of
interference `z − d`, independent of the others (GW 1966), carrying load on an area by its summit
law: Hertz (`HertzSummits()`, GW's own) or the elastic–plastic fits of Kogut & Etsion
(`KogutEtsionSummits()`, with the scene's hardness). For Hertz summits

    F/A_a = (4/3) E η √R J_{3/2}(d),   K/A_a = 2 E η √R J_{1/2}(d),   A_r/A_a = π η R J_1(d),
    J_n(d) = ∫_d^{z_max} (z − d)^n φ(z) dz,

and in general each band of the law adds its own (`_summit_table`). `K = -dF/dd` exactly. φ is
linear between its table's points, so each `J_n` is a sum of closed forms, one per interval:
exact, and differentiable with respect to d, R, η, H and every value of the table. Load control
solves `F(d) = F` for d below the highest summit, down to where the summits' contact areas add up to
the nominal area (`CLOSED_INTERFACE`: flagged beyond). Below the lowest summit every summit is in
contact and stays independent of the others, GW's assumption, which is less apt the larger the real
area (`Solution.real_area`) grows.
"""

from __future__ import annotations

import math
from typing import ClassVar

import jax.numpy as jnp
from jaxtyping import Array, Float

from ..numerics import InputError, NewtonBisection, PowerLaw, check_instance
from ..physics._summit_law import SUMMIT_REGIMES, AbstractSummitLaw, HertzSummits
from ..quantities import Status
from ._base import CLOSED_INTERFACE, LINEAR_ELASTIC_LIMIT, AbstractPathModel, JointResponse, PointResult
from ._spots import SpotFamilies, SpotState, SummitCount
from ._summit_path import follow
from ._summit_table import SummitTable, log_load, residual, residual_slope, summit_table

LOG_PI = math.log(math.pi)
# The highest separation solved for, as a fraction of the heights' span below the top: loads lower
# than the one it carries are out of range (near the top the load falls to zero as (z_max − d)^(7/2)).
TOP_MARGIN = 1e-6
# The smallest interference of the summits resolved one by one, as a fraction of the largest: a
# summit's load goes as w^(3/2) and the count of the lowest ones as w, so those below carry ~1e-15.
SPOT_FLOOR = 1e-6


class MeasuredAsperities(AbstractPathModel):
    """Greenwood–Williamson with measured statistics (module docstring); the surface's D, G and l_min
    are not used. Four regimes, e, ep1, ep2 and p, the bands of the summit law (all "e" for Hertz
    summits; a band's loading stiffness includes the summits crossing into it where the Kogut–Etsion
    load jumps); `Solution.a_l` is NaN.

    **Arguments:**

    - `radius`: the summits' radius R, m (> 0).
    - `density`: summits per unit nominal area η, 1/m² (> 0).
    - `heights`: the summit heights z at which the PDF is tabulated, m, increasing (≥ 2 points); the
      highest summits touch first.
    - `pdf`: φ(z) there, 1/m, ≥ 0; it is normalised to ∫φ dz = 1 (trapezoidal, φ being linear between points).
    - `summits`: how one summit carries load, `HertzSummits()` (default) or `KogutEtsionSummits()`
      (elastic–plastic, with the scene's hardness H and ν).
    - `root_finder`: the solve for each load's separation (`NewtonBisection()`).

    The fields are arrays: `jax.grad` reaches them through `eqx.tree_at` as it reaches the scene's
    parameters. `MeasuredAsperities.from_gaps` takes the PDF of the summits' initial gaps instead.
    """

    name: ClassVar[str] = "measured-asperities"
    regimes: ClassVar[tuple[str, ...]] = SUMMIT_REGIMES
    radius: Float[Array, ""]
    density: Float[Array, ""]
    heights: Float[Array, " table"]
    pdf: Float[Array, " table"]
    summits: AbstractSummitLaw = HertzSummits()
    root_finder: NewtonBisection = NewtonBisection()

    def __init__(
        self,
        radius,
        density,
        heights,
        pdf,
        summits: AbstractSummitLaw = HertzSummits(),
        root_finder: NewtonBisection = NewtonBisection(),
    ):
        self.radius, self.density = jnp.asarray(radius), jnp.asarray(density)
        self.heights, self.pdf = jnp.asarray(heights), jnp.asarray(pdf)
        self.summits, self.root_finder = summits, root_finder

    @classmethod
    def from_gaps(cls, radius, density, gaps, pdf, **choices) -> MeasuredAsperities:
        """The same model from the PDF of each summit's initial gap g to the flat (g ≥ 0 increasing,
        m; the summits at g = 0 touch first), as tmdsimpy's Brake–Reuss example reads its file
        (`normzinterp · z_max`): the heights are `max(g) − g`, in increasing order."""
        gaps, pdf = jnp.asarray(gaps), jnp.asarray(pdf)
        return cls(radius, density, gaps[-1] - gaps[::-1], pdf[::-1], **choices)

    def __check_init__(self):
        check_instance("root_finder", self.root_finder, NewtonBisection)
        check_instance("summits", self.summits, AbstractSummitLaw)
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
        return self.summits.elastic  # Hertz summits retrace their loading curve

    def kink_log_loads(self, s):
        return jnp.zeros((0,), jnp.result_type(s.D))

    def point_solver(self, s, unloading: bool = False):
        """`F* ↦ PointResult`; with `unloading`, each band's stiffness is its summits' initial unloading
        stiffness at the state loading reaches (the same as loading's for Hertz summits)."""
        solve = self._separation_solver(self._table(s))

        def one(F_star) -> PointResult:
            d, totals, status = solve(F_star)
            stiffness = totals.unloading if unloading else totals.stiffness
            response = JointResponse(totals.load, stiffness, jnp.sum(totals.area), jnp.array(False))
            return PointResult(jnp.full_like(d, jnp.nan), response, status)

        return one

    def path_solver(self, s):
        """`F*` along a load path ↦ its `PathPoints`: each summit remembers its deepest interference and
        unloads and reloads below it along Hertz's law about its residual interference (`_summit_path`);
        Hertz summits retrace their loading curve."""
        table = self._table(s)
        solve = self._separation_solver(table)
        return lambda F_star: follow(
            table, solve, self.root_finder, self.summits.bands_used, self.summits.elastic, F_star
        )

    def spot_solver(self, s):
        """The separation solve, and the summits in contact one interval of the table and one band of
        the summit law at a time, in `t = ln w*` from `w* = SPOT_FLOOR · (z_top − d)` (the summits below
        carry 1e-15 of a family's load)."""
        table = self._table(s)
        solve = self._separation_solver(table)
        bands = table.bands.in_units(-jnp.log(table.span))  # ω in √A_a

        def one(F_star) -> SpotState:
            d, totals, status = solve(F_star)
            z, d = table.heights * table.span, d * table.span  # in √A_a from the table's lowest point
            phi = table.pdf / table.span
            top = z[-1] - d
            used = self.summits.bands_used  # the families of bands that hold no summit are left out
            lower, upper = bands.edges[:used, None], bands.edges[1 : used + 1, None]
            clip = lambda w: jnp.minimum(jnp.clip(jnp.maximum(w, SPOT_FLOOR * top), lower, upper), top)  # noqa: E731
            low, high = clip(z[:-1] - d), clip(z[1:] - d)  # (bands, intervals)
            slope = (phi[1:] - phi[:-1]) / (z[1:] - z[:-1])
            tile = lambda x: jnp.broadcast_to(x, low.shape).reshape(-1)  # noqa: E731
            count = SummitCount(table.log_eta, d, tile(phi[:-1]), tile(slope), tile(z[:-1]))
            per_band = lambda law: PowerLaw(tile(law.log_coeff[:used, None]), tile(law.exponent[:used, None]))  # noqa: E731
            load, stiffness = per_band(bands.load), per_band(bands.unloading_stiffness())
            spots = SpotFamilies.without_interaction(
                count, load, stiffness, jnp.log(low).reshape(-1), jnp.log(high).reshape(-1)
            )
            return SpotState(status, spots, jnp.sum(totals.unloading), jnp.array(False))

        return one

    def _table(self, s) -> SummitTable:
        log_R = jnp.log(self.radius) - s.log_length
        bands = self.summits.bands(log_R, s.log_hardness, s.nu)
        return summit_table(self.heights, self.pdf, self.density, log_R, bands, s.log_length)

    def _separation_solver(self, table: SummitTable):
        """`F* ↦ (d, BandTotals, status)`: the flat's separation d (in u) that carries the load, and
        the totals there."""
        # Below the lowest summit by 2/(π η R) every summit's area is at least 0.93 π R (z − d) (the
        # smallest of the laws' areas per interference), so the interface has closed above it.
        closed = 2.0 * jnp.exp(-LOG_PI - table.log_eta - table.log_R) / table.span
        lowest, top = -closed, jnp.full_like(table.span, 1.0 - TOP_MARGIN)
        highest_load, lowest_load = log_load(table, lowest), log_load(table, top)

        def one(F_star):
            valid = jnp.isfinite(F_star) & (F_star > 0)
            target = jnp.log(jnp.where(valid, F_star, 1.0))
            in_range = (target > lowest_load) & (target <= highest_load) & (F_star <= LINEAR_ELASTIC_LIMIT)
            target = jnp.where(valid & in_range, target, 0.5 * (lowest_load + highest_load))
            guess = -0.5 * top  # mid-table: most loads put the flat among the summits
            y, converged = self.root_finder.find(residual, guess, (table, target), -top, -lowest, slope=residual_slope)
            totals = table.totals(-y)
            in_range = in_range & (jnp.sum(totals.area) < CLOSED_INTERFACE)
            status = jnp.select(
                [~valid, ~in_range, ~converged],
                [Status.INVALID_LOAD, Status.LOAD_OUT_OF_RANGE, Status.NOT_CONVERGED],
                Status.OK,
            ).astype(jnp.int32)
            return -y, totals, status

        return one


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
