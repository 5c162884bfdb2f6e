"""The load–approach curve by piecewise Gauss–Legendre quadrature (docs/model.md §6).

    δ(F) - δ(F0) = ∫_{ln F0}^{ln F} F'/K_t(F') d(ln F'),

split at every requested load, at the preload and at every kink of K(F) (where `a_l` crosses a
regime boundary, `core.kink_log_loads`), so that the integrand is smooth on each piece and a
fixed Gauss–Legendre rule of a few nodes per piece converges spectrally. The cost is fixed (one
`solve` over `nodes` points per piece), with no adaptive loop: forward-mode derivatives with
respect to the scene's parameters cost one solve's, which is what a fit of δ(F) needs
(`fitting.fit(..., approach=...)`). `approach` (diffrax, adaptive) is the reference it is tested
against.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float, Int

from ..core import Outputs, Scene, kink_log_loads, prepare, solve
from ..numerics import LoadsLike
from ..quantities import Scales, Status


class Approach(eqx.Module):
    """Result of `approach` and `approach_quadrature`: per load, the approach δ(F) − δ(F0) (m) and a
    status (0 = ok).

    A point is flagged (approach NaN) when the model is invalid at that load, at the preload, or
    anywhere on the path between them.
    """

    load: Float[Array, "*loads"]
    reference_load: Float[Array, ""]
    approach: Float[Array, "*loads"]
    status: Int[Array, "*loads"]


def approach_star(scene: Scene, log_loads, log_reference, nodes: int):
    """`(δ*(F) − δ*(F0), status)` at dimensionless `ln F*` (`δ* = δ / sqrt(A_a)`), traceable.

    The pieces' ends are the loads, the preload and the kinks inside their range; the partial
    integrals are summed in load order, so each δ* is one cumulative sum read at its load.
    """
    log_loads = log_loads.reshape(-1)
    # The integrand is continuous at a kink, so the integral does not depend on where a piece ends
    # (the two end terms of Leibniz's rule cancel): no derivative flows through the kinks, whose
    # absent ones (−inf) have none.
    kinks = jax.lax.stop_gradient(kink_log_loads(scene))
    low = jnp.minimum(log_loads.min(), log_reference)
    high = jnp.maximum(log_loads.max(), log_reference)
    # Kinks outside the range add nothing; put at the preload, they make pieces of zero length.
    kinks = jnp.where(jnp.isfinite(kinks) & (kinks > low) & (kinks < high), kinks, log_reference)
    ends = jnp.sort(jnp.concatenate([log_loads, log_reference[None], kinks]))
    t, w = (jnp.asarray(v, log_loads.dtype) for v in np.polynomial.legendre.leggauss(nodes))
    half = 0.5 * (ends[1:] - ends[:-1])
    x = 0.5 * (ends[1:] + ends[:-1])[:, None] + half[:, None] * t
    sol = solve(scene, jnp.exp(x) * Scales.of(scene).load, outputs=Outputs(regime_shares=False))
    good = sol.ok & (sol.stiffness_star > 0)
    slope = jnp.where(good, jnp.exp(x) / jnp.where(good, sol.stiffness_star, 1.0), 0.0)
    piece = half * (slope @ w)
    # A piece of zero length needs no valid node (its nodes all sit on a load that is checked itself).
    bad = jnp.any(~good, axis=1) & (half > 0)
    total = jnp.concatenate([jnp.zeros_like(piece[:1]), jnp.cumsum(piece)])
    at = jnp.searchsorted(ends, log_loads)
    at_reference = jnp.searchsorted(ends, log_reference)
    delta = total[at] - total[at_reference]
    # A load is flagged when a piece on its path from the preload has a bad node, with the status of
    # the first bad node of the first such piece (K = 0 has status ok: "not converged" stands for it).
    first = jnp.argmax(~good, axis=1)
    reasons = jnp.take_along_axis(sol.status.reshape(x.shape), first[:, None], axis=1)[:, 0]
    reasons = jnp.where(reasons == Status.OK, Status.NOT_CONVERGED, reasons)
    lo, hi = jnp.minimum(at, at_reference), jnp.maximum(at, at_reference)
    pieces = jnp.arange(half.size, dtype=lo.dtype)
    on_path = (pieces[None, :] >= lo[:, None]) & (pieces[None, :] < hi[:, None]) & bad[None, :]
    status = jnp.where(jnp.any(on_path, axis=1), reasons[jnp.argmax(on_path, axis=1)], Status.OK)
    return jnp.where(status == Status.OK, delta, jnp.nan), status.astype(jnp.int32)


@eqx.filter_jit
def _approach_quadrature(scene: Scene, loads, reference_load, nodes: int):
    scales = Scales.of(scene)
    delta, status = approach_star(
        scene, jnp.log(loads.reshape(-1) / scales.load), jnp.log(reference_load / scales.load), nodes
    )
    return Approach(loads, reference_load, (delta * scales.length).reshape(loads.shape), status.reshape(loads.shape))


def approach_quadrature(
    scene: Scene, loads: LoadsLike, reference_load: float | Float[ArrayLike, ""], *, nodes: int = 8
) -> Approach:
    """Normal approach of the joint relative to a preload, docs/model.md §6, by piecewise
    Gauss–Legendre quadrature of `dδ/d(ln F) = F/K_t` between the loads, the preload and the kinks
    of K(F).

    **Arguments:**

    - `scene`: the joint and the model choices.
    - `loads`: loads F (N), any shape; they may lie above or below the preload.
    - `reference_load`: the preload F0 (N) at which the approach is zero.
    - `nodes`: Gauss–Legendre nodes per piece, in [2, 64]. Eight give δ to ~1e-7 relative and twelve to
      ~1e-10 on the seed model where consecutive loads are a factor 2 apart (docs/applications.md).

    **Returns:** an `Approach`; `approach[i] = δ(F_i) − δ(F0)` in metres (negative below F0), NaN
    with a non-zero status where the model is invalid on the way from F0 to F_i.
    """
    if isinstance(nodes, bool) or not isinstance(nodes, int) or not 2 <= nodes <= 64:
        raise ValueError(f"nodes = {nodes!r} must be an integer in [2, 64]")
    prepare(scene, reference_load)  # the same checks as a load: positive and finite
    scene, loads = prepare(scene, loads)
    return _approach_quadrature(scene, loads, jnp.asarray(reference_load, loads.dtype), nodes)
