"""The compiled program of `fit_batch`: per curve and start, optax's L-BFGS on the curve's misfit (its
weighted residuals over the noise σ, and a prior's residuals where there is one), the best start
finished by Gauss–Newton steps, and the residuals and Jacobian at the end for the statistics."""

from __future__ import annotations

import jax
import jax.numpy as jnp

from jaxcontact.numerics import standard_promotion

from ._misfit import Misfit

# Gauss–Newton steps after L-BFGS (each taken only where it lowers the loss): from where L-BFGS's tests
# stop on the ill-conditioned D–G valley, a few reach the least-squares optimum to round-off.
POLISH_STEPS = 4


def solver(misfit: Misfit, max_iter: int, tol: float):
    """One curve's fit from one start `u0`: optax L-BFGS on `misfit.loss` until the gradient's norm or
    the loss's relative progress falls below `tol`, or `max_iter` steps."""
    import optax

    loss = misfit.loss
    optimiser = optax.lbfgs()

    # The line search leaves the value and gradient at its accepted point in the state: the next
    # step takes them from there. (`optax.value_and_grad_from_state` would do it by a `cond`, which
    # under `vmap` computes the gradient again on every step.)
    def body(carry):
        u, state, value, grad, _, k = carry
        updates, state = optimiser.update(grad, state, u, value=value, grad=grad, value_fn=loss)
        new_value = optax.tree_utils.tree_get(state, "value")
        new_grad = optax.tree_utils.tree_get(state, "grad")
        return optax.apply_updates(u, updates), state, new_value, new_grad, value, k + 1

    def going(carry):
        _, _, value, grad, previous, k = carry
        small = (jnp.linalg.norm(grad) < tol) | (jnp.abs(previous - value) <= tol * jnp.abs(value))
        return (k < max_iter) & ~((k > 2) & small)

    def run(u0):
        value, grad = misfit.value_and_grad(u0)
        with standard_promotion():
            init = (u0, optimiser.init(u0), value, grad, jnp.asarray(jnp.inf, u0.dtype), 0)
            u, _, value, _, _, k = jax.lax.while_loop(going, body, init)
        return u, value, k

    return run


def polished(misfit: Misfit, u):
    """Gauss–Newton steps from `u` (optimiser coordinates) on the misfit's residuals (the curve's over
    σ, and the prior's), each kept only where it lowers the loss: `(u, loss, r, ok, status, J)` at the
    best point evaluated, the curve's own `r` and `J = ∂r/∂stat`. One evaluation per step, the same
    program each time."""

    def step(_, carry):
        trial, best_u, best = carry
        found = misfit.evaluate(trial)
        r = found[0].reshape(-1)
        loss = misfit.loss_of(r, found[4])
        better = jnp.isfinite(loss) & (loss < best[0])
        best_u = jnp.where(better, trial, best_u)
        best = jax.tree.map(lambda new, old: jnp.where(better, new, old), (loss, *found), best)
        residuals, J_u = misfit.linearised(best_u, best[1:])
        JTJ = J_u.T @ J_u
        nudge = 1e-12 * jnp.trace(JTJ) * jnp.eye(JTJ.shape[0], dtype=JTJ.dtype)
        delta = jnp.linalg.solve(JTJ + nudge, -J_u.T @ residuals)
        return best_u + jnp.where(jnp.isfinite(delta), delta, 0.0), best_u, best

    shapes = jax.eval_shape(misfit.evaluate, u)
    empty = (jnp.asarray(jnp.inf, u.dtype), *(jnp.zeros(x.shape, x.dtype) for x in shapes))
    _, u, (loss, r, ok, status, J, _, _) = jax.lax.fori_loop(0, POLISH_STEPS, step, (u, u, empty))
    return u, loss, r, ok, status, J


def fit_curves(scene, data, sigmas, prior, u0s, fitted, max_iter: int, tol: float, index, kind):
    """Each curve (`data`, each one's `Observations` stacked, and its σ in `sigmas`; the prior's arrays or
    None) fitted from every start `u0s`: vmap over curves of (vmap over starts of the solver, the best
    start polished, its loss, steps, residuals, valid mask, statuses and Jacobian; every start's end
    and loss)."""

    def one_curve(data, sigma):
        misfit = Misfit(scene, data, sigma, prior, fitted, index, kind)
        us, losses, ks = jax.vmap(solver(misfit, max_iter, tol))(u0s)
        best = jnp.argmin(jnp.where(jnp.isfinite(losses), losses, jnp.inf))
        u, loss, r, ok, status, J = polished(misfit, us[best])
        # Every start's end, the best one polished: where the others ended says whether a distinct
        # optimum fits almost as well (`rival_optima`).
        return u, loss, ks[best], r, ok, status, J, us.at[best].set(u), losses.at[best].set(loss)

    return jax.vmap(one_curve)(data, sigmas)
