"""The compiled program of `fit_batch`: per curve and start, optax's L-BFGS on the curve's misfit (its
weighted residuals over the noise σ, and a prior's residuals where there is one), the best start
finished by Gauss–Newton steps, and the residuals and Jacobian at the end for the statistics."""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp

from jaxcontact.numerics import standard_promotion

from ._parameters import stat_of_u
from ._prior import traced_residuals
from ._residuals import Observations, observed_residuals


class Misfit(eqx.Module):
    """One curve's misfit: its residuals (`data`, weighted) over the noise `sigma`, and where there is a
    prior (`index` and `kind` static, `prior` its `(root, mean, log_q)`) the prior's `L⁻¹ (φ − μ)`; the
    loss is ½ Σ over both, over the curve's number of residual entries."""

    scene: object
    data: Observations
    sigma: jax.Array
    prior: tuple | None
    fitted: tuple = eqx.field(static=True)
    index: tuple | None = eqx.field(static=True)
    kind: object = eqx.field(static=True)

    def prior_residuals(self, stat):
        if self.prior is None:
            return jnp.zeros((0,), stat.dtype)
        return traced_residuals(self.index, self.kind, *self.prior, stat)

    def loss_of(self, r, r_prior):
        """The loss of the curve's residuals `r` and the prior's `r_prior`."""
        return 0.5 * (jnp.sum((r / self.sigma) ** 2) + jnp.sum(r_prior**2)) / r.size

    def loss(self, u):
        stat = stat_of_u(self.fitted, u)
        r, _, _ = observed_residuals(stat, self.scene, self.fitted, self.data)
        return self.loss_of(r, self.prior_residuals(stat))

    def evaluate(self, u):
        """`(r, ok, status, J)` of the curve at `u`, `J = ∂r/∂stat`, and the prior's residuals and Jacobian."""

        def residuals(stat):
            r, ok, status = observed_residuals(stat, self.scene, self.fitted, self.data)
            return r, (r, ok, status)

        stat = stat_of_u(self.fitted, u)
        J, (r, ok, status) = jax.jacfwd(residuals, has_aux=True)(stat)
        return r, ok, status, J, self.prior_residuals(stat), jax.jacfwd(self.prior_residuals)(stat)


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
        value, grad = jax.value_and_grad(loss)(u0)
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
    fitted, data = misfit.fitted, misfit.data

    def step(_, carry):
        trial, best_u, best = carry
        found = misfit.evaluate(trial)
        r = found[0].reshape(-1)
        loss = misfit.loss_of(r, found[4])
        better = jnp.isfinite(loss) & (loss < best[0])
        best_u = jnp.where(better, trial, best_u)
        best = jax.tree.map(lambda new, old: jnp.where(better, new, old), (loss, *found), best)
        _, r_best, ok_best, _, J_best, r_prior_best, J_prior_best = best
        used = (ok_best & ~jnp.isnan(data.targets)).reshape(-1)
        # ∂stat/∂u, one coordinate at a time (the map is elementwise): J in optimiser coordinates.
        slope = jax.jvp(lambda x: stat_of_u(fitted, x), (best_u,), (jnp.ones_like(best_u),))[1]
        J_curve = jnp.where(used[:, None], J_best.reshape(r.size, -1) / misfit.sigma, 0.0)
        J_u = jnp.concatenate([J_curve, J_prior_best]) * slope[None, :]
        residuals = jnp.concatenate([jnp.where(used, r_best.reshape(-1), 0.0) / misfit.sigma, r_prior_best])
        # The normal equations of a few parameters, nudged off singular (a step that does not lower
        # the loss is not kept).
        JTJ = J_u.T @ J_u
        nudge = 1e-12 * jnp.trace(JTJ) * jnp.eye(JTJ.shape[0], dtype=JTJ.dtype)
        delta = jnp.linalg.solve(JTJ + nudge, -J_u.T @ residuals)
        return best_u + jnp.where(jnp.isfinite(delta), delta, 0.0), best_u, best

    shapes = jax.eval_shape(misfit.evaluate, u)
    empty = (jnp.asarray(jnp.inf, u.dtype), *(jnp.zeros(x.shape, x.dtype) for x in shapes))
    _, u, (loss, r, ok, status, J, _, _) = jax.lax.fori_loop(0, POLISH_STEPS, step, (u, u, empty))
    return u, loss, r, ok, status, J


def program(treedef, fitted, max_iter: int, tol: float, index, kind):
    """(scene leaves, each curve's `Observations` and σ stacked, the prior's arrays or None, starts) ↦
    vmap over curves of (vmap over starts of the solver, the best start polished, its loss, steps,
    residuals, valid mask, statuses and Jacobian; every start's end and loss)."""

    def one_curve(scene, data, sigma, prior, u0s):
        misfit = Misfit(scene, data, sigma, prior, fitted, index, kind)
        us, losses, ks = jax.vmap(solver(misfit, max_iter, tol))(u0s)
        best = jnp.argmin(jnp.where(jnp.isfinite(losses), losses, jnp.inf))
        u, loss, r, ok, status, J = polished(misfit, us[best])
        # Every start's end, the best one polished: where the others ended says whether a distinct
        # optimum fits almost as well (`rival_optima`).
        return u, loss, ks[best], r, ok, status, J, us.at[best].set(u), losses.at[best].set(loss)

    def batch(leaves, data, sigmas, prior, u0s):
        scene = jax.tree_util.tree_unflatten(treedef, leaves)
        return jax.vmap(one_curve, in_axes=(None, 0, 0, None, None))(scene, data, sigmas, prior, u0s)

    return batch
