"""The contact solution on its own contact set, as a differentiable linear problem, and the exact
tangent stiffness.

At a converged solution the points split into those in elastic contact (A: 0 < p < H, zero gap),
plastic ones (U: p = H) and the rest (p = 0). With the sets held, the solution solves a linear
system: `(C p)_A − h_A − δ = 0`, `p_U = H`, `Σ p = P`. With `x1 = C_AA⁻¹ 1` and
`x2 = C_AA⁻¹ (h_A − (C H 1_U)_A)`: `δ = (P − |U| H − Σ x2) / Σ x1`, `p_A = x2 + δ x1`. Solved
here by conjugate gradients (`C_AA` is symmetric positive definite unless the interface is closed)
through `jax.lax.custom_linear_solve`, whose derivative rule solves the same system again, so that
`jax.grad` and `jax.jvp` are exact implicit derivatives with respect to the heights, the load and
the hardness: the iterations that found the sets are never differentiated. The stopping test is
relative to the right-hand side's 2-norm, for the tangent and cotangent systems as for the primal
one, whatever their scale; a zero right-hand side (a flat punch's heights) has the solution 0.
The tangent stiffness of the discretised contact is `dP/dδ = Σ x1` (elastic points
keep their zero gap, plastic ones their p = H): it depends on the sets alone, so that it is
piecewise constant in the heights, the load and the hardness, and changes only where a grid point
enters or leaves contact.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from ._operator import Compliance


def conjugate_gradients(matvec, b, start, tolerance: float, max_steps: int, diagonal=None):
    """CG from `start` until `‖b − A x‖ ≤ tolerance ‖b‖` (or `max_steps`); 0 for b = 0. With
    `diagonal`, preconditioned by its inverse (Jacobi)."""
    bound = (tolerance * jnp.linalg.norm(b)) ** 2

    def precondition(r):
        return r if diagonal is None else r / diagonal

    def running(state):
        _, r, _, _, step = state
        return (jnp.sum(r * r) > bound) & (step < max_steps) & (bound > 0)

    def body(state):
        x, r, d, rz, step = state
        Ad = matvec(d)
        alpha = rz / jnp.sum(d * Ad)
        x, r = x + alpha * d, r - alpha * Ad
        z = precondition(r)
        rz_new = jnp.sum(r * z)
        return x, r, z + (rz_new / rz) * d, rz_new, step + 1

    r = b - matvec(start)
    z = precondition(r)
    x, *_ = jax.lax.while_loop(running, body, (start, r, z, jnp.sum(r * z), 0))
    return jnp.where(bound > 0, x, 0.0)


def _active_solve(compliance: Compliance, active, vector, start, tolerance: float):
    """`C_AA⁻¹ vector` on the active points (the identity elsewhere keeps the operator invertible)."""

    def matvec(v):
        return jnp.where(active, compliance(jnp.where(active, v, 0.0)), v)

    def solve(operator, b):
        return conjugate_gradients(operator, b, start, tolerance, 4 * b.shape[0] + 200)

    return jax.lax.custom_linear_solve(matvec, vector, solve, symmetric=True)


def _unit_response(compliance: Compliance, points, tolerance: float):
    """`C_PP⁻¹ 1` on the points P (0 elsewhere): the pressure of a unit rigid approach of P."""
    ones = jnp.where(points, 1.0, 0.0).astype(compliance.stiffness.dtype)
    return _active_solve(compliance, points, ones, jnp.zeros_like(ones), tolerance)


def frozen_solution(
    compliance: Compliance,
    heights,
    total,
    hardness,
    active,
    plastic,
    guess,
    guess_offset,
    tolerance: float,
    fixed_compliance: bool = True,
):
    """`(pressure, offset, stiffness)` on the sets `active` (0 < p < H) and `plastic` (p = H), grid units.

    `guess`, `guess_offset`: the pressure and offset the constrained iteration found (a warm start
    for the second solve); `tolerance`: the conjugate gradients' relative tolerance;
    `fixed_compliance`: whether the compliance is a constant of the differentiation (the normal one
    in grid units is; the tangential one depends on ν).
    """
    x1 = _unit_response(compliance, active, tolerance)
    plastic_pressure = jnp.where(plastic, jnp.where(plastic, hardness, 0.0), 0.0).astype(heights.dtype)
    rhs = jnp.where(active, heights - compliance(plastic_pressure), 0.0)
    start = jax.lax.stop_gradient(jnp.where(active, guess - guess_offset * x1, 0.0))
    x2 = _active_solve(compliance, active, rhs, start, tolerance)
    stiffness = jnp.sum(jnp.where(active, x1, 0.0))
    # Σ x2 = 1ᵀ C_AA⁻¹ rhs = x1ᵀ rhs (C_AA symmetric): written so, the offset's derivative is a dot
    # product with x1, which depends on the sets alone, and needs no solve per tangent direction.
    weights = jax.lax.stop_gradient(x1) if fixed_compliance else x1
    offset = (total - jnp.sum(plastic_pressure) - jnp.sum(weights * rhs)) / stiffness
    pressure = jnp.where(active, x2 + offset * x1, plastic_pressure)
    return pressure, offset, stiffness


def elastic_stiffness(compliance: Compliance, contact, tolerance: float):
    """`Σ C_CC⁻¹ 1` on the contact set C, plastic points included: the tangent of a small unload,
    in which every point in contact moves with the surface (grid units)."""
    return jnp.sum(jnp.where(contact, _unit_response(compliance, contact, tolerance), 0.0))
