"""The total load `F_t(a_l)` (Eq. 35) piece by piece, between the kinks where `a_l` crosses a regime boundary.

The load-controlled solve (Sec. 4) inverts `F_t(a_l) = F`. `F_t` is continuous and increasing,
but its slope jumps wherever `a_l` crosses a regime boundary (the Kogut–Etsion load laws do not
join smoothly at `a_c`, `a_epc`, `a_pc`), and Newton's method converges slowly across a kink.
Between two kinks it is smooth, so the solve first finds the piece that holds the load (from
`F_t` at the kinks, once per scene), then runs Newton's method on that piece alone. For the
"xia2024" joint each piece also has a cheap closed form: every regime below the piece is
complete, so its load is a constant times `a_l^(D/2)` and only the regime that `a_l` is in
needs an integral.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float, Int

from ..numerics import PowerLaw, exponential_integral
from ..numerics._elementwise import pick


class AbstractLoadPieces(eqx.Module):
    """`ln F_t*` as a function of `ln a_l*` on each smooth piece of `[ln a_min*, 0]`.

    **Fields:** `knots`, the piece ends in `ln a_l*` (increasing; the first is `ln a_min*`, the
    last 0, the nominal area; a piece may be empty); `knot_log_loads`, `ln F_t*` there.
    """

    knots: eqx.AbstractVar[Float[Array, "pieces_plus_1"]]
    knot_log_loads: eqx.AbstractVar[Float[Array, "pieces_plus_1"]]

    @abc.abstractmethod
    def log_load(self, log_a_l, piece) -> Float[Array, ""]:
        """`ln F_t*(a_l)`, valid for `knots[piece] ≤ ln a_l ≤ knots[piece + 1]`."""

    @abc.abstractmethod
    def log_load_slope(self, log_a_l, piece) -> Float[Array, ""]:
        """`d ln F_t* / d ln a_l*` on the piece."""

    def locate(self, log_load) -> tuple[Int[ArrayLike, ""], Float[Array, ""], Float[Array, ""], Float[Array, ""]]:
        """The piece that holds the load `ln F*`, its ends, and a first guess of `ln a_l*` on it.

        The guess interpolates `ln a_l` linearly in `ln F` between the piece's ends (`F_t` is
        close to a power law on each piece). On the first piece `F_t(a_min) = 0`, and the guess
        is its upper end. Loads outside `(F_t(a_min), F_t(A_a)]` land on the first or last piece;
        the caller flags them.
        """
        g = self.knot_log_loads
        count = len(g) - 1
        piece = sum((g[k] < log_load).astype(jnp.int32) for k in range(1, count))
        lower, upper = pick(self.knots[:-1], piece), pick(self.knots[1:], piece)
        g_lower, g_upper = pick(g[:-1], piece), pick(g[1:], piece)
        # With g_lower = -inf this is exactly `upper`.
        guess = upper - (g_upper - log_load) * (upper - lower) / (g_upper - g_lower)
        return piece, lower, upper, jnp.clip(guess, lower, upper)


class GenericLoadPieces(AbstractLoadPieces):
    """Pieces of any joint, each evaluated through the joint's full `total_load`."""

    knots: Float[Array, "pieces_plus_1"]
    knot_log_loads: Float[Array, "pieces_plus_1"]
    joint: eqx.Module

    @classmethod
    def of(cls, joint) -> GenericLoadPieces:
        """The pieces of `joint` (an `AbstractJoint`) between its knots."""
        knots = joint.knots()
        return cls(knots, jnp.log(jax.vmap(joint.total_load)(knots)), joint)

    def log_load(self, log_a_l, piece):
        del piece
        return jnp.log(self.joint.total_load(log_a_l))

    def log_load_slope(self, log_a_l, piece):
        """By forward-mode differentiation of `log_load`."""
        return jax.jvp(lambda x: self.log_load(x, piece), (log_a_l,), (jnp.ones_like(log_a_l),))[1]


class PowerLawLoadPieces(AbstractLoadPieces):
    """Pieces of a joint whose load is `a_l^(D/2) Σ_regimes ∫ f(a) a^(-(D+2)/2) da` with power laws `f`.

    On piece `j` (`a_l` in regime `j`) the regimes below are complete: `F_t = a_l^(D/2) (C_j +
    ∫_{knot_j}^{a_l} law_j)`, with `C_j` their constant total.

    **Fields:** `knots`, `knot_log_loads` (as above); `density_exponent` = D/2; `laws`, the
    regimes' `f(a) · n(a) / a_l^(D/2)` (shape 4); `completed`, `C_j` (shape 4).
    """

    knots: Float[Array, "5"]
    knot_log_loads: Float[Array, "5"]
    density_exponent: Float[Array, ""]
    laws: PowerLaw
    completed: Float[Array, "4"]

    @classmethod
    def build(cls, knots, density_exponent, laws: PowerLaw) -> PowerLawLoadPieces:
        """From the knots (the regime edges clipped to `[ln a_min*, 0]`) and the per-regime laws."""
        full = laws.integral(knots[:-1], knots[1:])
        totals = [jnp.zeros_like(full[0])]
        for piece_load in full:  # a running sum of 4 (cumsum would be its own small kernel)
            totals.append(totals[-1] + piece_load)
        totals = jnp.stack(totals)
        knot_log_loads = density_exponent * knots + jnp.log(totals)
        return cls(knots, knot_log_loads, density_exponent, laws, totals[:-1])

    def _piece_law(self, piece):
        """The piece's regime law in `t = ln a` (coefficient and rate), its start, and `C_j`."""
        return (
            pick(self.laws.log_coeff, piece),
            pick(self.laws.exponent, piece) + 1.0,
            pick(self.knots[:-1], piece),
            pick(self.completed, piece),
        )

    def log_load(self, log_a_l, piece):
        log_coeff, rate, start, completed = self._piece_law(piece)
        return self.density_exponent * log_a_l + jnp.log(
            completed + exponential_integral(log_coeff, rate, start, log_a_l)
        )

    def log_load_slope(self, log_a_l, piece):
        """`D/2 + f(a_l) n(a_l) a_l / (C_j + ∫ f n da)`: the integral's derivative is its integrand."""
        log_coeff, rate, start, completed = self._piece_law(piece)
        total = completed + exponential_integral(log_coeff, rate, start, log_a_l)
        return self.density_exponent + jnp.exp(log_coeff + rate * log_a_l) / total
