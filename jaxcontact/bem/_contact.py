"""The boundary-element K(F) of a height map in JAX: jit-compiled, vmappable, exactly differentiable.

`solve(heights, size, modulus, loads)` presses a rigid flat on an elastic half-space with the map's
heights (or, equivalently, the rough rigid surface on a flat one), frictionless and non-adhesive,
under load control, optionally with the pressure capped at a hardness; docs/model.md §10.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float, Int

from ..models import CLOSED_INTERFACE
from ..numerics._validate import check_range, check_strategy
from ..quantities import Status
from ._ccg import contact_cg
from ._checks import check_arguments, check_iteration, checked_status, stand_in_loads, valid_problem
from ._fft import AbstractFFT, LocalFFT, check_fft
from ._operator import SUBSTRATES, AbstractSubstrate, Periodic
from ._problem import GridProblem
from ._solver import secant_stiffness
from ._tangent import elastic_stiffness, frozen_solution

# The iteration stops when every gap condition holds to this fraction of the heights' rms.
DEFAULT_TOLERANCE = {np.dtype(np.float64): 1e-9, np.dtype(np.float32): 1e-5}
# A load within this ratio of the last (a secant's other side) starts mostly from its pressure.
_CLOSE_RATIO = 1.1


class ContactSolution(eqx.Module):
    """The boundary-element contact at each load (leading axis: the loads, in the order given).

    **Fields:** `loads` (N); `stiffness` (N/m), the exact tangent `dF/dδ` of the discretised contact
    (NaN unless `status == 0`); `secant_stiffness` (N/m) `2F sinh(ε) / (δ(F e^ε) − δ(F e^−ε))` where
    asked for (`secant=ε`), else None; `offset` δ (m), the rigid approach (its zero is arbitrary for a
    periodic half-space); `contact_fraction` (A_r/A_a, elastic and plastic points); `plastic_fraction`;
    `mean_gap` (m), the mean separation of the two surfaces; `status` (`jaxcontact.Status`: OK,
    NOT_CONVERGED, LOAD_OUT_OF_RANGE for a closed interface or a load beyond `hardness × area`,
    INVALID_LOAD); `iterations` of the constrained conjugate gradients (all solves of the load);
    `pressure` (Pa, loads × n × n)
    where asked for, else None; `tangential_stiffness` (N/m) where `poisson` is given, else None:
    the full-stick tangential stiffness along the rows on the contact set (`_tangential`).
    """

    loads: Float[Array, " loads"]
    stiffness: Float[Array, " loads"]
    secant_stiffness: Float[Array, " loads"] | None
    offset: Float[Array, " loads"]
    contact_fraction: Float[Array, " loads"]
    plastic_fraction: Float[Array, " loads"]
    mean_gap: Float[Array, " loads"]
    status: Int[Array, " loads"]
    iterations: Int[Array, " loads"]
    pressure: Float[Array, "loads n n"] | None
    tangential_stiffness: Float[Array, " loads"] | None = None


def solve(
    heights: Float[ArrayLike, "n n"],
    size,
    modulus,
    loads: Float[ArrayLike, " loads"],
    *,
    hardness=None,
    poisson=None,
    substrate: AbstractSubstrate = Periodic(),
    tolerance: float | None = None,
    max_iterations: int = 2000,
    pressure: bool = False,
    secant: float = 0.0,
    preconditioned: bool = True,
    fft: AbstractFFT = LocalFFT(),
) -> ContactSolution:
    """The boundary-element contact of a rough surface at each load (docs/model.md §10).

    **Arguments:**

    - `heights`: the surface's heights, m, an n × n array (rows along x), spacing `size / n`.
    - `size`: the side length L, m (the nominal area is L²).
    - `modulus`: the contact modulus E* = E/(1 − ν²) of the pair, Pa.
    - `loads`: total normal loads, N, a 1-D array (solved in increasing order, each from the last
      one's pressure, and returned in the order given).
    - `hardness`: None (elastic), or the pressure cap H, Pa (perfectly plastic points flow at H).
    - `poisson`: None, or Poisson's ratio ν in [0, 0.5) of two bodies of like material: also return
      the tangential stiffness in full stick, every point in contact (plastic ones too) displaced
      along the rows with the rigid body (the uncoupled tangential problem, docs/in-service.md).
    - `substrate`: `Periodic()` (the map repeats; ContactMechanics's `stiffness_q0 = 0`) or `Free()`
      (an isolated map on an infinite half-space; the grid is doubled internally).
    - `tolerance`: on every gap condition, as a fraction of the heights' rms, in (0, 1e-5] (default
      1e-9 in float64, 1e-5 in float32); `max_iterations` (≥ 1) of the constrained conjugate
      gradients.
    - `pressure`: also return the pressure field at each load.
    - `secant`: ε > 0 also solves at `F e^(±ε)` and returns the secant stiffness over them
      (ContactMechanics's reference takes ε = 0.02), which varies smoothly with the heights.
    - `preconditioned`: search along the Fourier-preconditioned gap (`_ccg`; the same solution to
      the tolerance in a fraction of the iterations, nearly independent of the grid), or, False,
      Polonsky & Keer's plain iteration.
    - `fft`: `LocalFFT()` (the FFTs where the heights are), or `DistributedFFT(mesh, axis)`: the map's
      rows split over the devices along `axis` of a `jax.sharding.Mesh` and a distributed FFT (two
      all-to-all exchanges, nothing gathered), for maps too large for one device (n a multiple of
      the device count). The pressure comes back split so.

    **Returns:** a `ContactSolution`. Differentiable (`jax.grad`, `jax.jvp`) with respect to the
    heights, `modulus`, `hardness` and the loads, by implicit differentiation on the contact set
    (`_tangent`); `vmap` over maps works. The tangent stiffness is exact for the discretised
    contact and is piecewise constant in the heights and the load (it changes only where a grid
    point enters or leaves contact): its derivative with respect to them is zero almost
    everywhere; the offset, the mean gap and a secant stiffness between two loads vary smoothly.

    Traced arguments (under `jit`, `vmap`, `grad`) cannot raise: a map with non-finite heights, or a
    non-finite or non-positive size, modulus or hardness gives `INVALID_PARAMETERS` at every load
    (NaN values, zero derivatives), and the other maps of a `vmap` are solved as usual.

    **Raises:** `ValueError` for a map that is not square, not finite or smaller than 8 × 8, for
    non-positive size, modulus, hardness or concrete loads, and for a tolerance outside (0, 1e-5] or
    `max_iterations` < 1.
    """
    check_strategy("substrate", substrate, AbstractSubstrate, SUBSTRATES, "bem")
    check_arguments(heights, size, modulus, loads, hardness)
    check_fft(fft, np.shape(heights)[-1])
    check_iteration(tolerance, max_iterations)
    dtype = jnp.result_type(heights, loads, 1.0)
    if tolerance is None:
        tolerance = DEFAULT_TOLERANCE.get(np.dtype(dtype), 1e-5)
    arrays = tuple(jnp.asarray(x, dtype) for x in (heights, size, modulus, loads))
    cap = None if hardness is None else jnp.asarray(hardness, dtype)
    nu = None
    if poisson is not None:
        check_range("poisson", poisson, 0.0, 0.5, low_open=False, meaning="Poisson's ratio of like materials")
        nu = jnp.asarray(poisson, dtype)
    check_range("secant", secant, 0.0, 0.5, low_open=False)
    settings = (float(tolerance), int(max_iterations), bool(pressure), float(secant), bool(preconditioned))
    return _solve(*arrays, cap, nu, substrate, fft, *settings)


def contact_at(problem: GridProblem, total, start, tolerance: float, max_iterations: int) -> dict:
    """The contact at the load `total` (grid units) from the pressure `start`: the constrained
    iteration finds the contact set (never differentiated), `frozen_solution` the differentiable
    solution on it. A dict of grid-unit outputs, the pressure among them."""
    state = contact_cg(
        problem.compliance,
        jax.lax.stop_gradient(problem.heights),
        jax.lax.stop_gradient(total),
        jax.lax.stop_gradient(problem.cap),
        jax.lax.stop_gradient(start),
        tolerance,
        max_iterations,
        problem.capped,
        problem.preconditioned,
    )
    found = state.pressure
    active, plastic = (found > 0) & (found < problem.cap), found >= problem.cap
    closed = jnp.mean(found > 0) >= CLOSED_INTERFACE
    # A closed interface (C on every point is singular: the periodic q = 0 mode) or one with no
    # elastic point (the tangent is 0) has no linear problem to differentiate: solve a finite stand-in
    # (the highest point alone) with the inputs held, so that the flagged load's zero cotangent
    # stays zero and never multiplies an infinite partial.
    degenerate = closed | ~jnp.any(active)
    highest = jnp.arange(found.size).reshape(found.shape) == jnp.argmax(problem.heights)
    active, plastic = jnp.where(degenerate, highest, active), plastic & ~degenerate
    held = lambda x: jnp.where(degenerate, jax.lax.stop_gradient(x), x)  # noqa: E731
    heights, total_in, cap = held(problem.heights), held(total), held(problem.cap)
    pressure, offset, stiffness = frozen_solution(
        problem.compliance, heights, total_in, cap, active, plastic, found, state.offset, tolerance
    )
    gap = problem.compliance(pressure) - heights - offset
    extra = {}
    if problem.tangential is not None:
        contact = jnp.where(degenerate, highest, found > 0)
        extra["tangential_stiffness"] = elastic_stiffness(problem.tangential, contact, tolerance)
    return dict(
        **extra,
        pressure=pressure,
        found=jax.lax.stop_gradient(found),
        offset=offset,
        stiffness=stiffness,
        # In the working dtype: JAX's mean of a bool is float32 whatever x64 says.
        contact_fraction=jnp.mean(found > 0, dtype=found.dtype),
        plastic_fraction=jnp.mean(plastic, dtype=found.dtype),
        mean_gap=jnp.mean(jnp.maximum(gap, 0.0)),
        iterations=state.iterations,
        status=jnp.select(
            [degenerate | (total >= problem.cap * problem.heights.size), ~state.converged],
            [Status.LOAD_OUT_OF_RANGE, Status.NOT_CONVERGED],
            Status.OK,
        ).astype(jnp.int32),
    )


def warm_start(problem: GridProblem, previous, previous_total, total, weight):
    """The pressure a load's iteration starts from: the last load's, scaled to this one, blended
    with a uniform pressure (`weight` of the former); the uniform one alone before any load."""
    uniform = jnp.full_like(problem.heights, total / problem.heights.size)
    ratio = total / jnp.where(previous_total > 0, previous_total, 1.0)
    return jnp.where(previous_total > 0, weight * previous * ratio + (1 - weight) * uniform, uniform)


def sweep(problem: GridProblem, totals, tolerance: float, max_iterations: int, with_pressure: bool = False) -> dict:
    """`contact_at` at every load of `totals` (grid units, positive), solved in increasing order,
    each from the last one's pressure; the outputs in the order given (a leading loads axis)."""
    order = jnp.argsort(totals)

    def one(carry, total):
        previous, previous_total = carry
        # Every point starts in contact (the iteration sheds contact faster than it grows it), near
        # the last load's shape: half its pressure scaled to this load and half uniform, or from a
        # load within `_CLOSE_RATIO` (the secant's other side, whose contact set is nearly this one's)
        # 95 % the scaled pressure.
        close = total < _CLOSE_RATIO * previous_total
        start = warm_start(problem, previous, previous_total, total, jnp.where(close, 0.95, 0.5))
        out = contact_at(problem, total, start, tolerance, max_iterations)
        found = out.pop("found")
        if not with_pressure:
            del out["pressure"]
        return (found, total), out

    initial = (jnp.zeros_like(problem.heights), jnp.zeros((), problem.heights.dtype))
    _, outputs = jax.lax.scan(one, initial, totals[order])
    inverse = jnp.argsort(order)
    return {k: v[inverse] for k, v in outputs.items()}


def sweep_sides(problem: GridProblem, loads, sides, tolerance: float, max_iterations: int, with_pressure=False):
    """`sweep` at each of `loads` (SI, or F* in a dimensionless problem) times `e^side` for each of
    `sides`, all in one sweep: the outputs with leading axes (sides, loads)."""
    totals = jnp.concatenate([loads * math.exp(side) for side in sides]) / problem.load_unit
    outputs = sweep(problem, totals, tolerance, max_iterations, with_pressure)
    return {k: v.reshape(len(sides), -1, *v.shape[1:]) for k, v in outputs.items()}


@eqx.filter_jit
def _solve(
    heights, size, modulus, loads, hardness, nu, substrate, fft, tolerance, max_iterations, with_pressure, step, pc
):
    sound, heights, size, modulus, hardness = valid_problem(heights, size, modulus, hardness)
    if nu is not None:
        sound &= (nu >= 0) & (nu < 0.5)
        nu = jnp.where(sound, nu, 0.3)
    problem = GridProblem.build(heights, size, modulus, hardness, substrate, pc, nu, fft)
    solved, valid = stand_in_loads(loads, 1e-4 * modulus * size * size)
    sides = (-step, 0.0, step) if step > 0 else (0.0,)
    # Each load and, for the secant, its neighbours e^(±step) F.
    side = sweep_sides(problem, solved, sides, tolerance, max_iterations, with_pressure)
    out = {k: v[len(sides) // 2] for k, v in side.items()}
    status = jnp.where(valid, out["status"], Status.INVALID_LOAD)
    status = jnp.where(sound, status, Status.INVALID_PARAMETERS)
    secant = None
    if step > 0:
        status = jnp.where(status == Status.OK, jnp.max(side["status"], axis=0), status)
        rise = jnp.where(status == Status.OK, side["offset"][2] - side["offset"][0], 1.0)
        secant = secant_stiffness(loads, step, rise * problem.scale)
    tangential = out.get("tangential_stiffness")
    stiffnesses = tuple(k for k in (out["stiffness"], secant, tangential) if k is not None)
    status = checked_status(status, stiffnesses, (out["offset"],))
    ok = status == Status.OK
    return ContactSolution(
        loads=loads,
        stiffness=jnp.where(ok, out["stiffness"] * problem.stiffness_unit, jnp.nan),
        secant_stiffness=None if secant is None else jnp.where(ok, secant, jnp.nan),
        offset=jnp.where(ok, out["offset"] * problem.scale, jnp.nan),
        contact_fraction=jnp.where(sound, out["contact_fraction"], jnp.nan),
        plastic_fraction=jnp.where(sound, out["plastic_fraction"], jnp.nan),
        mean_gap=jnp.where(ok, out["mean_gap"] * problem.scale, jnp.nan),
        status=status,
        iterations=jnp.sum(side["iterations"], axis=0),
        pressure=out["pressure"] * (problem.load_unit / (size / heights.shape[0]) ** 2) if with_pressure else None,
        tangential_stiffness=None if nu is None else jnp.where(ok, tangential * problem.stiffness_unit, jnp.nan),
    )
