"""How measured summits unload and reload along a load path (`MeasuredAsperities.path_solver`,
docs/in-service.md).

Each summit remembers the largest interference loading gave it, `ω_m = z − d_m` with `d_m` the
flat's lowest position so far. Raised by `Δ = d − d_m ≥ 0`, it unloads, and reloads up to `ω_m`,
along Hertz's law about a larger radius and a residual interference `ω_res = ω_m − g`: Etsion,
Kligerman & Kadin's finding that an unloaded elastic–plastic sphere is a sphere of larger radius
(IJSS 42, 3716, 2005), in the form that keeps the load `P_m` and the contact radius `a_m` at the
top (as Jackson, Green & Marghitu take it for impacts, Nonlinear Dyn. 60, 217, 2010):

    P = P_m (1 − Δ/g)^(3/2),   A = A_m (1 − Δ/g),   g = 3 P_m / (4 E a_m),

so that the initial unloading stiffness is Sneddon's `1.5 P_m/g = 2E a_m` (the `unloading` of
`SummitTable.totals`). For Hertz summits `g = ω_m`: they unload along their loading curve. Beyond
`ω_m` a summit loads along its summit law again (Kadin, Kligerman & Etsion, IJSS 43, 7259, 2006).
Just past `ω_c` the Kogut–Etsion fits' jump in load (+3 %) and area (−7 %) makes `g` up to 6.8 %
larger than `ω_m` (`ω_res < 0`, for `ω_m < 1.6 ω_c`).

The totals have no closed form (`g` is not a power law of `z − d`). On each piece between the
table's points and the bands' edges, `ω_m` runs over the summits still in contact (`g(ω_m) > Δ`, `g` increasing in
each band) by Gauss–Legendre in `t`, `ω_m = lo + (hi − lo) t²`: the tangent's factor
`(1 − Δ/g)^(1/2)` vanishes as `√(ω_m − ω*)` where the last summits let go, and is smooth in t.
"""

from __future__ import annotations

import functools
import math

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from ..numerics import PowerLaw
from ..numerics._quadrature import gauss_legendre
from ..quantities import Branch, Status, branches
from ._base import PathPoints
from ._summit_table import SummitTable

# Gauss–Legendre nodes per band and interval of the table: the approach along a path is scipy's
# quadrature to 4e-12 on a 201-point Gaussian table (tests/test_summit_path.py).
NODES = 8


class Unloaded(eqx.Module):
    """The summits' totals raised by Δ from their deepest state (dimensionless): the load F*, the
    tangent `−dF*/dd*` (`E √A_a`) and the real area A_r/A_a."""

    load: Float[Array, ""]
    stiffness: Float[Array, ""]
    area: Float[Array, ""]


def recovery(table: SummitTable) -> PowerLaw:
    """`g(ω_m) = 1.5 P_m / (2 a_m)` per band, the interference a summit recovers elastically, with
    `ω_m` and `g` in units of the table's span."""
    bands = table.bands
    return (bands.load / bands.unloading_stiffness()).scaled(math.log(1.5) - jnp.log(table.span))


def _safe_log(x):
    positive = x > 0
    return jnp.where(positive, jnp.log(jnp.where(positive, x, 1.0)), -jnp.inf)


def unloaded(table: SummitTable, d_m, delta, used: int) -> Unloaded:
    """The totals with the flat at `d_m + delta` after it went down to `d_m` (both in the table's
    units, `delta ≥ 0`), over the first `used` bands of the summit law (module docstring)."""
    g = recovery(table)[:used]
    edges, z = table.bands.edges, table.heights
    top = z[-1] - d_m
    # One piece per interval between the table's points and the bands' inner edges, in ω_m: each lies
    # in one interval of the PDF and one band of the law.
    ends = jnp.sort(jnp.clip(jnp.concatenate([z - d_m, edges[1:used]]), 0.0, top))
    middle = 0.5 * (ends[1:] + ends[:-1])
    band = jnp.clip(jnp.searchsorted(edges, middle, side="right") - 1, 0, used - 1)
    interval = jnp.clip(jnp.searchsorted(z - d_m, middle, side="right") - 1, 0, z.size - 2)
    law = lambda law: PowerLaw(law.log_coeff[band, None], law.exponent[band, None])  # noqa: E731
    # The summits that still touch, g(ω_m) > Δ: ω_m above (Δ/k)^(1/e) in their band (0 at Δ = 0).
    recovering = law(g)
    still = jnp.exp((_safe_log(delta) - recovering.log_coeff) / recovering.exponent)
    lower = jnp.maximum(ends[:-1, None], still)
    width = jnp.maximum(ends[1:, None] - lower, 0.0)
    x, w = gauss_legendre(NODES)
    dtype = jnp.result_type(table.span)
    t = 0.5 * (jnp.asarray(x, dtype) + 1.0)
    omega = lower + width * t**2
    weight = 0.5 * jnp.asarray(w, dtype) * 2.0 * width * t  # dω = 2 (hi − lo) t dt
    slope = (table.pdf[1:] - table.pdf[:-1]) / (z[1:] - z[:-1])
    phi = (table.pdf[:-1] + slope * (d_m - z[:-1]))[interval, None] + slope[interval, None] * omega
    log_omega = _safe_log(omega)
    P_m, A_m = (law(x)(log_omega) for x in (table.bands.load, table.bands.area))
    g_m = jnp.where(omega > 0, recovering(log_omega), 1.0)
    left = jnp.clip(1.0 - delta / g_m, 0.0, 1.0)
    density = jnp.where(omega > 0, weight * phi, 0.0) * jnp.exp(table.log_eta)
    total = lambda x: jnp.sum(density * x)  # noqa: E731
    return Unloaded(
        load=total(P_m * left**1.5),
        stiffness=total(1.5 * P_m * jnp.sqrt(left) / g_m) / table.span,
        area=total(A_m * left),
    )


