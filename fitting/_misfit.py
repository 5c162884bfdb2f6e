"""One curve's misfit as a JAX function: its weighted residuals over the noise σ, and a prior's where
there is one; the loss, its gradient and the Gauss–Newton linearisation from one forward-mode
evaluation. The batch fit (`_batch_program`) and the posterior's log density (`_posterior`) are built
on it."""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp

from ._parameters import stat_of_u
from ._prior import traced_residuals
from ._residuals import Observations, linearised_residuals


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
        """½ mean square of the misfit at `u`, its gradient `J_uᵀ r / n` from the forward-mode
        Jacobian over the few parameters (`evaluate`): every place the optimiser asks for the loss and
        its gradient then runs one evaluation, the one the Gauss–Newton steps run, and the program
        holds no reverse-mode copy of the model."""

        @jax.custom_vjp
        def value(u):
            return self.value_and_grad(u)[0]

        def backward(grad, cotangent):
            return (cotangent * grad,)

        value.defvjp(self.value_and_grad, backward)
        return value(u)

    def value_and_grad(self, u):
        found = self.evaluate(u)
        residuals, J_u = self.linearised(u, found)
        return self.loss_of(found[0].reshape(-1), found[4]), J_u.T @ residuals / found[0].size

    def evaluate(self, u):
        """`(r, ok, status, J)` of the curve at `u`, `J = ∂r/∂stat`, and the prior's residuals and Jacobian."""

        stat = stat_of_u(self.fitted, u)
        found = linearised_residuals(stat, self.scene, self.fitted, self.data)
        return *found, self.prior_residuals(stat), jax.jacfwd(self.prior_residuals)(stat)

    def linearised(self, u, found):
        """The misfit's residual vector at `u` (the curve's over σ, 0 where a point is flagged or not
        measured, then the prior's) and its Jacobian in optimiser coordinates, from `evaluate(u)`."""
        r, ok, _, J, r_prior, J_prior = found
        used = (ok & ~jnp.isnan(self.data.targets)).reshape(-1)
        # ∂stat/∂u, one coordinate at a time (the map is elementwise).
        slope = jax.jvp(lambda x: stat_of_u(self.fitted, x), (u,), (jnp.ones_like(u),))[1]
        J_curve = jnp.where(used[:, None], J.reshape(used.size, -1) / self.sigma, 0.0)
        residuals = jnp.concatenate([jnp.where(used, r.reshape(-1), 0.0) / self.sigma, r_prior])
        return residuals, jnp.concatenate([J_curve, J_prior]) * slope[None, :]
