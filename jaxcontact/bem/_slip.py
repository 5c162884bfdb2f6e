"""Partial slip of a boundary-element contact under a tangential force, and its friction loops
(docs/in-service.md).

The normal contact is solved at the preload first. A tangential force Q along the rows then
loads it point by point with Coulomb's law (Polonsky & Keer's tangential problem in the
uncoupled approximation of two bodies of like material, as `_tangential` forms its compliance
`C_t`): the traction `q ≥ 0` on the contact set, capped at `μp` of each point's pressure, carries
`Σq = Q`; where `0 < q < μp` the point sticks and moves with the rigid body's tangential
displacement δ (`C_t q = δ`), where `q = μp` it slides (`C_t q ≤ δ`). It is the capped normal
problem with the cap `μp` per point, zero heights and δ its multiplier, solved by the same
constrained conjugate gradients (`_ccg.contact_cg`).

Cycled between ±Q₀ at constant normal load, each branch is the first loading doubled in both axes
from its turning point (Masing's rule; exact for the uncoupled problem while the stick zones shrink
monotonically, Cattaneo–Mindlin's superposition). With δ(Q) the first loading, the branch back
from Q₀ lies `2δ((Q₀ − Q)/2)` behind the tip, and the loop encloses

    W = 4 Q₀ δ(Q₀) − 8 ∫₀^{Q₀} δ(Q) dQ = 4 Q₀ s(Q₀) − 8 ∫₀^{Q₀} s dQ,   s = δ − Q/K_t,

with `K_t` the full-stick tangential stiffness (the linear part cancels, so that W ∝ Q₀³ at small
amplitude keeps its precision): Gauss–Legendre in Q.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float, Int

from ..numerics import InputError, check_range
from ..numerics._quadrature import gauss_legendre
from ..quantities import Status
from ._ccg import contact_cg
from ._checks import check_arguments, check_iteration, valid_problem
from ._contact import DEFAULT_TOLERANCE, contact_at
from ._operator import AbstractSubstrate, Periodic
from ._problem import GridProblem
from ._tangent import frozen_solution


class FrictionLoops(eqx.Module):
    """A boundary-element contact's friction loops about a preload, per tangential force amplitude.

    **Fields:** `force` Q₀ (N); `displacement` u₀ (m), the first loading's displacement at Q₀ (the
    loop's tip); `dissipation` W (J) per cycle; `secant_stiffness` Q₀/u₀ (N/m); `damping_ratio`
    W/(2π Q₀ u₀); `stick_share`, the share of the contact points that stick at Q₀;
    `stick_stiffness` (N/m), the full-stick tangential stiffness; `macroslip_force` μF (N);
    `status` per amplitude (`jaxcontact.Status`); `iterations` of the tangential solves.
    """

    force: Float[Array, " amplitudes"]
    displacement: Float[Array, " amplitudes"]
    dissipation: Float[Array, " amplitudes"]
    secant_stiffness: Float[Array, " amplitudes"]
    damping_ratio: Float[Array, " amplitudes"]
    stick_share: Float[Array, " amplitudes"]
    stick_stiffness: Float[Array, ""]
    macroslip_force: Float[Array, ""]
    status: Int[Array, " amplitudes"]
    iterations: Int[Array, " amplitudes"]


def friction_loops(
    heights: Float[ArrayLike, "n n"],
    size,
    modulus,
    load,
    mu,
    forces: Float[ArrayLike, " amplitudes"],
    *,
    poisson,
    hardness=None,
    substrate: AbstractSubstrate = Periodic(),
    nodes: int = 8,
    tolerance: float | None = None,
    max_iterations: int = 2000,
) -> FrictionLoops:
    """The friction loops of the contact of `heights` pressed by `load`, for each tangential force
    amplitude (module docstring).

    **Arguments:** `heights`, `size`, `modulus`, `hardness`, `substrate`, `tolerance` and
    `max_iterations` as `bem.solve` takes them; `load`, the normal load F, N; `mu`, the friction
    coefficient μ > 0; `forces`, tangential force amplitudes Q₀, N, a 1-D array in (0, μF);
    `poisson`, Poisson's ratio ν in [0, 0.5) of two bodies of like material; `nodes`,
    Gauss–Legendre nodes in Q on [0, Q₀] (static, 2–64). It holds one traction map per node and
    amplitude at once: `(nodes + 1) × amplitudes` maps of n² values.

    **Returns:** a `FrictionLoops`. Differentiable (`jax.grad`, `jax.jvp`) with respect to the
    heights, the load, μ, the forces and ν: the iterations find the contact, stick and slip sets, and
    the solutions on them are differentiated implicitly (`_tangent.frozen_solution`), as `bem.solve`'s
    are. A force at or beyond μF is flagged `LOAD_OUT_OF_RANGE` (the contact
    slides as a whole); a solve that does not converge `NOT_CONVERGED`.

    **Raises:** `ValueError` as `bem.solve` for the map and the iteration, and for a non-positive
    load or μ, amplitudes that are not 1-D or not positive, ν outside [0, 0.5), or `nodes` outside 2–64.
    """
    check_arguments(heights, size, modulus, jnp.atleast_1d(load), hardness, loads_name="load")
    check_iteration(tolerance, max_iterations)
    check_range("mu", mu, 0.0, meaning="friction coefficient")
    check_range("poisson", poisson, 0.0, 0.5, low_open=False, meaning="Poisson's ratio of like materials")
    if jnp.ndim(forces) != 1:
        raise InputError(f"forces has shape {jnp.shape(forces)}: give a 1-D array of tangential forces (N)")
    check_range("forces", forces, 0.0, meaning="N")
    if isinstance(nodes, bool) or not isinstance(nodes, int) or not 2 <= nodes <= 64:
        raise InputError(f"nodes = {nodes!r} must be an integer in [2, 64]")
    dtype = jnp.result_type(heights, forces, 1.0)
    if tolerance is None:
        tolerance = DEFAULT_TOLERANCE.get(np.dtype(dtype), 1e-5)
    arrays = tuple(jnp.asarray(x, dtype) for x in (heights, size, modulus, load, mu, forces, poisson))
    cap = None if hardness is None else jnp.asarray(hardness, dtype)
    return _loops(*arrays, cap, substrate, nodes, float(tolerance), int(max_iterations))


@eqx.filter_jit
def _loops(heights, size, modulus, load, mu, forces, nu, hardness, substrate, nodes, tolerance, max_iterations):
    sound, heights, size, modulus, hardness = valid_problem(heights, size, modulus, hardness)
    sound &= jnp.isfinite(mu) & (mu > 0)
    mu = jnp.where(sound, mu, 0.3)
    problem = GridProblem.build(heights, size, modulus, hardness, substrate, True, nu)
    total = load / problem.load_unit
    uniform = jax.lax.stop_gradient(jnp.full_like(problem.heights, total / problem.heights.size))
    normal = contact_at(problem, total, uniform, tolerance, max_iterations)
    # The cap per point, differentiable through the normal solve's own implicit derivative.
    limit = mu * jnp.where(normal["found"] > 0, normal["pressure"], 0.0)
    stick = normal["tangential_stiffness"]  # full stick, grid units
    macroslip = jnp.sum(limit)
    amplitudes = forces / problem.load_unit
    in_range = (amplitudes > 0) & (amplitudes < macroslip) & jnp.isfinite(amplitudes)
    amplitudes = jnp.where(in_range, amplitudes, 0.5 * macroslip)  # flagged ones: a stand-in, solved and dropped

    x, w = gauss_legendre(nodes)
    fractions = jnp.concatenate([0.5 * (jnp.asarray(x, heights.dtype) + 1.0), jnp.ones((1,), heights.dtype)])
    levels = (amplitudes[:, None] * fractions[None, :]).reshape(-1)
    order = jnp.argsort(levels)
    held_compliance, held_limit = jax.lax.stop_gradient((problem.tangential, limit))
    zeros = jnp.zeros_like(limit)

    def sets(traction):
        """The points that stick (0 < q < μp) and those that slide (q = μp) under a traction map."""
        return (traction > 0) & (traction < held_limit), (traction >= held_limit) & (held_limit > 0)

    def one(carry, level):
        ratio = level / jnp.where(carry[1] > 0, carry[1], 1.0)
        start = jnp.where(carry[1] > 0, carry[0] * ratio, held_limit * (level / jnp.sum(held_limit)))
        # The iteration finds the stick and slip sets (never differentiated); the solution on them is
        # the differentiable one (`_tangent.frozen_solution`, the capped normal problem's).
        state = contact_cg(held_compliance, zeros, level, held_limit, start, tolerance, max_iterations)
        return (state.pressure, level), (state.pressure, state.offset, state.converged, state.iterations)

    start = (zeros, jnp.zeros((), limit.dtype))
    _, found = jax.lax.scan(one, start, jax.lax.stop_gradient(levels[order]))
    back = jnp.argsort(order)
    tractions, guesses, converged, iterations = (a[back] for a in found)

    def frozen(level, traction, guess):
        stuck, slid = sets(traction)
        args = (zeros, level, limit, stuck, slid, traction, guess, tolerance)
        _, offset, _ = frozen_solution(problem.tangential, *args, fixed_compliance=False)
        return offset

    offsets = jax.lax.map(lambda a: frozen(*a), (levels, tractions, guesses))
    shape = (amplitudes.size, nodes + 1)
    offsets, converged, iterations = (a.reshape(shape) for a in (offsets, converged, iterations))
    tips = tractions.reshape(*shape, *limit.shape)[:, -1]
    contact = jnp.maximum(jnp.sum(held_limit > 0, dtype=limit.dtype), 1.0)
    shares = jnp.sum(sets(tips)[0], axis=(1, 2), dtype=limit.dtype) / contact
    slip = offsets - levels.reshape(shape) / stick  # δ − Q/K_t, grid units
    weights = 0.5 * jnp.asarray(w, heights.dtype) * amplitudes[:, None]
    energy = 4.0 * amplitudes * slip[:, -1] - 8.0 * jnp.sum(weights * slip[:, :-1], axis=1)

    status = jnp.where(jnp.all(converged, axis=1), normal["status"], Status.NOT_CONVERGED)
    status = jnp.where(in_range, status, Status.LOAD_OUT_OF_RANGE)
    status = jnp.where(sound, status, Status.INVALID_PARAMETERS).astype(jnp.int32)
    ok = status == Status.OK
    displacement = offsets[:, -1] * problem.scale
    dissipation = energy * problem.load_unit * problem.scale
    nan = lambda x: jnp.where(ok, x, jnp.nan)  # noqa: E731
    return FrictionLoops(
        force=forces,
        displacement=nan(displacement),
        dissipation=nan(dissipation),
        secant_stiffness=nan(forces / displacement),
        damping_ratio=nan(dissipation / (2 * math.pi * forces * displacement)),
        stick_share=nan(shares),
        stick_stiffness=jnp.where(normal["status"] == Status.OK, stick * problem.stiffness_unit, jnp.nan),
        macroslip_force=macroslip * problem.load_unit,
        status=status,
        iterations=jnp.sum(iterations, axis=1),
    )
