"""What a contact model is: `AbstractContactModel`, what a point solve returns, and the swept models.

A model is an `eqx.Module` passed in as a choice (`Scene(..., model=Xia2024(interaction=...))`),
as diffrax takes `solver=Tsit5()`. The solve asks it one thing: given the scene's dimensionless
groups, a function from one load `F*` to a `PointResult` (`AbstractContactModel.point_solver`).
A model with a state variable other than the largest spot (the separation of Greenwood–Williamson
or Persson) subclasses `AbstractContactModel` and writes its own `point_solver`; the models of the
Majumdar–Bhushan family subclass `AbstractLargestSpotModel` (`_largest_spot`).
"""

from __future__ import annotations

import abc
import dataclasses
import typing
from collections.abc import Callable
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float, Int

from ..numerics import InputError
from ..numerics._elementwise import unrolled_sum
from ..quantities import DimensionlessScene, Status
from ._spots import Separated, SpotState

# A nominal pressure above E (F* > 1) means strains of order one: beyond the linear elasticity of
# the elastic comparators (GW, Persson), whose loads are flagged out of range there.
LINEAR_ELASTIC_LIMIT = 1.0
# A predicted real contact area of this share of the nominal one or more is a closed interface: no
# finite stiffness is left to measure (every model and the boundary-element reference flag it).
CLOSED_INTERFACE = 0.99


class JointResponse(eqx.Module):
    """Totals of the joint at one state (or a batch of them, `*loads`), dimensionless, split by the
    model's regimes.

    **Fields:** `regime_load` (F* per regime), `regime_stiffness` (K* per regime), `real_area`
    (A_r*), `breakdown` (True where the model is not valid at this load, e.g. the "paper"
    interaction's ω' vanishes inside the range).
    """

    regime_load: Float[Array, "*loads regimes"]
    regime_stiffness: Float[Array, "*loads regimes"]
    real_area: Float[Array, "*loads"]
    breakdown: Bool[Array, "*loads"]


class PointResult(eqx.Module):
    """One load point (or a batch of them, `*loads`), dimensionless: `ln a_l*`, the joint's response
    there, and the status."""

    log_a_l: Float[Array, "*loads"]
    response: JointResponse
    status: Int[Array, "*loads"]

    @property
    def stiffness_star(self):
        """K* where the point is valid, NaN otherwise."""
        K = unrolled_sum(self.response.regime_stiffness)
        return jnp.where(self.status == Status.OK, K, jnp.nan)


def separated_point(state: Separated) -> PointResult:
    """The `PointResult` of a Greenwood–Williamson-type state (one regime; `a_l` NaN: no largest spot)."""
    response = JointResponse(state.load[None], state.stiffness[None], state.area, jnp.array(False))
    return PointResult(jnp.full_like(state.separation, jnp.nan), response, state.status)


class AbstractContactModel(eqx.Module):
    """A statistical model of the joint's normal contact: load ↦ stiffness, real area, status.

    **Class attributes:** `name` (the registry's key, used in scene files and reports),
    `regimes` (names of the slots of `Solution.load_share` and `stiffness_share`), and
    `pad_loads` (True unless set: eager solves and fits pad load arrays to a few lengths, so that
    new lengths do not compile again; a model whose every load is a costly solve, such as the
    boundary-element one, sets it to False), `precision` (the relative precision of K as the model
    computes it, 0 for round-off: fits stop no finer than it), `single_spots` (whether
    `spot_solver` gives the spots one by one; False for Persson and the BEM). A model that solves for each load's
    state holds its root finder as a field (`root_finder`, as diffrax's implicit solvers do).
    """

    name: eqx.AbstractClassVar[str]
    regimes: eqx.AbstractClassVar[tuple[str, ...]]
    pad_loads: ClassVar[bool] = True
    precision: ClassVar[float] = 0.0
    single_spots: ClassVar[bool] = True

    @abc.abstractmethod
    def point_solver(self, s: DimensionlessScene, unloading: bool = False) -> Callable[[Float[Array, ""]], PointResult]:
        """Set up everything that does not depend on the load; returns `F* ↦ PointResult`.

        **Arguments:** `s`, the scene's dimensionless groups (valid parameters: the caller has
        put stand-ins where they are not); `unloading`, whether each result's stiffness is the
        initial unloading tangent at the state its load reaches on loading (`Unloading()`, docs/in-service.md)
        rather than the loading one; a model that `unloads_as_it_loads` returns its loading tangent.
        """

    @abc.abstractmethod
    def kink_log_loads(self, s: DimensionlessScene) -> Float[Array, " kinks"]:
        """`ln F*` where the slope of K(F) jumps (an empty array for a smooth model); integrators
        of K(F) step to them."""

    @abc.abstractmethod
    def unloads_as_it_loads(self) -> bool:
        """Whether every state of the model unloads along its loading curve (an elastic model), so
        that its unloading and tangential stiffnesses follow from its loading solve."""

    @abc.abstractmethod
    def spot_solver(self, s: DimensionlessScene) -> Callable[[Float[Array, ""]], SpotState]:
        """`F* ↦ SpotState`: the state at one load with its spots one by one (for partial slip,
        `jaxcontact.tangential_cycle`). A model without single spots sets `single_spots = False`
        and raises `without_single_spots(self)` here."""

    @typing.final
    def options(self) -> dict[str, str]:
        """The model's choices by name, as scene files and reports spell them: `model`, then every
        field that is a named choice, and the choices inside those (an interaction's quadrature)."""
        return {"model": self.name, **_named_choices(self)}


