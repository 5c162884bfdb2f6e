"""Load control (Sec. 4, docs/model.md §4): the loads in, a `Solution` out.

`solve` checks the loads, makes the scene dimensionless, asks the scene's model for its
per-load solve (`AbstractContactModel.point_solver`; for the largest-spot models the a_l solve of
`models._base`), maps it over the loads and rescales the results.

Failed points never raise and never poison a batch: each is solved at a harmless stand-in
load, its outputs are replaced by NaN and it is given a non-zero `status`, so the values and
gradients of the other points are exactly what they would be alone.
"""

from __future__ import annotations

import functools

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from ..models import PointResult
from ..models import curve_solver as model_curve_solver
from ..numerics import LoadsLike
from ..numerics._elementwise import unrolled_sum
from ..numerics._quadrature import for_loads
from ..physics import AbstractStiffness, Loading, TangentialStick, Unloading
from ..programs import _programs as programs
from ..quantities import Scales, Status, nondimensionalise
from ..quantities._domain import PARAMETERS, all_valid, scene_fields, valid_fields
from ._defaults import table1_values
from ._prepare import _prepare
from ._scene import Scene
from ._settings import Outputs
from ._solution import Solution, is_solved, masked_rescale, thrown


def within_domain(scene: Scene) -> tuple[Scene, Bool[Array, ""]]:
    """The scene, with a stand-in value for each float parameter outside its domain; and whether none is.

    Traced parameters cannot be checked at construction (an optimiser may step to D = 2).
    Evaluated as they are, such parameters give NaN, and a NaN inside the computation leaks into
    gradients even where the result is masked (0 · NaN). Evaluated at valid stand-ins (and
    flagged), masked points contribute exactly zero.
    """
    valid = valid_fields(scene)
    # Any valid value will do as a stand-in: the default scene's. Each parameter is replaced on
    # its own check, not on the whole scene's: XLA copies the check into every fusion that reads
    # the parameter, and in a gradient the whole scene's check, copied hundreds of times, was a
    # third of the program.
    stand_in = table1_values()
    values = tuple(jnp.where(valid[name], x, stand_in[name]) for x, name in zip(scene_fields(scene), PARAMETERS))
    return eqx.tree_at(scene_fields, scene, values), all_valid(valid)


def _flagged(guarded: Scene, in_domain, build):
    """The model's solve (`build`) of the scene with stand-ins (`within_domain`), its points flagged
    `INVALID_PARAMETERS` where the scene as given was not `in_domain`."""
    model_solve = build(guarded.model, nondimensionalise(guarded))

    def flagged(F_star) -> PointResult:
        point = model_solve(F_star)
        status = jnp.where(in_domain, point.status, Status.INVALID_PARAMETERS).astype(jnp.int32)
        return PointResult(point.log_a_l, point.response, status)

    return flagged


def point_solver(scene: Scene, stiffness: AbstractStiffness = Loading()):
    """Set up the load-controlled solve once per scene; returns `F* ↦ PointResult` for one load.

    Everything that does not depend on the load (the joint's constants, the Wang–Komvopoulos ψ,
    `F_t` at the kinks that bracket each piece) is computed here, so that callers that evaluate
    K(F) many times (`approach`, `dynamics`) pay for it once. Points of a scene whose (traced)
    parameters are outside their domain get `Status.INVALID_PARAMETERS`. With
    `stiffness=Unloading()` each point's stiffness is the initial unloading tangent of the state
    its load reaches on loading (`solve`'s `Outputs(stiffness=Unloading())`); only the normal
    stiffnesses (`stiffness.unloading` decides which) are points' own.
    """
    if not stiffness.unloading:
        return _flagged(*within_domain(scene), type(scene.model).point_solver)
    curve = _flagged(*within_domain(scene), functools.partial(model_curve_solver, unloading=True))

    def one_point(F_star) -> PointResult:
        return jax.tree.map(lambda x: x[0], curve(jnp.reshape(F_star, (1,))))

    return one_point


def kink_log_loads(scene: Scene) -> Float[Array, " kinks"]:
    """`ln F*` where K(F) has a kink (the model's `kink_log_loads`), for integrators of K(F)."""
    scene, _ = within_domain(scene)
    return scene.model.kink_log_loads(nondimensionalise(scene))


