"""Load control (Sec. 4, MODEL.md §4): the loads in, a `Solution` out.

`solve` checks the loads, makes the scene dimensionless, asks the scene's model for its
per-load solve (`AbstractContactModel.point_solver`; for the largest-spot models the a_l solve of
`models.base`), maps it over the loads and rescales the results.

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

from ..models.base import PointResult
from ..numerics.compat import top_level
from ..numerics.elementwise import unrolled_sum
from ..numerics.validate import InputError, check_instance, concrete
from . import programs
from .defaults import table1_values
from .domain import PARAMETERS, all_valid, scene_fields, valid_fields
from .scales import Scales, nondimensionalise
from .scene import Scene
from .settings import NewtonBisection, Outputs
from .solution import Solution, is_solved, masked_rescale
from .status import Status


def _check_loads(loads) -> None:
    values = concrete(loads)
    if values is None:
        return
    # Two reductions decide the common case; NaN fails `> 0` and falls through to the search.
    if values.size and values.min() > 0 and values.max() < np.inf:
        return
    bad = ~(np.isfinite(values) & (values > 0))
    if np.any(bad):
        where = np.argwhere(bad)[0]
        index = f"[{', '.join(map(str, where))}]" if values.ndim else ""
        raise InputError(
            f"loads{index} = {float(values[tuple(where)])!r} N is not a valid load: "
            "loads must be finite and > 0 (valid range (0, inf) N)"
        )


_DTYPES: dict = {}


def _working_dtype(leaves, loads, memo=None):
    # A weak Python float: float32 unless x64 is on or an input is already float64. Cached by the
    # inputs' dtypes, as jnp.result_type costs more than the rest of an eager call's checks; `memo`
    # (one scene's) is keyed by the loads' dtype alone, so a repeated call looks at no leaf.
    quick = (jax.config.jax_enable_x64, getattr(loads, "dtype", None), getattr(loads, "weak_type", False))
    if memo is not None and quick in memo:
        return memo[quick]
    typed = [x for x in (*leaves, loads) if hasattr(x, "dtype")]
    key = (jax.config.jax_enable_x64, *((x.dtype, getattr(x, "weak_type", False)) for x in typed))
    if key not in _DTYPES:
        _DTYPES[key] = jnp.result_type(1.0, *typed)
    if memo is not None:
        memo[quick] = _DTYPES[key]
    return _DTYPES[key]


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


def point_solver(scene: Scene, solver: NewtonBisection = NewtonBisection()):
    """Set up the load-controlled solve once per scene; returns `F* ↦ PointResult` for one load.

    Everything that does not depend on the load (the joint's constants, the Wang–Komvopoulos ψ,
    `F_t` at the kinks that bracket each piece) is computed here, so that callers that evaluate
    K(F) many times (`approach`, `dynamics`) pay for it once. Points of a scene whose (traced)
    parameters are outside their domain get `Status.INVALID_PARAMETERS`.
    """
    scene, in_domain = within_domain(scene)
    s = nondimensionalise(scene)
    tolerance = solver.tolerance_for(jnp.result_type(s.log_a_min))
    model_point = scene.model.point_solver(s, tolerance=tolerance, max_steps=solver.max_steps)

    def one_point(F_star) -> PointResult:
        point = model_point(F_star)
        status = jnp.where(in_domain, point.status, Status.INVALID_PARAMETERS).astype(jnp.int32)
        return PointResult(point.log_a_l, point.response, status)

    return one_point


def kink_log_loads(scene: Scene) -> Float[Array, " kinks"]:
    """`ln F*` where K(F) has a kink (the model's `kink_log_loads`), for integrators of K(F)."""
    scene, _ = within_domain(scene)
    return scene.model.kink_log_loads(nondimensionalise(scene))


def _solve(tree: tuple[Scene, Outputs, NewtonBisection], loads):
    scene, outputs, solver = tree
    # The scales too come from the stand-in where the scene is out of its domain (the points are
    # flagged by `point_solver`, which is handed the scene as it is).
    guarded, _ = within_domain(scene)
    scales = Scales.of(guarded)
    # A traced NaN or non-positive load is flagged by `point_solver`; divided by E A_a as it is, it
    # would give the scales a NaN derivative that the masking cannot remove (0 · NaN).
    usable = jnp.isfinite(loads) & (loads > 0)
    load_star = jnp.where(usable, jnp.where(usable, loads, 1.0) / scales.load, loads)
    points = jax.vmap(point_solver(scene, solver))(load_star.reshape(-1))
    log_a_l, response, status = points.log_a_l, points.response, points.status
    shape = loads.shape
    solved = is_solved(status)
    ok = status == Status.OK
    stiffness_total = unrolled_sum(response.regime_stiffness)
    a_l_star = jnp.exp(log_a_l)
    load_share = stiffness_share = None
    regimes = scene.model.regimes
    if outputs.regime_shares:
        load_total = jnp.where(solved, unrolled_sum(response.regime_load), 1.0)[:, None]
        positive = jnp.where(ok & (stiffness_total > 0), stiffness_total, 1.0)[:, None]  # K = 0: all plastic
        load_share = masked_rescale(solved[:, None], response.regime_load / load_total).reshape(shape + (len(regimes),))
        stiffness_share = masked_rescale(ok[:, None], response.regime_stiffness / positive).reshape(
            shape + (len(regimes),)
        )
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
        scene, outputs, _ = jax.tree_util.tree_unflatten(treedef, leaves)
        shares = 0.0 if outputs.regime_shares else None
        fields = ("load", "a_l", "stiffness", "real_area", "status", "modulus", "nominal_area")
        template = Solution(
            **dict.fromkeys(fields, 0.0), load_share=shares, stiffness_share=shares, regimes=scene.model.regimes
        )
        return jax.tree_util.tree_structure(template)

    return tree


def _check_scalar_parameters(scene: Scene) -> None:
    for name, value in zip(PARAMETERS, scene_fields(scene)):
        if not isinstance(value, jax.core.Tracer) and jnp.ndim(value) != 0:
            raise InputError(
                f"{name} has shape {jnp.shape(value)}: solve takes one scene, with scalar parameters; for a batch "
                "of scenes, vmap over them: jax.vmap(jc.solve, in_axes=(0, None))(jc.stack_scenes(scenes), loads)"
            )


def _on_host(array: jax.Array) -> bool:
    # A CPU-resident array reads as numpy without a copy; an accelerator's would need a transfer.
    return all(device.platform == "cpu" for device in array.devices())


# The scene of the last eager call, flattened, checked and cast per working dtype: a user who
# calls `solve` in a loop on one scene pays for that once. Scenes are immutable, and the strong
# reference kept here makes the identity test sound. Nothing made inside a trace is kept: arrays
# made there (even from a concrete scene a caller's `jit` closes over) belong to that trace.
_last_scene: dict = {}


def _same(a, b) -> bool:
    return a is b or a == b


def _scene_leaves(scene: Scene, outputs: Outputs, solver: NewtonBisection, loads):
    keep = top_level()
    last = _last_scene.get("tree")
    if last is not None and last[0] is scene and _same(last[1], outputs) and _same(last[2], solver):
        return _cast(_last_scene, loads, keep)
    check_instance("scene", scene, Scene)
    check_instance("outputs", outputs, Outputs)
    check_instance("solver", solver, NewtonBisection)
    # The settings have no array leaves: they are part of the tree's structure, so that each
    # combination is its own program.
    tree = (scene, outputs, solver)
    leaves, treedef = jax.tree_util.tree_flatten(tree)
    if not all(getattr(x, "ndim", 0) == 0 for x in leaves):
        _check_scalar_parameters(scene)
    entry = dict(tree=tree, leaves=leaves, treedef=treedef, cast={}, dtypes={})
    if not keep:  # traced leaves too: they exist only inside a trace
        return _cast(entry, loads, keep=False)
    _last_scene.clear()
    _last_scene.update(entry)
    return _cast(_last_scene, loads, keep)


def _cast(entry: dict, loads, keep: bool):
    dtype = _working_dtype(entry["leaves"], loads, entry["dtypes"])
    cast = entry["cast"].get(dtype)
    if cast is None:
        leaves = entry["leaves"]
        # Leaves already of the working dtype are passed through: no conversion of each. Weakly
        # typed ones (a scene built from Python floats) are made strong, so that it shares its
        # compiled program with the same scene built from numpy or JAX values.
        arrays = [
            x if isinstance(x, jax.Array) and x.dtype == dtype and not x.weak_type else jnp.asarray(x, dtype)
            for x in leaves
        ]
        unchanged = all(a is b for a, b in zip(arrays, leaves))
        cast = (entry["tree"] if unchanged else jax.tree_util.tree_unflatten(entry["treedef"], arrays), arrays)
        if keep:
            entry["cast"][dtype] = cast
    return dtype, *cast, entry["treedef"]


# The JAX load array of the last eager call, with its working dtype and prepared form: a user who
# solves many scenes at one array of loads has it checked once (the check reads it on the host,
# a fifth of an eager call's overhead). JAX arrays are immutable, and the strong reference kept
# here makes the identity test sound; numpy arrays can change in place and are checked every time.
_last_loads: tuple = (None, None, None)


def _prepare(scene: Scene, loads, outputs: Outputs = Outputs(), solver: NewtonBisection = NewtonBisection()):
    global _last_loads
    last, last_dtype, last_prepared = _last_loads
    seen = last is loads
    if not seen:
        _check_loads(loads)
    dtype, tree, leaves, treedef = _scene_leaves(scene, outputs, solver, loads)
    if seen and last_dtype == dtype:
        return tree, leaves, treedef, last_prepared
    if isinstance(loads, jax.core.Tracer) or (isinstance(loads, jax.Array) and not _on_host(loads)):
        prepared = loads if loads.dtype == dtype else loads.astype(dtype)
    else:  # host arrays go to a jitted program as they are, faster than through jnp.asarray
        prepared = np.asarray(loads, dtype=dtype)
    if isinstance(loads, jax.Array) and not isinstance(loads, jax.core.Tracer) and top_level():
        _last_loads = (loads, dtype, prepared)
    return tree, leaves, treedef, prepared


def prepare(scene: Scene, loads):
    """Check concrete loads and parameters, pick the working dtype, and make every float leaf an
    array of it: `(scene, loads)` as `solve` would compute with them."""
    (scene, _, _), _, _, loads = _prepare(scene, loads)
    return scene, loads


# The defaults of `solve`'s options: one object each, so that the last call's check is an identity test.
DEFAULT_OUTPUTS = Outputs()
DEFAULT_SOLVER = NewtonBisection()


def solve(
    scene: Scene,
    loads: Float[ArrayLike, "*loads"],
    *,
    outputs: Outputs = DEFAULT_OUTPUTS,
    solver: NewtonBisection = DEFAULT_SOLVER,
) -> Solution:
    """Normal contact stiffness of the joint at each load (MODEL.md §4, Eqs. 30–39).

    **Arguments:**

    - `scene`: the joint and its model (`jaxcontact.Scene`).
    - `loads`: total normal load F in newtons, a scalar or an array of any shape.
    - `outputs`: what to return beside K, a_l and A_r: `Outputs(regime_shares=True)` (the default)
      splits load and stiffness by regime; `Outputs(regime_shares=False)` spends nothing on it.
    - `solver`: the per-load solve of the model's state, `NewtonBisection(max_steps=64,
      tolerance=None)` (64 ε of the working dtype).

    **Returns:** a `Solution` with one entry per load. Points that cannot be computed (load out of
    range, interaction breakdown, unconverged solve, a traced non-positive load) carry a non-zero
    `status` and NaN values; the rest of the batch is unaffected.

    Works under `jax.jit`, `jax.vmap` (over loads, or over scenes whose float fields are
    batched arrays) and `jax.grad`/`jax.jvp` with respect to every float field of the scene and
    the loads. Runs in float64 when `jax_enable_x64` is on and in float32 otherwise.

    **Raises:** `ValueError` for concrete loads that are negative, zero or not finite.
    """
    _, leaves, treedef, loads = _prepare(scene, loads, outputs, solver)
    return programs.call(_solve, leaves, treedef, loads, _solution_tree(treedef))
