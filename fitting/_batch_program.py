"""The compiled program of `fit_batch`: per curve and start, optimistix's Levenberg–Marquardt on the
curve's misfit (its weighted residuals over the noise σ, and a prior's residuals where there is one),
the best start's residuals and Jacobian at its end for the statistics."""

from __future__ import annotations

import jax
import jax.numpy as jnp

from ._misfit import Misfit

# χ² (in units of the curve's own s²) that the Gauss–Newton step from a start's end would still gain,
# below which a start that used up its steps has converged all the same: the loss is then flat to
# round-off over the remaining step, where the trust region's test of each step is decided by round-off.
SETTLED = 1e-6


def solver(misfit: Misfit, max_iter: int, tol: float):
    """One curve's fit from one start `u0`: optimistix's Levenberg–Marquardt on the misfit's residual
    vector, until an accepted step changes the parameters (optimiser coordinates) and the residuals by
    less than `tol`, relative and absolute (optimistix's Cauchy test), or `max_iter` steps. Each step
    evaluates the model once (`Misfit.least_squares`)."""
    import lineax as lx
    import optimistix as optx

    method = optx.LevenbergMarquardt(rtol=tol, atol=tol, linear_solver=lx.QR())

    def run(u0):
        solution = optx.least_squares(
            lambda u, _: misfit.least_squares(u), method, u0, has_aux=True, max_steps=max_iter, throw=False
        )
        found = solution.aux
        done = solution.result == optx.RESULTS.successful
        converged = done | (misfit.remaining_gain(solution.value, found) < SETTLED)
        loss = misfit.loss_of(found[0].reshape(-1), found[4])
        return solution.value, loss, solution.stats["num_steps"], converged, found

    return run


def fit_curves(scene, data, sigmas, prior, u0s, fitted, max_iter: int, tol: float, index, kind):
    """Each curve (`data`, each one's `Observations` stacked, and its σ in `sigmas`; the prior's arrays or
    None) fitted from every start `u0s`: vmap over curves of (vmap over starts of the solver; the best
    start's end, loss, steps, whether it converged, residuals, valid mask, statuses and Jacobian; every
    start's end and loss)."""

    def one_curve(data, sigma):
        misfit = Misfit(scene, data, sigma, prior, fitted, index, kind)
        us, losses, ks, converged, found = jax.vmap(solver(misfit, max_iter, tol))(u0s)
        best = jnp.argmin(jnp.where(jnp.isfinite(losses), losses, jnp.inf))
        r, ok, status, J = (x[best] for x in found[:4])
        # Every start's end: where the others ended says whether a distinct optimum fits almost as well
        # (`rival_optima`).
        return us[best], losses[best], ks[best], converged[best], r, ok, status, J, us, losses

    return jax.vmap(one_curve)(data, sigmas)