def _solve(tree: tuple[Scene, Outputs], loads):
    scene, outputs = tree
    scene = for_loads(scene, loads.size)  # the program's layout (`PowerSeries`)
    # The scales too come from the stand-in where the scene is out of its domain (its points are flagged).
    guarded, in_domain = within_domain(scene)
    scales = Scales.of(guarded)
    # A traced NaN or non-positive load is flagged by `point_solver`; divided by E A_a as it is, it
    # would give the scales a NaN derivative that the masking cannot remove (0 · NaN).
    usable = jnp.isfinite(loads) & (loads > 0)
    load_star = jnp.where(usable, jnp.where(usable, loads, 1.0) / scales.load, loads)
    kind = outputs.stiffness
    build = functools.partial(model_curve_solver, unloading=kind.unloading)
    points = _flagged(guarded, in_domain, build)(load_star.reshape(-1))
    log_a_l, response, status = points.log_a_l, points.response, points.status
    shape = loads.shape
    solved = is_solved(status)
    ok = status == Status.OK
    regime_stiffness = kind.of_normal(response.regime_stiffness, guarded.material.nu)
    stiffness_total = unrolled_sum(regime_stiffness)
    a_l_star = jnp.exp(log_a_l)
    load_share = stiffness_share = None
    regimes = scene.model.regimes
    if outputs.regime_shares:
        load_total = jnp.where(solved, unrolled_sum(response.regime_load), 1.0)[:, None]
        positive = jnp.where(ok & (stiffness_total > 0), stiffness_total, 1.0)[:, None]  # K = 0: all plastic
        load_share = masked_rescale(solved[:, None], response.regime_load / load_total).reshape(shape + (len(regimes),))
        stiffness_share = masked_rescale(ok[:, None], regime_stiffness / positive).reshape(shape + (len(regimes),))
    return Solution(
        load=loads,
        a_l=masked_rescale(solved, a_l_star, scales.area).reshape(shape),
        stiffness=masked_rescale(ok, stiffness_total, scales.stiffness).reshape(shape),
        real_area=masked_rescale(solved, response.real_area, scales.area).reshape(shape),
        status=status.reshape(shape),
        load_share=load_share,
        stiffness_share=stiffness_share,
        modulus=scales.modulus.reshape((1,) * len(shape)),
        nominal_area=scales.area.reshape((1,) * len(shape)),
        regimes=regimes,
    )


def _solution_tree(treedef):
    """`leaves ↦` the tree structure of `_solve`'s `Solution` for this scene, without tracing it."""

    def tree(leaves):
        scene, outputs = jax.tree_util.tree_unflatten(treedef, leaves)
        zero = jnp.zeros(())
        shares = jnp.zeros((len(scene.model.regimes),)) if outputs.regime_shares else None
        fields = ("load", "a_l", "stiffness", "real_area", "modulus", "nominal_area")
        template = Solution(
            **dict.fromkeys(fields, zero),
            status=jnp.zeros((), jnp.int32),
            load_share=shares,
            stiffness_share=shares,
            regimes=scene.model.regimes,
        )
        return jax.tree_util.tree_structure(template)

    return tree


# The default of `solve`'s option: one object, so that the last call's check is an identity test.
DEFAULT_OUTPUTS = Outputs()


def solve(
    scene: Scene,
    loads: LoadsLike,
    *,
    outputs: Outputs = DEFAULT_OUTPUTS,
    throw: bool = False,
) -> Solution:
    """Normal contact stiffness of the joint at each load (docs/model.md §4, Eqs. 30–39).

    **Arguments:**

    - `scene`: the joint and its model (`jaxcontact.Scene`).
    - `loads`: total normal load F in newtons, a scalar or an array of any shape.
    - `outputs`: what to return beside K, a_l and A_r: `Outputs(regime_shares=True)` (the default)
      splits load and stiffness by regime; `Outputs(regime_shares=False)` spends nothing on it.
    - `throw`: raise where a point has no valid result instead of flagging it: a `StatusError`
      naming the points and their statuses, or under `jit` a runtime error with the first bad
      point's `Status.message`.

    **Returns:** a `Solution` with one entry per load. Points that cannot be computed (load out of
    range, interaction breakdown, unconverged solve, a traced non-positive load) carry a non-zero
    `status` and NaN values; the rest of the batch is unaffected.

    Works under `jax.jit`, `jax.vmap` (over loads, or over scenes whose float fields are
    batched arrays) and `jax.grad`/`jax.jvp` with respect to every float field of the scene and
    the loads. Runs in float64 when `jax_enable_x64` is on and in float32 otherwise.

    **Raises:** `ValueError` for concrete loads that are negative, zero or not finite.
    """
    if not isinstance(throw, bool):
        raise InputError(f"throw = {throw!r} must be true or false")
    _, leaves, treedef, loads = _prepare(scene, loads, outputs)
    solution = programs.call(_solve, leaves, treedef, loads, _solution_tree(treedef), pad=scene.model.pad_loads)
    return thrown(solution) if throw else solution


_UNLOADING = Outputs(stiffness=Unloading())
_TANGENTIAL = Outputs(stiffness=TangentialStick())


def dynamic_stiffness(scene: Scene, preload: LoadsLike, *, throw: bool = False) -> Solution:
    """The normal stiffness of a small vibration about a preload reached by loading: every spot
    unloads elastically from its state at the preload (docs/in-service.md). For an elastic model it
    is the loading K; where spots flowed it is larger (the seed model's fully plastic spots, K = 0
    on loading, each unload with `2E*r`).

    **Arguments:** as `solve`, `preload` its loads. **Returns:** `solve(scene, preload,
    outputs=Outputs(stiffness=Unloading()))`, a `Solution` whose `stiffness` is that tangent.
    **Raises:** `ValueError` for a model without an unloading law (none of the registered ones).
    """
    return solve(scene, preload, outputs=_UNLOADING, throw=throw)


def tangential_stiffness(scene: Scene, loads: LoadsLike, *, throw: bool = False) -> Solution:
    """Mindlin's tangential stiffness in full stick at each load (reached by loading): each spot's
    `8G*r`, `2(1 − ν)/(2 − ν)` times its unloading stiffness for two bodies of like material
    (docs/in-service.md).

    **Arguments:** as `solve`. **Returns:** `solve(scene, loads, outputs=Outputs(stiffness=TangentialStick()))`.
    **Raises:** `ValueError` for a model without an unloading law (none of the registered ones).
    """
    return solve(scene, loads, outputs=_TANGENTIAL, throw=throw)
