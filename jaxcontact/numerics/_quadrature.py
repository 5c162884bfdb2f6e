"""Quadrature in log-area, and the quadrature choices a model takes as objects.

Only the interaction stiffness needs it (every other integral of the model has a closed
form). Integrands span many decades of `a`, so the variable is `t = ln a`, in which they are
smooth and slowly varying.
"""

from __future__ import annotations

import abc
import typing
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ._caches import cached
from ._compat import standard_promotion
from ._pole_integral import PoleIntegral
from ._validate import InputError


@cached
def gauss_legendre(nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights on [-1, 1] (numpy's `leggauss`, computed once per node count)."""
    return np.polynomial.legendre.leggauss(nodes)


def integrate_log_area(integrand, log_lower, log_upper, nodes: int):
    """`∫ g(t) dt` over `[log_lower, log_upper]` (elementwise over the bounds' shape).

    **Arguments:**

    - `integrand`: `g(t)`, the integrand with respect to `t = ln a` (that is, `a · h(a)` for
      `∫ h(a) da`); called with `t` of shape `bounds.shape + (nodes,)`, it returns the same shape.
    - `log_lower`, `log_upper`: bounds, of equal shape; an empty interval gives 0.
    - `nodes`: number of Gauss–Legendre nodes per interval (static).
    """
    x, w = gauss_legendre(nodes)
    half = 0.5 * (log_upper - log_lower)[..., None]
    mid = 0.5 * (log_upper + log_lower)[..., None]
    t = mid + half * jnp.asarray(x, dtype=half.dtype)
    return jnp.sum(jnp.asarray(w, dtype=half.dtype) * integrand(t), axis=-1) * half[..., 0]


class AbstractQuadrature(eqx.Module):
    """How the interaction part of the stiffness (the one integral without a closed form) is done.

    Every quadrature does the pole integral of the "paper" interaction (`pole_integrals`); the row
    quadratures (`AbstractRowQuadrature`) also do any smooth integrand (`integrate_rows`).
    """

    name: eqx.AbstractClassVar[str]
    # Whether the closed forms beside this quadrature's pole integrals (`paper_correction`) are one
    # array over the regimes (True) or a chain of scalar operations per regime (False, None).
    regimes_together: eqx.AbstractVar[bool | None]

    @abc.abstractmethod
    def pole_integrals(
        self, power: Float[Array, " rows"], log_coeff, log_u_lower, log_u_upper
    ) -> list[Float[Array, ""]]:
        """`e^log_coeff ∫ u^power / (1 - u) du` from `u_lower` to `u_upper` (`u < 1`, `power ≥ 2`),
        one scalar per row (laid out as `regimes_together` says: `PowerSeries`)."""


# A solve of at most this many loads takes `PowerSeries(regimes_together=None)` as True (`for_loads`).
TOGETHER_UP_TO = 128


class PowerSeries(AbstractQuadrature):
    """No nodes: the pole integral summed to round-off (`pole_integral`). The "paper" interaction's
    default; it does no other integral, so the "series" interaction cannot take it.

    **Arguments:** `regimes_together` (static), how the regimes are laid out in the program, for the
    same numbers:

    - `False`: each regime (and each end of its interval) is its own chain of scalar operations.
      Under `vmap` a vector of regimes becomes a short minor axis, and XLA on CPU does not
      vectorise a loop whose lanes read different coefficients (the series' 21 Horner steps): row
      by row, 65,536 loads run about 6x faster.
    - `True`: the regimes and both ends in one array. The program is much smaller: the fit's
      residual-and-Jacobian program compiles in about 60 % of the time.
    - `None` (default): `True` for a solve of at most `TOGETHER_UP_TO` = 128 loads, where the
      compilation is the cost (a fit's program, an eager call), `False` above and in the
      per-point solvers.
    """

    name: ClassVar[str] = "power-series"
    regimes_together: bool | None = eqx.field(static=True, default=None)

    def pole_integrals(self, power, log_coeff, log_u_lower, log_u_upper):
        poles = PoleIntegral.build(power)
        if self.regimes_together:
            both = jnp.stack([log_u_upper, log_u_lower])
            ends = poles(both, jnp.broadcast_to(log_coeff, both.shape))
            values = ends[0] - ends[1]
            return [values[i] for i in range(power.shape[0])]
        return [
            poles[i](log_u_upper[i], log_coeff[i]) - poles[i](log_u_lower[i], log_coeff[i])
            for i in range(power.shape[0])
        ]


def for_loads(tree, loads: int):
    """`tree` with each `PowerSeries(regimes_together=None)` in it laid out for a solve of `loads`
    loads (`PowerSeries`)."""

    def resolved(x):
        if isinstance(x, PowerSeries) and x.regimes_together is None:
            return PowerSeries(regimes_together=loads <= TOGETHER_UP_TO)
        return x

    return jax.tree_util.tree_map(resolved, tree, is_leaf=lambda x: isinstance(x, PowerSeries))


class AbstractRowQuadrature(AbstractQuadrature):
    """A quadrature rule for any smooth integrand, applied row by row (one row per regime)."""

    regimes_together: ClassVar[bool] = False

    @abc.abstractmethod
    def integrate_rows(self, integrand, row_args, log_lower, log_upper):
        """`∫ integrand(t, *row_args[i]) dt` over `[log_lower[i], log_upper[i]]`, one result per row.

        **Arguments:**

        - `integrand`: elementwise in `t` and in the row arguments (it broadcasts).
        - `row_args`: tuple of arrays with one entry per row (the regime's coefficients).
        - `log_lower`, `log_upper`: the rows' bounds; an empty interval gives 0.
        """

    @typing.final
    def pole_integrals(self, power, log_coeff, log_u_lower, log_u_upper):
        """By this rule in `w = -ln(1 - u)`, where the integral is `∫ e^log_coeff u^power dw`: bounded
        and smooth, over an interval that grows only like `-ln(1 - u_max)` as the pole approaches.
        The power series does the same integral exactly; this is its cross-check and the accuracy
        study's quadrature knob."""
        # u < 1 inside every interval the caller keeps; an empty one may lie past the pole (a_min
        # beyond breakdown), and is clamped there so that its zero length still gives exactly 0.
        below_pole = -float(jnp.finfo(log_u_lower.dtype).eps)
        tiny = float(jnp.finfo(log_u_lower.dtype).tiny)

        def integrand(w, log_coeff, power):
            # u^power with u = 1 - e^(-w). u = 0 only on an empty interval (w = 0), where the floor
            # gives tiny^power = 0 without a branch (power ≥ 2): a `where` here would stop XLA
            # from vectorising the loop.
            u = jnp.maximum(-jnp.expm1(-w), tiny)
            return jnp.exp(log_coeff + power * jnp.log(u))

        w_lower = -jnp.log1p(-jnp.exp(jnp.minimum(log_u_lower, below_pole)))
        w_upper = -jnp.log1p(-jnp.exp(jnp.minimum(log_u_upper, below_pole)))
        # All rows in one call: the integrand has no Horner loop to vectorise row by row, and an
        # adaptive rule's loop is then traced and compiled once, not once per regime.
        values = self.integrate_rows(integrand, (log_coeff, power), w_lower, w_upper)
        return [values[i] for i in range(power.shape[0])]


class GaussLegendre(AbstractRowQuadrature):
    """`nodes` fixed Gauss–Legendre nodes per regime (static, 2 to 1024)."""

    name: ClassVar[str] = "gauss-legendre"
    nodes: int = eqx.field(static=True, default=16)

    def __check_init__(self):
        if isinstance(self.nodes, bool) or not isinstance(self.nodes, int) or not 2 <= self.nodes <= 1024:
            raise InputError(f"GaussLegendre: nodes = {self.nodes!r} must be an integer in [2, 1024]")

    def integrate_rows(self, integrand, row_args, log_lower, log_upper):
        expanded = tuple(a[..., None] for a in row_args)
        return integrate_log_area(lambda t: integrand(t, *expanded), log_lower, log_upper, self.nodes)


class Adaptive(AbstractRowQuadrature):
    """quadax's adaptive Gauss–Kronrod (`quadgk`) to relative `tolerance` (static, in (0, 0.1))."""

    name: ClassVar[str] = "adaptive"
    tolerance: float = eqx.field(static=True, default=1e-10)

    def __check_init__(self):
        if not 0.0 < self.tolerance < 1e-1:
            raise InputError(f"quadrature_tolerance = {self.tolerance!r} must be in (0, 0.1)")

    def integrate_rows(self, integrand, row_args, log_lower, log_upper):
        import quadax  # only where an adaptive quadrature is traced: not a cost of `import jaxcontact`

        nonempty = log_upper > log_lower
        upper = jnp.where(nonempty, log_upper, log_lower + 1.0)  # quadgk wants a proper interval

        def one_row(lo, hi, *args):
            value, _ = quadax.quadgk(
                integrand, jnp.stack([lo, hi]), args=args, epsabs=0.0, epsrel=self.tolerance, max_ninter=100
            )
            return value

        with standard_promotion():
            rows = jnp.vectorize(one_row)(log_lower, upper, *row_args)
        return jnp.where(nonempty, rows, 0.0)
