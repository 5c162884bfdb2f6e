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
        """The misfit's residual vector at `u` (the curve's over σ, a flagged point's constant and an
        unmeasured entry's 0 included, then the prior's) and its Jacobian in optimiser coordinates, from
        `evaluate(u)`."""
        r, ok, _, J, r_prior, J_prior = found
        # A flagged point's residual is a constant; its row of J is 0 (whatever the model's derivative there).
        used = (ok & ~jnp.isnan(self.data.targets)).reshape(-1)
        # ∂stat/∂u, one coordinate at a time (the map is elementwise).
        slope = jax.jvp(lambda x: stat_of_u(self.fitted, x), (u,), (jnp.ones_like(u),))[1]
        J_curve = jnp.where(used[:, None], J.reshape(used.size, -1) / self.sigma, 0.0)
        residuals = jnp.concatenate([r.reshape(-1) / self.sigma, r_prior])
        return residuals, jnp.concatenate([J_curve, J_prior]) * slope[None, :]

    def least_squares(self, u):
        """`(residuals, found)`: the residual vector of `linearised` at `u`, differentiable by the
        Jacobian that `evaluate` computed alongside it (a least-squares solver's linearisation then
        evaluates the model once, forward mode over the few parameters), and `evaluate(u)`."""

        @jax.custom_jvp
        def vector(u):
            found = self.evaluate(u)
            return self.linearised(u, found)[0], found

        @vector.defjvp
        def jvp(primals, tangents):
            (u,), (du,) = primals, tangents
            found = self.evaluate(u)
            residuals, J_u = self.linearised(u, found)
            return (residuals, found), (J_u @ du, jax.tree.map(_zero_tangent, found))

        return vector(u)

    def remaining_gain(self, u, found):
        """The χ² that the Gauss–Newton step from `u` would gain, in units of the curve's own
        `s² = Σr²/(N − p)` (from `evaluate(u)`)."""
        residuals, J_u = self.linearised(u, found)
        g = J_u.T @ residuals
        JTJ = J_u.T @ J_u
        nudge = 1e-12 * jnp.trace(JTJ) * jnp.eye(JTJ.shape[0], dtype=JTJ.dtype)
        gain = g @ jnp.linalg.solve(JTJ + nudge, g)
        n = jnp.sum(~jnp.isnan(self.data.targets)) + found[4].size - u.size
        s2 = (residuals @ residuals) / jnp.maximum(n, 1).astype(residuals.dtype)
        return gain / jnp.maximum(s2, jnp.finfo(s2.dtype).tiny)


def _zero_tangent(x):
    if jnp.issubdtype(x.dtype, jnp.inexact):
        return jnp.zeros_like(x)
    return jnp.zeros(x.shape, jax.dtypes.float0)
