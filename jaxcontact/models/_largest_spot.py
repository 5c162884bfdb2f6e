"""The load-controlled solve shared by every model with a largest spot (docs/model.md §4).

Models of the Majumdar–Bhushan family describe the joint by its largest contact spot `a_l`;
they subclass `AbstractLargestSpotModel`, say how to build their `AbstractJoint` (the load,
stiffness and area integrals as functions of `ln a_l*`), and inherit the a_l solve, written once
here.
"""

from __future__ import annotations

import abc
import typing
from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from ..numerics import NewtonBisection
from ..numerics._elementwise import unrolled_sum
from ..quantities import DimensionlessScene, Status
from ._base import AbstractContactModel, AbstractSweptModel, JointResponse, PointResult
from ._load_pieces import AbstractLoadPieces
from ._spots import SpotFamilies, SpotState


def curve_solver(
    model: AbstractContactModel, s: DimensionlessScene, unloading: bool = False
) -> Callable[[Float[Array, " loads"]], PointResult]:
    """`F*` (1-D) ↦ the `PointResult`s of all loads: a swept model's sweep, else `point_solver`
    mapped over the loads (`jax.vmap`). With `unloading`, each result's stiffness is the initial
    unloading tangent from the state its load reaches on loading."""
    if isinstance(model, AbstractSweptModel):
        return model.loads_solver(s, unloading)
    return jax.vmap(model.point_solver(s, unloading=unloading))


class AbstractJoint(eqx.Module):
    """A load–area–stiffness model of the whole joint as a function of `ln a_l*`."""

    log_a_min: eqx.AbstractVar[Float[Array, ""]]

    @abc.abstractmethod
    def regime_load(self, log_a_l) -> Float[Array, " regimes"]:
        """Dimensionless load carried in each regime."""

    def total_load(self, log_a_l):
        """`F_t*(a_l)`, Eq. (35); increasing in `a_l`."""
        return unrolled_sum(self.regime_load(log_a_l))

    @abc.abstractmethod
    def kinks(self) -> Float[Array, " kinks"]:
        """`ln a_l*` where the slope of `F_t` jumps (a regime boundary), increasing."""

    def knots(self) -> Float[Array, " knots"]:
        """Ends of the smooth pieces of `F_t` in `ln a_l*`: `ln a_min*`, the kinks (clipped), 0."""
        return jnp.concatenate(
            [self.log_a_min[None], jnp.clip(self.kinks(), self.log_a_min, 0.0), jnp.zeros_like(self.log_a_min)[None]]
        )

    @abc.abstractmethod
    def load_pieces(self) -> AbstractLoadPieces:
        """`F_t` piece by piece between its kinks, for the load-controlled solve: for any joint
        `GenericLoadPieces.of(self)`; a joint with closed-form pieces can do better."""

    @abc.abstractmethod
    def response(self, log_a_l, log_load) -> JointResponse:
        """Everything at the solved `a_l`; `log_load = ln F*` sets the nominal pressure."""

    @abc.abstractmethod
    def unloading_stiffness(self, log_a_l, log_load) -> tuple[Float[Array, " regimes"], Bool[Array, ""]]:
        """Each regime's initial unloading stiffness from the solved `a_l` (every spot unloads
        elastically, one that flowed with the elastic stiffness of its contact area at the top), and
        the breakdown flag."""

    @abc.abstractmethod
    def spots(self, log_a_l, log_load) -> SpotFamilies:
        """The spots at the solved `a_l`, one family per regime, each spot with its load and its
        initial unloading stiffness (`unloading_stiffness` is their sum): for partial slip."""


def _piece_residual(log_a_l, args):
    pieces, piece, log_load = args
    return pieces.log_load(log_a_l, piece) - log_load, None


def _piece_residual_slope(log_a_l, args):
    pieces, piece, _ = args
    return pieces.log_load_slope(log_a_l, piece)


