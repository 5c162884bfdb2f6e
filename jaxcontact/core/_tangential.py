"""Partial slip and friction hysteresis of a joint about a preload (docs/in-service.md).

The joint is pressed to its preload F (by loading) and displaced tangentially by a displacement u
common to every spot, cycled between ±u₀. Each spot of load P and full-stick tangential stiffness
`k_t` (Mindlin's `8G*r`, `2(1 − ν)/(2 − ν)` times its unloading stiffness, as
`tangential_stiffness` sums them) follows Cattaneo–Mindlin up to its slip displacement
`u* = 3μP/(2k_t)` and Masing's rules on the cycle (`physics._mindlin`). The joint's backbone,
loop and dissipation are the sums over its spots (`_spot_sums`).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float, Int

from ..models import without_single_spots
from ..numerics._validate import InputError, check_range
from ..physics import mindlin_ratio
from ..quantities import Scales, Status, nondimensionalise
from ._loadcontrol import within_domain
from ._scene import Scene
from ._spot_sums import spot_sums


class TangentialCycle(eqx.Module):
    """A joint's friction loop about a preload, per displacement amplitude (docs/in-service.md).

    **Fields:** `amplitude` u₀ (m); `force` Q₀ (N), the backbone at u₀ (the loop's tip);
    `dissipation` W (J), the energy lost per cycle; `secant_stiffness` Q₀/u₀ (N/m);
    `damping_ratio` ζ = W/(2π Q₀ u₀), the viscous damping that dissipates as much per cycle;
    `sliding_share`, the share of the preload carried by spots that slide at u₀; `stick_stiffness`
    (N/m), the slope at u = 0 (`tangential_stiffness` at the preload); `macroslip_force` μF (N),
    where the joint slides as a whole; `status` per amplitude (`jaxcontact.Status`; NaN values where
    not OK).
    """

    amplitude: Float[Array, " amplitudes"]
    force: Float[Array, " amplitudes"]
    dissipation: Float[Array, " amplitudes"]
    secant_stiffness: Float[Array, " amplitudes"]
    damping_ratio: Float[Array, " amplitudes"]
    sliding_share: Float[Array, " amplitudes"]
    stick_stiffness: Float[Array, ""]
    macroslip_force: Float[Array, ""]
    status: Int[Array, " amplitudes"]


def tangential_cycle(
    scene: Scene, preload, amplitudes: Float[ArrayLike, " amplitudes"], mu, *, nodes: int = 16
) -> TangentialCycle:
    """The friction loop of the joint about a preload reached by loading, for each tangential
    displacement amplitude (Cattaneo–Mindlin spots, Masing's rules; module docstring).

    **Arguments:**

    - `scene`: the joint; its model must resolve single spots (`Xia2024`, `JZZ2010`, any
      `AbstractLargestSpotModel`, `GreenwoodWilliamson`, `MeasuredAsperities`).
    - `preload`: the normal load F, N (a scalar; `jax.vmap` for several).
    - `amplitudes`: tangential displacement amplitudes u₀, m, a 1-D array.
    - `mu`: the friction coefficient μ > 0.
    - `nodes`: Gauss–Legendre nodes on each side of each family's slip boundary (static, 8–256).

    **Returns:** a `TangentialCycle`. Differentiable with respect to every float of the scene, the
    preload, the amplitudes and μ; `jax.vmap` over preloads, μ or scenes; float32 works. A preload
    the model cannot solve gives its status at every amplitude; a traced NaN or non-positive
    amplitude `INVALID_LOAD`, a traced μ ≤ 0 `INVALID_PARAMETERS`, the rest of the batch unaffected.

    **Raises:** `ValueError` for a model without single spots (Persson, the BEM), for concrete
    non-positive or non-finite preload, amplitudes or μ, for amplitudes that are not 1-D, and for
    `nodes` outside 8–256.
    """
    if not scene.model.single_spots:
        raise without_single_spots(scene.model)
    if isinstance(nodes, bool) or not isinstance(nodes, int) or not 8 <= nodes <= 256:
        raise InputError(f"nodes = {nodes!r} must be an integer in [8, 256]")
    if jnp.ndim(preload) != 0:
        raise InputError(f"preload has shape {jnp.shape(preload)}: give one load (N); jax.vmap for several")
    if jnp.ndim(amplitudes) != 1:
        raise InputError(f"amplitudes has shape {jnp.shape(amplitudes)}: give a 1-D array of displacements (m)")
    check_range("preload", preload, 0.0, meaning="N")
    check_range("amplitudes", amplitudes, 0.0, meaning="m")
    check_range("mu", mu, 0.0, meaning="friction coefficient")
    dtype = jnp.result_type(scene.material.E, preload, amplitudes, mu, 1.0)
    arrays = (jnp.asarray(preload, dtype), jnp.asarray(amplitudes, dtype), jnp.asarray(mu, dtype))
    return _cycle(scene, *arrays, nodes)


@eqx.filter_jit
def _cycle(scene: Scene, preload, amplitudes, mu, nodes: int) -> TangentialCycle:
    guarded, in_domain = within_domain(scene)
    scales = Scales.of(guarded)
    s = nondimensionalise(guarded)
    usable_load = jnp.isfinite(preload) & (preload > 0)
    load_star = jnp.where(usable_load, preload, scales.load * 1e-6) / scales.load
    state = guarded.model.spot_solver(s)(load_star)
    families, unloading, breakdown = state.spots, state.unloading, state.breakdown
    point_status = jnp.where(in_domain, state.status, Status.INVALID_PARAMETERS)

    valid_mu = jnp.isfinite(mu) & (mu > 0)
    mu_ = jnp.where(valid_mu, mu, 1.0)
    ratio = mindlin_ratio(guarded.material.nu)
    usable = jnp.isfinite(amplitudes) & (amplitudes > 0)
    u0 = jnp.where(usable, amplitudes, scales.length * 1e-9) / scales.length  # in √A_a

    sums = spot_sums(families, u0, mu_ / ratio, nodes)
    force, energy, sliding = mu_ * sums["force"], mu_ * sums["energy"], sums["sliding"]

    at_preload = jnp.where(breakdown, Status.INTERACTION_BREAKDOWN, point_status)
    at_preload = jnp.where(usable_load, at_preload, Status.INVALID_LOAD)
    at_preload = jnp.where((at_preload == Status.OK) & ~sums["monotone"], Status.NOT_CONVERGED, at_preload)
    at_preload = jnp.where(valid_mu, at_preload, Status.INVALID_PARAMETERS)
    status = jnp.where(usable, at_preload, Status.INVALID_LOAD).astype(jnp.int32)
    ok = status == Status.OK
    q0 = force * scales.load
    w = energy * scales.load * scales.length
    amplitude_si = u0 * scales.length
    nan = jnp.nan
    return TangentialCycle(
        amplitude=amplitudes,
        force=jnp.where(ok, q0, nan),
        dissipation=jnp.where(ok, w, nan),
        secant_stiffness=jnp.where(ok, q0 / amplitude_si, nan),
        damping_ratio=jnp.where(ok, w / (2 * math.pi * q0 * amplitude_si), nan),
        sliding_share=jnp.where(ok, sliding / load_star, nan),
        stick_stiffness=jnp.where(at_preload == Status.OK, ratio * unloading * scales.stiffness, nan),
        macroslip_force=jnp.where(usable_load & valid_mu, mu * preload, nan),
        status=status,
    )
