"""Load control (Sec. 4, MODEL.md §4): solve `F_t(a_l) = F` for the largest spot, then evaluate.

The solve runs in `ln a_l*` on `[ln a_min*, 0]` (the largest spot lies between the smallest
fractal asperity and the nominal area). `F_t` at the regime boundaries (once per scene) tells
which smooth piece of `F_t` holds each load (`load_pieces`); Newton's method then runs on that
piece alone, from the piece's log-log interpolant and with its closed-form slope (`solver`:
plain steps first, optimistix's safeguarded loop for any point that needs more), and the root is
differentiated by the implicit function theorem, `da_l/dθ = -(∂F_t/∂θ)/(∂F_t/∂a_l)`.

Failed points never raise and never poison a batch: each is solved at a harmless stand-in
load, its outputs are replaced by NaN and it is given a non-zero `status`, so the values and
gradients of the other points are exactly what they would be alone.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Bool, Float

from ._elementwise import unrolled_sum
from ._validate import concrete
from .dimensionless import nondimensionalise
from .joint import AbstractJoint, JointResponse, Xia2024Joint
from .jzz2010 import JZZ2010Joint
from .scene import Scene
from .solution import Solution, is_solved, masked_rescale
from .solver import solve_increasing
from .status import Status


def make_joint(scene: Scene) -> AbstractJoint:
    """The dimensionless joint model that `scene` asks for."""
    s = nondimensionalise(scene)
    if scene.model == "xia2024":
        return Xia2024Joint.from_dimensionless(s, scene.interaction, scene.quadrature_nodes, scene.quadrature,
                                               scene.quadrature_tolerance)
    return JZZ2010Joint.from_dimensionless(s)


def _piece_residual(log_a_l, args):
    pieces, piece, log_load = args
    return pieces.log_load(log_a_l, piece) - log_load, None


def _piece_residual_slope(log_a_l, args):
    pieces, piece, _ = args
    return pieces.log_load_slope(log_a_l, piece)


def _check_loads(loads) -> None:
    values = concrete(loads)
    if values is None:
        return
    bad = ~(np.isfinite(values) & (values > 0))
    if np.any(bad):
        where = np.argwhere(bad)[0]
        index = f"[{', '.join(map(str, where))}]" if values.ndim else ""
        raise ValueError(f"loads{index} = {float(values[tuple(where)])!r} N is not a valid load: "
                         "loads must be finite and > 0 (valid range (0, inf) N)")


def _working_dtype(scene: Scene, loads):
    # A weak Python float: float32 unless x64 is on or an input is already float64.
    leaves = [x for x in jax.tree.leaves((scene, loads)) if eqx.is_array_like(x)]
    return jnp.result_type(1.0, *[x for x in leaves if not isinstance(x, float)])


# Any valid scene (Table 1's), in the order of `_float_fields`: where a scene's parameters are out
# of their domain, the model is evaluated at these instead, so that nothing it computes is NaN.
_STAND_IN = dict(D=1.4058, G=2.2826e-10, l_min=1e-9, E=220e9, nu=0.25, H=100e9, area=1e-4)


def _float_fields(scene: Scene):
    s, m = scene.surface, scene.material
    return s.D, s.G, s.l_min, m.E, m.nu, m.H, scene.area


def within_domain(scene: Scene) -> tuple[Scene, Bool[Array, ""]]:
    """The scene, with stand-in values if any float parameter is outside its domain; and whether none is.

    Traced parameters cannot be checked at construction (an optimiser may step to D = 2).
    Evaluated as they are, such parameters give NaN, and a NaN inside the computation leaks into
    gradients even where the result is masked (0 · NaN). Evaluated at a valid stand-in (and
    flagged), masked points contribute exactly zero.
    """
    fields = _float_fields(scene)
    D, G, l_min, E, nu, H, area = fields
    inside = ((D > 1.0) & (D < 2.0) & (G > 0) & (l_min > 0) & (E > 0) & (H > 0) & (nu >= 0) & (nu < 0.5)
              & (area > 0) & (l_min * l_min < area))  # the last: a_min* < 1
    values = tuple(jnp.where(inside, x, stand_in) for x, stand_in in zip(fields, _STAND_IN.values()))
    return eqx.tree_at(_float_fields, scene, values), inside


class PointResult(eqx.Module):
    """One load point, dimensionless: `ln a_l*`, the joint's response there, and the status."""

    log_a_l: jax.Array
    response: JointResponse
    status: jax.Array

    @property
    def stiffness_star(self):
        """K* where the point is valid, NaN otherwise."""
        K = unrolled_sum(self.response.regime_stiffness)
        return jnp.where(self.status == Status.OK, K, jnp.nan)


