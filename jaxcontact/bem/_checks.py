"""The boundary-element solve's arguments: checked where concrete (`ValueError`), and where traced
replaced by a solvable stand-in and flagged (`valid_problem`, `stand_in_loads`); a point's status
made honest (`checked_status`)."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from ..numerics._validate import InputError, assigned, check_range, concrete
from ..quantities import Status

SMALLEST_GRID = 8
# Looser, the iteration stops before the contact set settles: on a 256² rough surface at 2-95 %
# contact the tangent is within 1.4e-4 of a converged solve at 1e-5, 2.8e-3 at 1e-4, 2.5e-2 at 1e-3.
MAX_TOLERANCE = 1e-5


def check_arguments(heights, size, modulus, loads, hardness, loads_name: str = "loads") -> None:
    """`ValueError` for concrete arguments a solve cannot take; `loads_name` names the loads argument."""
    shape = jnp.shape(heights)
    if len(shape) != 2 or shape[0] != shape[1]:
        raise InputError(f"heights has shape {shape}: the boundary-element solve takes a square map (n × n)")
    if shape[0] < SMALLEST_GRID:
        raise InputError(f"heights is {shape[0]} × {shape[1]}: at least {SMALLEST_GRID} points a side are needed")
    if not jnp.issubdtype(jnp.result_type(heights), jnp.floating):
        raise InputError(f"heights has dtype {jnp.result_type(heights)}: give real heights (m), a float array")
    finite, spread, span = _summary(heights)
    if finite is not None and not finite:
        raise InputError("heights has NaN or infinite values: give a map of finite heights (m)")
    if spread is not None and not np.isfinite(spread):
        raise InputError(f"heights spans {span:.3g} m, beyond the working precision's range: give heights in metres")
    check_range("size", size, 0.0, meaning="side length, m")
    check_range("modulus", modulus, 0.0, meaning="contact modulus, Pa")
    if hardness is not None:
        check_range("hardness", hardness, 0.0, meaning="Pa")
    if jnp.ndim(loads) != 1 or jnp.shape(loads)[0] == 0:
        raise InputError(f"{assigned(loads_name, repr(jnp.shape(loads)))} must be a non-empty 1-D array of loads (N)")
    check_range(loads_name, loads, 0.0, meaning="N")


def _summary(heights):
    """Whether every height is finite, their standard deviation and their span; None while traced.
    On the host, in float64; on the devices for a map spread over several processes (`jax.distributed`),
    which no one process holds whole."""
    if isinstance(heights, jax.core.Tracer):
        return None, None, None
    if isinstance(heights, jax.Array) and not heights.is_fully_addressable:
        return tuple(x.item() for x in _device_summary(heights))
    values = concrete(heights)
    with np.errstate(over="ignore"):
        return bool(np.all(np.isfinite(values))), np.std(values), np.ptp(values)


@jax.jit
def _device_summary(heights):
    return jnp.all(jnp.isfinite(heights)), jnp.std(heights), jnp.ptp(heights)


def check_iteration(tolerance, max_iterations) -> None:
    """The constrained iteration's settings (`solve`, `BEM`); None is the precision's default."""
    if tolerance is not None:
        check_range("tolerance", tolerance, 0.0, MAX_TOLERANCE, high_open=False, meaning="fraction of the rms height")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, (int, np.integer)) or max_iterations < 1:
        raise InputError(f"max_iterations = {max_iterations!r} must be an integer >= 1")


def valid_problem(heights, size, modulus, hardness):
    """Whether traced arguments are a solvable problem (finite heights whose rms is representable,
    positive finite size, modulus and hardness), and stand-ins where they are not: a flat map in unit
    size and modulus, solved like any other and then flagged, so that the batch's other maps keep
    finite values and gradients."""
    rms = jax.lax.stop_gradient(jnp.std(heights))
    ok = jnp.all(jnp.isfinite(heights)) & jnp.isfinite(rms)
    for value in (size, modulus) + (() if hardness is None else (hardness,)):
        ok &= jnp.isfinite(value) & (value > 0)
    heights = jnp.where(ok, heights, 0.0)
    size, modulus = jnp.where(ok, size, 1.0), jnp.where(ok, modulus, 1.0)
    hardness = None if hardness is None else jnp.where(ok, hardness, 1.0)
    return ok, heights, size, modulus, hardness


def checked_status(status, stiffnesses, finite=()):
    """`status` with each OK point whose `stiffnesses` are not finite and positive, or whose other
    values `finite` are not finite, made `NOT_CONVERGED`: a number with status OK is a number."""
    good = jnp.ones(jnp.shape(status), bool)
    for value in stiffnesses:
        good &= jnp.isfinite(value) & (value > 0)
    for value in finite:
        good &= jnp.isfinite(value)
    return jnp.where((status == Status.OK) & ~good, Status.NOT_CONVERGED, status)


def stand_in_loads(loads, default):
    """The loads with every NaN or non-positive one replaced by the geometric mean of the valid ones
    (`default` if none is): solved like the others, then flagged."""
    valid = jnp.isfinite(loads) & (loads > 0)
    mean = jnp.exp(jnp.mean(jnp.log(jnp.where(valid, loads, 1.0)), where=valid))
    return jnp.where(valid, loads, jnp.where(jnp.any(valid), mean, default)), valid