class AbstractLargestSpotModel(AbstractContactModel):
    """A model whose state is the largest contact spot `a_l` (docs/model.md §4): load control solves
    `F_t(a_l) = F` for it.

    Subclasses say how to build their joint (`joint`) and hold the root finder of the solve
    (`root_finder`, a `NewtonBisection`); the solve is this class's.
    """

    root_finder: eqx.AbstractVar[NewtonBisection]

    @abc.abstractmethod
    def joint(self, s: DimensionlessScene) -> AbstractJoint:
        """The dimensionless joint of this model for the scene's groups `s`."""

    @typing.final
    def kink_log_loads(self, s):
        """Where `a_l` crosses a regime boundary: the loads at the kinks of `F_t` (`AbstractJoint.kinks`)."""
        return self.joint(s).load_pieces().knot_log_loads[1:-1]

    @typing.final
    def unloads_as_it_loads(self) -> bool:
        return False

    @typing.final
    def spot_solver(self, s):
        """The a_l solve with the unloading stiffness of its state (`point_solver(s, unloading=True)`),
        and there the joint's spots (`AbstractJoint.spots`)."""
        joint, solve = self.joint(s), self.point_solver(s, unloading=True)

        def one(F_star) -> SpotState:
            point = solve(F_star)
            log_load = jnp.log(jnp.where(F_star > 0, F_star, 1.0))
            spots = joint.spots(point.log_a_l, log_load)
            unloading = unrolled_sum(point.response.regime_stiffness)
            return SpotState(point.status, spots, unloading, point.response.breakdown)

        return one

    @typing.final
    def point_solver(self, s, unloading: bool = False):
        """The a_l solve in `ln a_l*` on `[ln a_min*, 0]` (docs/model.md §4); with `unloading`, the
        response's stiffness is the joint's initial unloading stiffness there (`unloading_stiffness`).

        `F_t` at the kinks (once per scene) tells which smooth piece of `F_t` holds each load
        (`load_pieces`); Newton's method then runs on that piece alone, from the piece's log-log
        interpolant and with its closed-form slope (`rootfind`), and the root is differentiated
        by the implicit function theorem, `da_l/dθ = -(∂F_t/∂θ)/(∂F_t/∂a_l)`. A point that
        cannot be computed is solved at a harmless stand-in load and given a non-zero status.
        """
        joint = self.joint(s)
        pieces = joint.load_pieces()
        log_load_lowest = pieces.knot_log_loads[0]  # -inf where any F > 0 is reachable
        log_load_highest = pieces.knot_log_loads[-1]
        # Failed points are solved at a harmless stand-in: the load that puts a_l midway (in logs).
        log_load_middle = jnp.log(joint.total_load(0.5 * joint.log_a_min))
        joint_valid = jnp.isfinite(log_load_highest) & jnp.isfinite(log_load_middle)
        # Where F_t(a_min) = 0, loads near it put a_l a hair above a_min and the totals are
        # proportional to ln(a_l/a_min), which round-off in ln a_l (a few ulps of |ln a_min|)
        # cannot resolve below this: such points are flagged, not returned as numbers.
        eps = float(jnp.finfo(jnp.result_type(joint.log_a_min)).eps)
        target = max(1e-8, 1e3 * eps)  # relative accuracy asked of K: 1e-8 in float64, 1e-4 in float32
        smallest_resolved = 4.0 * eps * jnp.abs(joint.log_a_min) / target
        starts_at_zero = ~jnp.isfinite(log_load_lowest)

        def one_point(F_star) -> PointResult:
            valid = jnp.isfinite(F_star) & (F_star > 0)
            log_load = jnp.log(jnp.where(valid, F_star, 1.0))
            in_range = (log_load > log_load_lowest) & (log_load <= log_load_highest)
            usable = valid & in_range
            log_load = jnp.where(usable, log_load, log_load_middle)
            piece, lower, upper, guess = pieces.locate(log_load)
            log_a_l, converged = self.root_finder.find(
                _piece_residual, guess, (pieces, piece, log_load), lower, upper, slope=_piece_residual_slope
            )
            response = joint.response(log_a_l, log_load)
            if unloading:
                stiffness, breakdown = joint.unloading_stiffness(log_a_l, log_load)
                breakdown = breakdown | response.breakdown  # the state is the loading one
                response = JointResponse(response.regime_load, stiffness, response.real_area, breakdown)
            unresolved = starts_at_zero & (log_a_l - joint.log_a_min < smallest_resolved)
            status = jnp.select(
                [~joint_valid, ~valid, ~in_range, ~converged, unresolved, response.breakdown],
                [
                    Status.INVALID_PARAMETERS,
                    Status.INVALID_LOAD,
                    Status.LOAD_OUT_OF_RANGE,
                    Status.NOT_CONVERGED,
                    Status.UNRESOLVED_LOAD,
                    Status.INTERACTION_BREAKDOWN,
                ],
                Status.OK,
            ).astype(jnp.int32)
            return PointResult(log_a_l, response, status)

        return one_point
