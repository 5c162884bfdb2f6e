"""Two-scale contact: a mesoscale gap between two smooth elastic bodies, the roughness between them a
compliant layer (`bem._layer`) in series with the half-space (docs/bolted-joint.md).

At every grid point the bodies' approach Δ less the gap g less the elastic displacement u = C p is
taken up by the layer: `u + c(p) + g − Δ = 0` where the point carries pressure, `≥ 0` where it does
not (where the layer lets go), with `Σ p a = F` (a the pixel area). In units of the grid spacing s and of
the modulus E (x = p/E): `R(x) = C x + c(E x)/s + g/s − Δ/s`. The energy `½xᵀCx + Σ∫c + Σ g x` is
convex, and Newton's method on the points that carry pressure, with the load as a constraint,
solves it: each step two conjugate-gradient solves with `H = C + diag(c'(E x) E/s)` (symmetric
positive definite), then the points it would push below zero are released.

Derivatives are exact implicit ones: one Newton correction from the converged state with the state
held, `(x, Δ) − J⁻¹ (R, Σx − F*)`, whose derivative is `−J⁻¹ ∂(R, Σx − F*)/∂θ` (the linear solve by
`jax.lax.custom_linear_solve`). The normal stiffness is `dF/dΔ = E s 1ᵀH⁻¹1` on the loaded points; the
tilt stiffnesses, `dM/dθ` at fixed load for a rotation about each in-plane axis through the map's
centre, `E s (ξᵀH⁻¹ξ − (ξᵀH⁻¹1)²/1ᵀH⁻¹1)` with ξ the lever arm. On unloading the same, with the layer's
unloading compliance in H (a plastically flattened roughness unloads stiffer than it loaded).
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float, Int

from ..numerics._validate import InputError, check_range, check_strategy
from ..quantities import Status
from ._checks import check_arguments, check_iteration
from ._layer import AbstractLayer
from ._operator import SUBSTRATES, AbstractSubstrate, Compliance, Periodic
from ._tangent import conjugate_gradients

# Each Newton step's linear solves, relative to their right-hand side (float32, float64).
_CG_TOLERANCE = (1e-6, 1e-12)


class LayeredSolution(eqx.Module):
    """The two-scale contact at each load (leading axis: the loads).

    **Fields:** `loads` (N); `pressure` (Pa, loads × n × n); `approach` (m), the bodies' approach
    Δ (the layer's closure plus the elastic displacement plus the gap at a loaded point);
    `stiffness` (N/m), dF/dΔ; `tilt_stiffness` (N·m/rad, loads × 2), about the axes along the
    rows and the columns through the map's centre; `dynamic_stiffness` and `dynamic_tilt_stiffness`,
    the same on unloading from the state loading reached (each loaded point's layer with its
    unloading stiffness `k_n,dyn`, the contact set held: a small vibration about the load once its
    first cycle is past; equal to the loading ones for a layer that unloads as it loads);
    `contact_fraction`, the share of points that carry
    pressure; `status` (0 = ok; `LOAD_OUT_OF_RANGE` where a point's pressure exceeds the layer's
    `highest`); `iterations` (Newton steps).
    """

    loads: Float[Array, " loads"]
    pressure: Float[Array, "loads n n"]
    approach: Float[Array, " loads"]
    stiffness: Float[Array, " loads"]
    tilt_stiffness: Float[Array, "loads 2"]
    dynamic_stiffness: Float[Array, " loads"]
    dynamic_tilt_stiffness: Float[Array, "loads 2"]
    contact_fraction: Float[Array, " loads"]
    status: Int[Array, " loads"]
    iterations: Int[Array, " loads"]


class _Grid(eqx.Module):
    """The problem in grid units (module docstring) with its layer, one load."""

    compliance: Compliance
    layer: AbstractLayer
    gap: Float[Array, "n n"]  # g/s
    modulus: Float[Array, ""]
    spacing: Float[Array, ""]
    tolerance: float = eqx.field(static=True)  # the Newton residual's, relative (`_newton`)

    def residual(self, x, approach):
        closure = self.layer.closure(self.modulus * x)
        return self.compliance(x) + closure / self.spacing + self.gap - approach

    def diagonal(self, x, unloading: bool = False):
        compliance = self.layer.unloading_compliance if unloading else self.layer.compliance
        return compliance(self.modulus * x) * self.modulus / self.spacing

    def solver(self, x, loaded, unloading: bool = False):
        """`v ↦ H_LL⁻¹ v` on the loaded points `loaded` (the identity elsewhere); with `unloading`, H
        holds the layer's compliance on unloading."""
        d = self.diagonal(x, unloading)
        own = self.compliance(jnp.zeros_like(x).at[0, 0].set(1.0))[0, 0]  # a pixel's own compliance
        jacobi = jnp.where(loaded, own + d, 1.0)

        def matvec(v):
            return jnp.where(loaded, self.compliance(jnp.where(loaded, v, 0.0)) + d * v, v)

        steps, tolerance = 4 * x.size + 200, _CG_TOLERANCE[x.dtype == jnp.float64]

        def cg(operator, b):
            return conjugate_gradients(operator, b, jnp.zeros_like(b), tolerance, steps, jacobi)

        # The solve's derivative is the same solve again (symmetric H): reverse mode through K.
        return lambda v: jax.lax.custom_linear_solve(matvec, jnp.where(loaded, v, 0.0), cg, symmetric=True), matvec


def _newton(grid: _Grid, total, max_iterations: int):
    """The converged `(x, Δ/s, loaded, iterations, converged)` at the load `total` (Σx)."""
    n2 = grid.gap.size

    def loaded_set(x, r):
        return (x > 0) | (r < 0)

    def step(state):
        x, approach, _, k, _ = state
        r = grid.residual(x, approach)
        loaded = loaded_set(x, r)
        solve, _ = grid.solver(x, loaded)
        step_x, lam = _bordered(solve, loaded, -r, total - jnp.sum(x), 1.0)
        dx = jnp.where(loaded, step_x, 0.0)
        x_new = jnp.maximum(x + dx, 0.0)  # a point pushed below zero lets go
        r_new = grid.residual(x_new, approach + lam)
        held = loaded_set(x_new, r_new)
        # Loaded points off their balance, open ones that penetrate, relative to
        # the displacements at stake: the gap's relief and the approach (the layer's closure on a flat).
        scale = jnp.maximum(jnp.max(grid.gap) - jnp.min(grid.gap), jnp.abs(approach + lam - jnp.min(grid.gap)))
        worst = jnp.max(jnp.where(x_new > 0, jnp.abs(r_new), jnp.maximum(-r_new, 0.0)))
        done = (worst <= grid.tolerance * scale) & (jnp.abs(jnp.sum(x_new) - total) <= grid.tolerance * total)
        return x_new, approach + lam, held, k + 1, done

    def running(state):
        return ~state[4] & (state[3] < max_iterations)

    x0 = jnp.full(grid.gap.shape, total / n2)
    start = (x0, jnp.mean(grid.gap), jnp.ones_like(x0, bool), 0, jnp.zeros((), bool))
    return jax.lax.while_loop(running, step, start)


def _bordered(solve, loaded, bx, ba, sign):
    """`(x, a)` solving J (x, a) = (b_x, b_a) on the loaded points, J = [[H, −1], [1ᵀ, 0]] (sign = 1:
    a Newton step with Δ as the load's multiplier) or its transpose [[H, 1], [−1ᵀ, 0]] (sign = −1),
    by the Schur complement: x = H⁻¹b_x + sign·a H⁻¹1 with Σx = sign·b_a (`solve`: H⁻¹ on them).
    Points not loaded keep b_x."""
    y1, y2 = solve(jnp.ones_like(bx)), solve(bx)
    a = sign * (sign * ba - jnp.sum(jnp.where(loaded, y2, 0.0))) / jnp.sum(jnp.where(loaded, y1, 0.0))
    return jnp.where(loaded, y2 + sign * a * y1, bx), a


def _implicit(grid: _Grid, x_star, approach_star, loaded, total):
    """`(x, Δ/s)` equal to the converged ones, with their implicit derivatives (module docstring)."""
    held = jax.lax.stop_gradient
    x_star, approach_star = held(x_star), held(approach_star)
    frozen = jax.tree.map(held, grid)
    solve, matvec_h = frozen.solver(x_star, loaded)

    shape = x_star.shape
    # One flat vector (the map, then Δ): custom_linear_solve takes a symbolic zero tangent of one
    # part of a tuple right-hand side as no value.
    split = lambda v: (v[:-1].reshape(shape), v[-1])  # noqa: E731
    join = lambda vx, va: jnp.concatenate([vx.reshape(-1), va[None]])  # noqa: E731

    def matvec(v):
        vx, va = split(v)
        return join(jnp.where(loaded, matvec_h(vx) - va, vx), jnp.sum(jnp.where(loaded, vx, 0.0)))

    def bordered(b, sign):
        return join(*_bordered(solve, loaded, *split(b), sign))

    rhs = join(jnp.where(loaded, grid.residual(x_star, approach_star), 0.0), jnp.sum(x_star) - total)
    delta = jax.lax.custom_linear_solve(
        matvec, rhs, lambda m, b: bordered(b, 1.0), transpose_solve=lambda m, b: bordered(b, -1.0)
    )
    dx, da = split(delta)
    return x_star - jnp.where(loaded, dx, 0.0), approach_star - da


def _tangents(solve, loaded, dtype):
    """K and the two tilt stiffnesses (units of E s) of the loaded points, `solve` being H⁻¹ there."""
    n = loaded.shape[0]
    lever = jnp.arange(n, dtype=dtype) - (n - 1) / 2
    ones = jnp.where(loaded, 1.0, 0.0).astype(dtype)
    y1 = solve(ones)
    stiffness = jnp.sum(ones * y1)
    tilts = []
    for arm in (jnp.broadcast_to(lever[:, None], loaded.shape), jnp.broadcast_to(lever[None, :], loaded.shape)):
        arm = jnp.where(loaded, arm, 0.0)
        tilts.append(jnp.sum(arm * solve(arm)) - jnp.sum(arm * y1) ** 2 / stiffness)
    return stiffness, jnp.stack(tilts)


def layered_at(grid: _Grid, total, max_iterations: int):
    """One load: the pressure (units of E), Δ/s, K and the tilt stiffnesses on loading and on unloading
    (units of E s), the loaded set, the Newton steps and whether they converged."""
    x_star, approach_star, loaded, iterations, converged = _newton(
        jax.tree.map(jax.lax.stop_gradient, grid), jax.lax.stop_gradient(total), max_iterations
    )
    x, approach = _implicit(grid, x_star, approach_star, loaded, total)
    loading = _tangents(grid.solver(x, loaded)[0], loaded, x.dtype)
    if grid.layer.unloads_as_it_loads():
        return x, approach, loading, loading, loaded, iterations, converged
    # The contact set held: a small unloading opens no point and closes none.
    unloading = _tangents(grid.solver(x, loaded, True)[0], loaded, x.dtype)
    return x, approach, loading, unloading, loaded, iterations, converged


@eqx.filter_jit
def _solve_layered(gap, size, modulus, loads, layer, substrate: AbstractSubstrate, tolerance, max_iterations):
    n = gap.shape[0]
    spacing = size / n
    grid = _Grid(Compliance.build(n, substrate, gap.dtype), layer, gap / spacing, modulus, spacing, tolerance)
    usable = jnp.isfinite(loads) & (loads > 0)
    totals = jnp.where(usable, loads, modulus * size * size * 1e-4) / (modulus * spacing**2)
    x, approach, (K, tilt), (K_u, tilt_u), loaded, iterations, converged = jax.vmap(
        lambda t: layered_at(grid, t, max_iterations)
    )(totals)
    status = jnp.where(converged, Status.OK, Status.NOT_CONVERGED)
    # A point pressed beyond the layer's law: the answer would rest on an extrapolation.
    beyond = jnp.max(x, axis=(1, 2)) * modulus > layer.highest()
    status = jnp.where(usable, jnp.where(beyond, Status.LOAD_OUT_OF_RANGE, status), Status.INVALID_LOAD)
    ok = status == Status.OK
    nan = lambda v, unit: jnp.where(ok.reshape((-1,) + (1,) * (v.ndim - 1)), v * unit, jnp.nan)  # noqa: E731
    pressure = x * modulus
    fraction = jnp.mean(pressure > 0, axis=(1, 2))
    return LayeredSolution(
        loads=loads,
        pressure=nan(pressure, 1.0),
        approach=nan(approach, spacing),
        stiffness=nan(K, modulus * spacing),
        tilt_stiffness=nan(tilt, modulus * spacing**3),
        dynamic_stiffness=nan(K_u, modulus * spacing),
        dynamic_tilt_stiffness=nan(tilt_u, modulus * spacing**3),
        contact_fraction=jnp.where(ok, fraction.astype(gap.dtype), jnp.nan),
        status=status.astype(jnp.int32),
        iterations=iterations.astype(jnp.int32),
    )


def solve_layered(
    gap,
    size,
    modulus,
    loads,
    layer: AbstractLayer,
    *,
    substrate: AbstractSubstrate = Periodic(),
    tolerance: float | None = None,
    max_iterations: int = 100,
) -> LayeredSolution:
    """Two-scale contact (module docstring): the pressure over a mesoscale gap with the roughness a
    compliant layer, at each total load.

    **Arguments:**

    - `gap`: the mesoscale gap g(x, y) between the two bodies' mean surfaces, m, an n × n map (its
      level is arbitrary: `approach` is measured from it).
    - `size`: the map's side, m; `modulus`: the bodies' contact modulus E*, Pa.
    - `loads`: total normal loads, N, a 1-D array.
    - `layer`: the roughness's law, `bem.WinklerLayer(k)` or `bem.TabulatedLayer.from_law(jc.interface_law(...))`.
    - `substrate`: `bem.Periodic()` (the map repeats) or `bem.Free()` (an isolated patch).
    - `tolerance`: the balance of every point and of the load, relative to the displacements at
      stake (the gap's relief, the approach) and to the load (default 1e-9 in float64, 1e-5 in
      float32); `max_iterations`: Newton steps.

    **Returns:** a `LayeredSolution`. `jax.grad` and `jax.jvp` with respect to the gap, size,
    modulus, loads and the layer's arrays are exact implicit derivatives.

    **Raises:** `ValueError` for a map that is not square, non-finite heights, or a non-positive size,
    modulus or load.
    """
    check_arguments(gap, size, modulus, loads, None)
    check_iteration(None, max_iterations)
    check_strategy("substrate", substrate, AbstractSubstrate, SUBSTRATES, "bem")
    if not isinstance(layer, AbstractLayer):
        raise InputError(f"layer = {layer!r} must be bem.WinklerLayer(k) or bem.TabulatedLayer(...)")
    dtype = jnp.result_type(gap, loads, 1.0)
    if tolerance is None:
        tolerance = 1e-9 if dtype == jnp.float64 else 1e-5
    check_range("tolerance", tolerance, 0.0, 1e-2, meaning="relative")
    arrays = tuple(jnp.asarray(x, dtype) for x in (gap, size, modulus, loads))
    return _solve_layered(*arrays, layer, substrate, float(tolerance), int(max_iterations))