def full_recovery(table: SummitTable, d_m, used: int):
    """How far the flat rises from `d_m` until the last summit lets go: the largest `g` of the
    summits in contact, at the top of each band they reach (table units)."""
    g = recovery(table)[:used]
    edges = table.bands.edges
    top = table.heights[-1] - d_m
    reached = edges[:used] < top
    highest = jnp.where(reached, jnp.minimum(edges[1 : used + 1], top), 1.0)
    return jnp.max(jnp.where(reached, g(jnp.log(highest)), 0.0))


def follow(table: SummitTable, solve, root_finder, used: int, elastic: bool, F_star) -> PathPoints:
    """The summits along a load path `F_star` (1-D, in the order applied): `solve` is the loading
    solve of one load, `F* ↦ (d, BandTotals, status)`, and `root_finder` solves each point below the
    path's running maximum for its Δ (module docstring). `elastic` summits (Hertz) retrace their
    loading curve: every point is then the loading solve at its load."""
    if elastic:
        d, totals, status = jax.vmap(solve)(F_star)
        stiffness = jnp.sum(totals.stiffness, axis=-1)
        return _points(table, d, stiffness, stiffness, jnp.sum(totals.area, axis=-1), status, jnp.zeros_like(d[0]))
    peak = jax.lax.cummax(F_star)
    d_m, totals, status = jax.vmap(solve)(peak)
    below = F_star < peak
    find = functools.partial(_residual, used=used)
    find_slope = functools.partial(_residual_slope, used=used)

    def unload(F, d):
        ceiling = full_recovery(table, d, used)
        target = jnp.log(jnp.where(F > 0, F, 1.0))
        args = (table, d, target)
        y, converged = root_finder.find(find, -0.5 * ceiling, args, -ceiling, jnp.zeros_like(d), slope=find_slope)
        return -y, converged

    delta, converged = jax.vmap(unload)(F_star, d_m)
    delta = jnp.where(below, delta, 0.0)
    state = jax.vmap(lambda d, x: unloaded(table, d, x, used))(d_m, delta)
    status = jnp.where(below & ~converged & (status == Status.OK), Status.NOT_CONVERGED, status)
    # At the top (Δ = 0) the unloading tangent is Sneddon's sum, in closed form.
    unloading = jnp.where(below, state.stiffness, jnp.sum(totals.unloading, axis=-1))
    loading = branches(F_star) == Branch.LOADING
    stiffness = jnp.where(loading, jnp.sum(totals.stiffness, axis=-1), unloading)
    area = jnp.where(below, state.area, jnp.sum(totals.area, axis=-1))
    deepest = d_m[-1]  # the path's overall maximum
    residual = table.heights[-1] - deepest - full_recovery(table, deepest, used)
    return _points(table, d_m + delta, stiffness, unloading, area, status, residual)


def _points(table: SummitTable, d, stiffness, unloading, area, status, residual) -> PathPoints:
    """The `PathPoints` of the flat's heights `d` along the path; `residual`, the top summit's residual
    interference after the path (table units)."""
    ok = status == Status.OK
    nan = lambda x: jnp.where(ok, x, jnp.nan)  # noqa: E731
    return PathPoints(
        approach_star=nan((d[0] - d) * table.span),
        stiffness_star=nan(stiffness),
        unloading_star=nan(unloading),
        real_area_star=nan(area),
        status=status.astype(jnp.int32),
        residual_star=jnp.where(jnp.all(ok), residual * table.span, jnp.nan),
    )


# The root finder's residual and slope, increasing in y = −Δ (`_measured_asperities` notes why
# every traced value is an argument).
def _residual(y, args, used):
    table, d_m, target = args
    return jnp.log(unloaded(table, d_m, -y, used).load) - target, None


def _residual_slope(y, args, used):
    table, d_m, _ = args
    state = unloaded(table, d_m, -y, used)
    return table.span * state.stiffness / state.load