def point_solver(scene: Scene):
    """Set up the load-controlled solve once per scene; returns `F* ↦ PointResult` for one load.

    Everything that does not depend on the load (the joint's constants, the Wang–Komvopoulos ψ,
    `F_t` at the kinks that bracket each piece) is computed here, so that callers that evaluate
    K(F) many times (`approach`, `dynamics`) pay for it once.
    """
    scene, in_domain = within_domain(scene)
    joint = make_joint(scene)
    dtype = jnp.result_type(joint.log_a_min)
    tolerance = scene.solver_tolerance or float(64 * jnp.finfo(dtype).eps)
    pieces = joint.load_pieces()
    log_load_lowest = pieces.knot_log_loads[0]  # -inf for xia2024: any F > 0 is reachable
    log_load_highest = pieces.knot_log_loads[-1]
    # Failed points are solved at a harmless stand-in: the load that puts a_l midway (in logs).
    log_load_middle = jnp.log(joint.total_load(0.5 * joint.log_a_min))
    parameters_valid = in_domain & jnp.isfinite(log_load_highest) & jnp.isfinite(log_load_middle)

    def one_point(F_star) -> PointResult:
        valid = jnp.isfinite(F_star) & (F_star > 0)
        log_load = jnp.log(jnp.where(valid, F_star, 1.0))
        in_range = (log_load > log_load_lowest) & (log_load <= log_load_highest)
        usable = valid & in_range
        log_load = jnp.where(usable, log_load, log_load_middle)
        piece, lower, upper, guess = pieces.locate(log_load)
        log_a_l, converged = solve_increasing(_piece_residual, guess, (pieces, piece, log_load), lower, upper,
                                              tolerance=tolerance, max_steps=scene.max_steps, slope=_piece_residual_slope)
        response = joint.response(log_a_l, log_load)
        status = jnp.select(
            [~parameters_valid, ~valid, ~in_range, ~converged, response.breakdown],
            [Status.INVALID_PARAMETERS, Status.INVALID_LOAD, Status.LOAD_OUT_OF_RANGE, Status.NOT_CONVERGED,
             Status.INTERACTION_BREAKDOWN],
            Status.OK,
        ).astype(jnp.int32)
        return PointResult(log_a_l, response, status)

    return one_point


@eqx.filter_jit
def _solve(scene: Scene, loads):
    # The scales too come from the stand-in where the scene is out of its domain (the points are
    # flagged by `point_solver`, which is handed the scene as it is).
    guarded, _ = within_domain(scene)
    E, area = guarded.material.E, guarded.area
    load_star = loads / (E * area)
    points = jax.vmap(point_solver(scene))(load_star.reshape(-1))
    log_a_l, response, status = points.log_a_l, points.response, points.status
    shape = loads.shape
    solved = is_solved(status)
    ok = status == Status.OK
    stiffness_total = unrolled_sum(response.regime_stiffness)
    a_l_star = jnp.exp(log_a_l)
    load_share = stiffness_share = None
    if scene.regime_shares:
        load_total = jnp.where(solved, unrolled_sum(response.regime_load), 1.0)[:, None]
        positive = jnp.where(ok & (stiffness_total > 0), stiffness_total, 1.0)[:, None]  # K = 0: all plastic
        load_share = masked_rescale(solved[:, None], response.regime_load / load_total).reshape(shape + (4,))
        stiffness_share = masked_rescale(ok[:, None], response.regime_stiffness / positive).reshape(shape + (4,))
    return Solution(
        load=loads,
        a_l=masked_rescale(solved, a_l_star, area).reshape(shape),
        stiffness=masked_rescale(ok, stiffness_total, E * jnp.sqrt(area)).reshape(shape),
        real_area=masked_rescale(solved, response.real_area, area).reshape(shape),
        status=status.reshape(shape),
        load_share=load_share,
        stiffness_share=stiffness_share,
        modulus=E.reshape((1,) * len(shape)),
        nominal_area=area.reshape((1,) * len(shape)),
    )


def prepare(scene: Scene, loads):
    """Check concrete loads, pick the working dtype, and make every float leaf an array of it."""
    _check_loads(loads)
    dtype = _working_dtype(scene, loads)
    return jax.tree.map(lambda x: jnp.asarray(x, dtype), scene), jnp.asarray(loads, dtype)


def solve(scene: Scene, loads: Float[ArrayLike, "*loads"]) -> Solution:
    """Normal contact stiffness of the joint at each load (MODEL.md §4, Eqs. 30–39).

    **Arguments:**

    - `scene`: the joint and the model choices (`jaxcontact.Scene`).
    - `loads`: total normal load F in newtons, a scalar or an array of any shape.

    **Returns:** a `Solution` with one entry per load. Points that cannot be computed (load out of
    range, interaction breakdown, unconverged solve, a traced non-positive load) carry a non-zero
    `status` and NaN values; the rest of the batch is unaffected.

    Works under `jax.jit`, `jax.vmap` (over loads, or over scenes whose float fields are
    batched arrays) and `jax.grad`/`jax.jvp` with respect to every float field of the scene and
    the loads. Runs in float64 when `jax_enable_x64` is on and in float32 otherwise.

    **Raises:** `ValueError` for concrete loads that are negative, zero or not finite.
    """
    return _solve(*prepare(scene, loads))
