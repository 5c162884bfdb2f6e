"""Per-point status codes of `Solution.status` (0 means the point is valid)."""

from __future__ import annotations

import enum

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float, Int


class Status(enum.IntEnum):
    """Why a load point has no valid result.

    - `OK`: valid.
    - `LOAD_OUT_OF_RANGE`: the load needs a largest spot beyond the nominal area (a_l > A_a), or
      (model "jzz2010") below the smallest fractal asperity (a_l < l_min²); for "gw" and "persson",
      a nominal pressure above E (F* > 1) or a closed interface; for the BEM reference, a contact
      fraction of 99 % or more.
    - `INTERACTION_BREAKDOWN`: interaction "paper", and ω'(a) = ξ' - σ' vanishes inside the
      stiffness range (docs/model.md §3): the model is not valid there. `a_l` and the load split are
      still reported; the stiffness is NaN.
    - `NOT_CONVERGED`: the a_l solve ran out of steps (the model's `root_finder=NewtonBisection(max_steps=...)`),
      or the boundary-element iteration out of its `max_iterations`.
    - `INVALID_LOAD`: the load is not a positive finite number (only possible for traced loads;
      concrete ones raise `ValueError`).
    - `INVALID_PARAMETERS`: a traced scene parameter lies outside its valid range (e.g. an
      optimiser stepped to D = 2); concrete ones raise `ValueError` when the scene is built.
    - `UNRESOLVED_LOAD`: the load is so small that its largest spot lies within round-off of the
      smallest asperity a_min = l_min² (ln(a_l/a_min) below ~1e5 ulps of ln a_min in the working
      precision), so the stiffness, which is proportional to that difference there, cannot be
      computed to 1e-8 (float64) or 1e-4 (float32). Use float64, or larger loads.
    """

    OK = 0
    LOAD_OUT_OF_RANGE = 1
    INTERACTION_BREAKDOWN = 2
    NOT_CONVERGED = 3
    INVALID_LOAD = 4
    INVALID_PARAMETERS = 5
    UNRESOLVED_LOAD = 6

    @property
    def message(self) -> str:
        """What the code means, in a sentence (the messages of `solve(..., throw=True)`)."""
        return _MESSAGES[self]


_MESSAGES = {
    Status.OK: "the point is valid",
    Status.LOAD_OUT_OF_RANGE: "the load is outside the model's range (a largest spot beyond the nominal area or "
    "below the smallest asperity, a nominal pressure above E, or a closed interface)",
    Status.INTERACTION_BREAKDOWN: "the 'paper' interaction breaks down: ω' vanishes inside the stiffness range",
    Status.NOT_CONVERGED: "the solve ran out of steps (NewtonBisection's max_steps, or the BEM's max_iterations)",
    Status.INVALID_LOAD: "the load is not a positive finite number",
    Status.INVALID_PARAMETERS: "a scene parameter lies outside its valid range",
    Status.UNRESOLVED_LOAD: "the load is too small to resolve in this precision (use float64, or larger loads)",
}


class StatusError(RuntimeError):
    """A point of `solve(..., throw=True)` has no valid result; the message names its status."""


def status_message(code: int | np.integer | Int[ArrayLike, ""]) -> str:
    """A short name for a status code, e.g. for tables: "ok", "interaction_breakdown", ..."""
    try:
        return Status(int(code)).name.lower()
    except ValueError:
        return f"unknown_status_{int(code)}"


class Branch(enum.IntEnum):
    """Which branch of a load path a point lies on (`solve_path`, `bem.solve_path`): reached by
    loading beyond every earlier load (`LOADING`, where plastic flow can occur), by unloading
    (`UNLOADING`), or by loading again up to the largest earlier load (`RELOADING`); the last two
    are elastic."""

    LOADING = 0
    UNLOADING = 1
    RELOADING = 2


def branches(path: Float[Array, " points"]) -> Int[Array, " points"]:
    """Each point's `Branch`: loading at the first point and where a load exceeds every earlier one,
    unloading where it is below the last one, reloading otherwise. A load equal to the largest
    earlier one is reloading: the state is the one left there, and its tangent the elastic one
    reached from below (at a kink of the path's curve, whose loading side begins only beyond it)."""
    previous = jnp.concatenate([path[:1], path[:-1]])
    peak = jnp.concatenate([path[:1], jax.lax.cummax(path)[:-1]])
    loading = (jnp.arange(path.shape[0]) == 0) | (path > peak)
    return jnp.select([loading, path < previous], [Branch.LOADING, Branch.UNLOADING], Branch.RELOADING).astype(
        jnp.int32
    )
