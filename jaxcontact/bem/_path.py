"""A load path with memory on the capped boundary-element contact (docs/in-service.md).

Where the pressure sits at the hardness the surface flows: after each load of the path, the heights
of its plastic points are lowered by their interpenetration (`gap < 0` there), a permanent change
for every later load. On the flattened heights the same pressure is an elastic solution with zero
gap on every contact point, so that unloading, and reloading up to the largest earlier load, are
elastic until the cap is reached again. A point reached by unloading or reloading has the elastic
tangent of its contact set (plastic points unload with the surface); one reached by loading beyond
every earlier load the capped tangent of `bem.solve` (plastic points stay at the cap).
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float, Int

from ..numerics._validate import InputError, check_strategy
from ..quantities import Branch, Status, branches
from ._checks import check_arguments, check_iteration, checked_status, stand_in_loads, valid_problem
from ._contact import DEFAULT_TOLERANCE, contact_at, warm_start
from ._fft import AbstractFFT, LocalFFT, check_fft
from ._operator import SUBSTRATES, AbstractSubstrate, Periodic
from ._problem import GridProblem
from ._tangent import elastic_stiffness


class PathSolution(eqx.Module):
    """The boundary-element contact along a load path (leading axis: the path's points, in order).

    **Fields:** `loads` (N); `approach` (m), the rigid approach relative to the first point;
    `stiffness` (N/m), the exact tangent `dF/dδ` on the branch travelled; `unloading_stiffness`
    (N/m), the elastic tangent of a small unload from the point (equal to `stiffness` off the
    loading branch and wherever nothing flows); `contact_fraction`, `plastic_fraction`; `branch`
    (`jaxcontact.Branch`); `status` (as `bem.solve`'s); `iterations`; `residual_approach` (m), the
    approach left after unloading fully (the flattening of the highest point, `max h − max h'`);
    `heights` (m), the flattened map after the path.
    """

    loads: Float[Array, " points"]
    approach: Float[Array, " points"]
    stiffness: Float[Array, " points"]
    unloading_stiffness: Float[Array, " points"]
    contact_fraction: Float[Array, " points"]
    plastic_fraction: Float[Array, " points"]
    branch: Int[Array, " points"]
    status: Int[Array, " points"]
    iterations: Int[Array, " points"]
    residual_approach: Float[Array, ""]
    heights: Float[Array, "n n"]


def solve_path(
    heights: Float[ArrayLike, "n n"],
    size,
    modulus,
    path: Float[ArrayLike, " points"],
    *,
    hardness=None,
    substrate: AbstractSubstrate = Periodic(),
    tolerance: float | None = None,
    max_iterations: int = 2000,
    preconditioned: bool = True,
    fft: AbstractFFT = LocalFFT(),
) -> PathSolution:
    """The boundary-element contact along a load path, the plastic flattening kept (module docstring).

    **Arguments:**

    - `heights`, `size`, `modulus`, `hardness`, `substrate`, `tolerance`, `max_iterations`,
      `preconditioned`, `fft`: as `bem.solve`; `hardness` None is the elastic contact, where every branch
      retraces the loading one.
    - `path`: total normal loads, N, a 1-D array in the order applied (any sequence: load, unload,
      reload, ...).

    **Returns:** a `PathSolution`. Differentiable (`jax.grad`, `jax.jvp`) with respect to the
    heights, `modulus`, `hardness` and the loads by the implicit rule of `bem.solve`, through the
    flattening of every earlier point; `vmap` over maps works. A traced NaN or non-positive load is
    flagged `INVALID_LOAD` and leaves the surface as it was.

    **Raises:** `ValueError` as `bem.solve`.
    """
    check_strategy("substrate", substrate, AbstractSubstrate, SUBSTRATES, "bem")
    check_arguments(heights, size, modulus, path, hardness, loads_name="path")
    check_iteration(tolerance, max_iterations)
    check_fft(fft, np.shape(heights)[-1])
    if not isinstance(preconditioned, bool):
        raise InputError(f"preconditioned = {preconditioned!r} must be true or false")
    dtype = jnp.result_type(heights, path, 1.0)
    if tolerance is None:
        tolerance = DEFAULT_TOLERANCE.get(np.dtype(dtype), 1e-5)
    arrays = tuple(jnp.asarray(x, dtype) for x in (heights, size, modulus, path))
    cap = None if hardness is None else jnp.asarray(hardness, dtype)
    return _solve_path(*arrays, cap, substrate, float(tolerance), int(max_iterations), preconditioned, fft)


def solve_path_grid(
    heights, size, modulus, path, hardness, substrate, tolerance, max_iterations, pc, fft=LocalFFT()
) -> PathSolution:
    """`solve_path` on arrays of one dtype with its settings checked, traceable (the BEM model's path)."""
    sound, heights, size, modulus, hardness = valid_problem(heights, size, modulus, hardness)
    problem = GridProblem.build(heights, size, modulus, hardness, substrate, pc, None, fft)
    loads, valid = stand_in_loads(path, 1e-4 * modulus * size * size)
    kinds = branches(jnp.where(valid, path, 0.0))

    def one(carry, inputs):
        flattened, previous, previous_total = carry
        total, usable, kind = inputs
        now = eqx.tree_at(lambda p: p.heights, problem, flattened)
        # Mostly from the last point's pressure scaled to this load: a path's neighbours share most
        # of their contact set, on unloading as on loading.
        start = warm_start(now, previous, previous_total, total, 0.9)
        out = contact_at(now, total, start, tolerance, max_iterations)
        at_cap = out["found"] >= now.cap
        plastic = at_cap & usable
        gap = now.compliance(out["pressure"]) - flattened - out["offset"]
        flattened = flattened + jnp.where(plastic, jnp.minimum(gap, 0.0), 0.0)
        # With nothing at the cap the contact set is the solve's own elastic set, whose tangent it
        # has: a second linear solve is needed only where points flow.
        elastic = jax.lax.cond(
            jnp.any(at_cap),
            lambda: elastic_stiffness(now.compliance, out["found"] > 0, tolerance),
            lambda: out["stiffness"],
        )
        stiffness = jnp.where(kind == Branch.LOADING, out["stiffness"], elastic)
        found = jnp.where(usable, out["found"], previous)
        point = dict(
            offset=out["offset"],
            stiffness=stiffness,
            unloading=elastic,
            contact_fraction=out["contact_fraction"],
            plastic_fraction=out["plastic_fraction"],
            iterations=out["iterations"],
            status=out["status"],
        )
        return (flattened, found, jnp.where(usable, total, previous_total)), point

    initial = (problem.heights, jnp.zeros_like(problem.heights), jnp.zeros((), heights.dtype))
    (flattened, _, _), out = jax.lax.scan(one, initial, (loads / problem.load_unit, valid, kinds))
    status = jnp.where(valid, out["status"], Status.INVALID_LOAD)
    status = jnp.where(sound, status, Status.INVALID_PARAMETERS)
    status = checked_status(status, (out["stiffness"], out["unloading"]), (out["offset"],))
    ok = status == Status.OK
    unit, scale = problem.stiffness_unit, problem.scale
    approach = (out["offset"] - out["offset"][0]) * scale
    residual = (jnp.max(problem.heights) - jnp.max(flattened)) * scale
    return PathSolution(
        loads=path,
        approach=jnp.where(ok & ok[0], approach, jnp.nan),
        stiffness=jnp.where(ok, out["stiffness"] * unit, jnp.nan),
        unloading_stiffness=jnp.where(ok, out["unloading"] * unit, jnp.nan),
        contact_fraction=jnp.where(sound, out["contact_fraction"], jnp.nan),
        plastic_fraction=jnp.where(sound, out["plastic_fraction"], jnp.nan),
        branch=kinds,
        status=status,
        iterations=out["iterations"],
        residual_approach=jnp.where(sound & jnp.all(ok), residual, jnp.nan),
        heights=jnp.where(sound, flattened * scale, jnp.nan),
    )


_solve_path = eqx.filter_jit(solve_path_grid)