def _named_choices(module: eqx.Module) -> dict[str, str]:
    choices = {}
    for field in dataclasses.fields(module):
        value = getattr(module, field.name)
        if isinstance(value, eqx.Module) and isinstance(getattr(type(value), "name", None), str):
            choices[field.name] = value.name
            choices.update(_named_choices(value))
    return choices


class PathPoints(eqx.Module):
    """A swept model's contact along a load path, dimensionless (`F* = F/(E A_a)`, lengths in
    `sqrt(A_a)`; leading axis the path's points): `approach_star` relative to the first point,
    `stiffness_star` on the branch travelled, `unloading_star` of a small unload, `real_area_star`
    (A_r/A_a), `status`, and `residual_star`, the approach left after a full unload."""

    approach_star: Float[Array, " points"]
    stiffness_star: Float[Array, " points"]
    unloading_star: Float[Array, " points"]
    real_area_star: Float[Array, " points"]
    status: Int[Array, " points"]
    residual_star: Float[Array, ""]


class AbstractPathModel(AbstractContactModel):
    """A model that remembers the load path (`jaxcontact.solve_path`): a capped surface's plastic
    flattening (the boundary-element model), each summit's deepest interference
    (`MeasuredAsperities`)."""

    @abc.abstractmethod
    def path_solver(self, s: DimensionlessScene) -> Callable[[Float[Array, " points"]], PathPoints]:
        """`F*` along a load path (1-D, in the order applied) ↦ its `PathPoints`, with the model's
        memory of the path."""


class AbstractSweptModel(AbstractPathModel):
    """A model whose loads are cheaper solved together, in one sweep, each from the last one's
    solution (the boundary-element contact): it writes `sweep_solver`; `point_solver` is a sweep
    of one load."""

    @abc.abstractmethod
    def sweep_solver(self, s: DimensionlessScene) -> Callable[[Float[Array, " loads"]], PointResult]:
        """`F*` (1-D) ↦ the `PointResult`s of all loads (a leading loads axis)."""

    @typing.final
    def loads_solver(self, s: DimensionlessScene, unloading: bool = False):
        """`F*` (1-D) ↦ the `PointResult`s of all loads: the sweep, or with `unloading` (for a model
        that does not unload as it loads) the initial unloading tangents (`unloading_solver`)."""
        return self.unloading_solver(s) if unloading and not self.unloads_as_it_loads() else self.sweep_solver(s)

    @typing.final
    def point_solver(self, s, unloading: bool = False):
        sweep = self.loads_solver(s, unloading)
        return lambda F_star: jax.tree.map(lambda x: x[0], sweep(F_star[None]))

    @typing.final
    def unloading_solver(self, s: DimensionlessScene) -> Callable[[Float[Array, " loads"]], PointResult]:
        """`F*` (1-D) ↦ the `PointResult`s whose stiffness is the initial unloading tangent at each
        load reached by loading: the path of the loads in increasing order (`path_solver`), so that
        each state keeps what loading to it left (a capped surface's flattening), read back in the
        order given."""
        follow = self.path_solver(s)

        def curve(F_star):
            order = jnp.argsort(F_star)
            path = follow(F_star[order])
            given = lambda x: x[jnp.argsort(order)]  # noqa: E731
            response = JointResponse(
                F_star[:, None],
                given(path.unloading_star)[:, None],
                given(path.real_area_star),
                jnp.zeros(F_star.shape, bool),
            )
            return PointResult(jnp.full_like(F_star, jnp.nan), response, given(path.status))

        return curve


def without_single_spots(model: AbstractContactModel) -> InputError:
    """The error of asking a model that resolves no single spots for them (partial slip)."""
    return InputError(
        f"model = {model.name!r} resolves no single spots: partial slip (tangential_cycle) needs a model that "
        "does (xia2024, jzz2010, gw, measured-asperities)"
    )
