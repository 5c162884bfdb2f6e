"""The fit's residuals: the model against the data, in statistical coordinates.

Each observable (`_observables`: the stiffness, the approach) is a column of `Observations.targets`,
divided by its noise σ (`Observations.weights` = 1/σ), so that a curve of both is one least-squares
problem. A target that is NaN was not measured: its residual is 0 and it is left out of every count.
"""

from __future__ import annotations

from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from jaxcontact import programs
from jaxcontact.numerics import register_cache

from ._observables import AbstractObservable, Stiffness
from ._parameters import with_stat


class Observations(eqx.Module):
    """What a fit compares the model with, padded (the caller cuts the padding off).

    `loads` (N); `targets` (load, column): ln K and/or δ − δ(F0) (m), NaN where not measured;
    `weights` (column): 1/σ; `flagged` (column): the residual of a point outside the model, in the
    column's units before weighting; `reference_load` F0 (N) of the approach; `columns`: the
    `AbstractObservable` of each column (static).
    """

    loads: Float[Array, " points"]
    targets: Float[Array, "points columns"]
    weights: Float[Array, " columns"]
    flagged: Float[Array, " columns"]
    reference_load: Float[Array, ""]
    columns: tuple[AbstractObservable, ...] = eqx.field(static=True)

    @property
    def measured(self) -> np.ndarray:
        return np.isfinite(np.asarray(self.targets))


def stiffness_curve(loads, log_stiffness) -> Observations:
    """A stiffness curve as observations, σ = 1 in ln K (traceable: `log_residuals` builds one inside a
    caller's trace, where `observations`' checks on the host cannot run)."""
    loads, log_stiffness = jnp.asarray(loads), jnp.asarray(log_stiffness)
    return Observations(
        loads=loads,
        targets=log_stiffness[:, None],
        weights=jnp.ones(1, loads.dtype),
        flagged=jnp.full(1, Stiffness().flagged(log_stiffness), loads.dtype),
        reference_load=jnp.min(loads),
        columns=(Stiffness(),),
    )


def log_residuals(stat, scene, params, loads, log_stiffness):
    """`(r, ok)`: log-stiffness residuals at statistical coordinates `stat`, and the valid mask."""
    r, ok, _ = observed_residuals(stat, scene, params, stiffness_curve(loads, log_stiffness))
    return r[:, 0], ok[:, 0]


def observed_residuals(stat, scene, params, data: Observations):
    """`(r, ok, status)`, each (load, column): weighted residuals (0 where not measured), the model's
    valid mask and its status, at statistical coordinates `stat`."""
    scene = with_stat(scene, params, stat)
    rows = []
    for k, column in enumerate(data.columns):
        target = jnp.where(jnp.isnan(data.targets[:, k]), 0.0, data.targets[:, k])
        rows.append(column.residuals(scene, data.loads, target, data.flagged[k], data.reference_load))
    r, ok, status = (jnp.stack(x, axis=1) for x in zip(*rows))
    r = jnp.where(jnp.isnan(data.targets), 0.0, r * data.weights)
    return r, ok, status


def linearised_residuals(stat, scene, params, data: Observations):
    """`(r, ok, status, J)`: `observed_residuals` at `stat` and their forward-mode Jacobian `∂r/∂stat`
    over the few parameters, as a JAX function (the fit's compiled program and the batch's misfit)."""

    def residuals(s):
        r, ok, status = observed_residuals(s, scene, params, data)
        return r, (r, ok, status)

    J, (r, ok, status) = jax.jacfwd(residuals, has_aux=True)(stat)
    return r, ok, status, J


def residuals_and_jacobian(stat, scene, params, data: Observations):
    """Residuals, valid mask, status (each (load, column)) and d(residual)/d(stat) at `stat`: the fit's
    one compiled program (per scene structure, fitted parameters, observables, dtype and number of
    points), which the optimisers, the statistics and the rival-optimum check share.

    `scene` must have array leaves of one dtype (`jaxcontact.core.prepare`).
    """
    return bound_program(scene, params, data)(stat)


def bound_program(scene, params, data: Observations):
    """`stat ↦ residuals_and_jacobian(stat, scene, params, data)`, the scene and data flattened once:
    an optimiser's hundreds of evaluations of one curve pay for that once."""
    leaves, treedef = jax.tree_util.tree_flatten(scene)
    data_leaves, data_def = jax.tree_util.tree_flatten(data)
    dtype = data.loads.dtype
    shapes = tuple((x.shape, x.dtype) for x in jax.tree_util.tree_leaves((leaves, data_leaves)))
    key = (treedef, data_def, params, dtype, shapes)
    if key not in _PROGRAMS:

        def flat(stat, leaves, data_leaves):
            scene = jax.tree_util.tree_unflatten(treedef, leaves)
            return linearised_residuals(stat, scene, params, jax.tree_util.tree_unflatten(data_def, data_leaves))

        static = f"fitting {[p.name for p in params]} {[c.name for c in data.columns]}"
        args = (np.zeros(len(params), dtype), leaves, data_leaves)
        _PROGRAMS[key] = programs.program("residuals_and_jacobian", static, flat, args, closed_over=(treedef, data_def))
    program = _PROGRAMS[key]
    return lambda stat: program(np.asarray(stat, dtype), leaves, data_leaves)


class Evaluated(NamedTuple):
    """`residuals_and_jacobian` at the curve's first `rows` loads, flattened by load (row-major over
    the columns): `r`, `ok`, `status`, `J` (entries, parameters), and `measured`."""

    r: np.ndarray
    ok: np.ndarray
    status: np.ndarray
    J: np.ndarray
    measured: np.ndarray

    @property
    def used(self) -> np.ndarray:
        return self.ok & self.measured


def evaluated(stat, scene, params, data: Observations, rows: int) -> Evaluated:
    return evaluated_by(bound_program(scene, params, data), stat, rows, data.measured[:rows].reshape(-1))


def evaluated_by(program, stat, rows: int, measured: np.ndarray) -> Evaluated:
    """`evaluated` by a `bound_program`, with the curve's `measured` mask (its first `rows` loads)."""
    r, ok, status, J = (np.asarray(x)[:rows] for x in program(stat))
    return Evaluated(r.reshape(-1), ok.reshape(-1), status.reshape(-1), J.reshape(r.size, -1), measured)


# Built programs, by scene structure, fitted parameters, observables and argument shapes.
_PROGRAMS: dict = {}
register_cache(_PROGRAMS.clear)
