"""The joint along a load path in the order applied: load, unload, reload (docs/in-service.md).

An elastic model without a path law (GW, Persson) has no memory: every point of a path is the
loading solve at its load, and the approach is the load–approach curve read from the path's first
point. A model with a memory of the path (`AbstractPathModel.path_solver`) follows it: the
boundary-element model the plastic flattening of its capped surface, `MeasuredAsperities` each
summit's deepest interference. A model whose spots flow but that has no path law (the seed model,
JZZ: their spot population is not a set of spots that grow and shrink, docs/in-service.md) is
refused.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float, Int

from ..core import Outputs, Scene, prepare, solve
from ..core._loadcontrol import within_domain
from ..models import AbstractPathModel
from ..numerics import InputError
from ..quantities import Scales, Status, branches, nondimensionalise
from ._approach_sum import approach_quadrature

_LOADING = Outputs(regime_shares=False)


class LoadPath(eqx.Module):
    """The joint along a load path (leading axis: the path's points, in the order applied).

    **Fields:** `load` (N); `approach` (m), relative to the first point; `stiffness` (N/m), the
    tangent on the branch travelled; `unloading_stiffness` (N/m), the tangent of a small unload
    from the point; `real_area` (m²); `branch` (`jaxcontact.Branch`); `status` (0 = ok);
    `residual_approach` (m), the approach left after a full unload (0 for an elastic model).
    """

    load: Float[Array, " points"]
    approach: Float[Array, " points"]
    stiffness: Float[Array, " points"]
    unloading_stiffness: Float[Array, " points"]
    real_area: Float[Array, " points"]
    branch: Int[Array, " points"]
    status: Int[Array, " points"]
    residual_approach: Float[Array, ""]


def solve_path(scene: Scene, path, *, nodes: int = 8) -> LoadPath:
    """The joint along a load path (module docstring).

    **Arguments:**

    - `scene`: the joint; its model is elastic (`unloads_as_it_loads()`) or remembers the path
      (`AbstractPathModel`: the BEM model, capped with `plastic=True`; `MeasuredAsperities`).
    - `path`: total normal loads, N, a 1-D array in the order applied.
    - `nodes`: Gauss–Legendre nodes per piece of an elastic model's approach (`approach_quadrature`).

    **Returns:** a `LoadPath`. Works under `jax.jit` and `jax.grad` (with respect to the scene's
    float fields and the loads) as `solve` and the BEM's `solve_path` do.

    **Raises:** `ValueError` for a path that is not 1-D or has a non-positive or non-finite load,
    and for a model whose spots flow without a path law (xia2024, jzz2010).
    """
    model = scene.model
    if jnp.ndim(path) != 1:
        raise InputError(f"path has shape {jnp.shape(path)}: give the loads (N) as a 1-D array in the order applied")
    if not isinstance(model, AbstractPathModel) and not model.unloads_as_it_loads():
        raise InputError(
            f"model = {model.name!r} has no load-path law (its spots flow, and how they unload and reload along a "
            "path is not built: docs/in-service.md): solve_path takes an elastic model (gw, persson), "
            "measured-asperities or the boundary-element model (bem)"
        )
    scene, loads = prepare(scene, path)
    loads = jnp.asarray(loads)
    kinds = branches(loads)
    if isinstance(model, AbstractPathModel):
        return _followed(scene, loads, kinds)
    loading = solve(scene, loads, outputs=_LOADING)
    curve = approach_quadrature(scene, loads, loads[0], nodes=nodes)
    status = jnp.where(loading.status == Status.OK, curve.status, loading.status)
    ok = status == Status.OK
    stiffness = jnp.where(ok, loading.stiffness, jnp.nan)
    return LoadPath(
        load=loads,
        approach=jnp.where(ok, curve.approach, jnp.nan),
        stiffness=stiffness,
        unloading_stiffness=stiffness,
        real_area=jnp.where(ok, loading.real_area, jnp.nan),
        branch=kinds,
        status=status,
        residual_approach=jnp.where(jnp.all(ok), jnp.zeros((), loads.dtype), jnp.nan),
    )


@eqx.filter_jit
def _followed(scene: Scene, loads, kinds) -> LoadPath:
    guarded, in_domain = within_domain(scene)
    scales = Scales.of(guarded)
    points = guarded.model.path_solver(nondimensionalise(guarded))(loads / scales.load)
    status = jnp.where(in_domain, points.status, Status.INVALID_PARAMETERS).astype(jnp.int32)
    ok = status == Status.OK
    length = scales.length
    return LoadPath(
        load=loads,
        approach=jnp.where(ok, points.approach_star * length, jnp.nan),
        stiffness=jnp.where(ok, points.stiffness_star * scales.stiffness, jnp.nan),
        unloading_stiffness=jnp.where(ok, points.unloading_star * scales.stiffness, jnp.nan),
        real_area=jnp.where(ok, points.real_area_star * scales.area, jnp.nan),
        branch=kinds,
        status=status,
        residual_approach=jnp.where(jnp.all(ok), points.residual_star * length, jnp.nan),
    )
