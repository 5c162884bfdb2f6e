"""The fit's residuals: log stiffness of the model against the data, in statistical coordinates.

`r_i = ln K_model(F_i; θ) - ln K_i`. Data points that the model cannot evaluate at a trial θ
(interaction breakdown, load out of range) contribute a constant residual `FLAGGED_RESIDUAL` with
no gradient, so that no start can win by pushing points out of the model; points where it gives
K = 0 (every spot plastic) contribute `ZERO_STIFFNESS_RESIDUAL`, worse than any real misfit.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

import jaxcontact as jc
from jaxcontact import programs

from ._parameters import with_stat

FLAGGED_RESIDUAL = 1.0  # a miss by a factor e in stiffness
# A valid point where the model says K = 0 (every spot plastic) against a measured K > 0 misses by
# an infinite factor; this stands for it, worse than any misfit a model of the data could have, so
# that no start wins by making the stiffness vanish.
ZERO_STIFFNESS_RESIDUAL = 50.0


def log_residuals(stat, scene, params, loads, log_stiffness):
    """`(r, ok)`: log-stiffness residuals at statistical coordinates `stat`, and the valid mask."""
    r, ok, _ = residuals_and_status(stat, scene, params, loads, log_stiffness)
    return r, ok


# The fit reads the stiffness and the status alone.
_OUTPUTS = jc.Outputs(regime_shares=False)


def residuals_and_status(stat, scene, params, loads, log_stiffness):
    sol = jc.solve(with_stat(scene, params, stat), loads, outputs=_OUTPUTS)
    ok = sol.ok & (sol.stiffness > 0)
    K = jnp.where(ok, sol.stiffness, 1.0)  # no log of NaN or 0: no NaN in any gradient
    missed = jnp.where(sol.fully_plastic, ZERO_STIFFNESS_RESIDUAL, FLAGGED_RESIDUAL)
    return jnp.where(ok, jnp.log(K) - log_stiffness, missed), ok, sol.status


def residuals_and_jacobian(stat, scene, params, loads, log_stiffness):
    """Residuals, valid mask, status and d(residual)/d(stat) at `stat`: the fit's one compiled
    program (per scene structure, fitted parameters, dtype and number of points), which the
    optimisers, the statistics and the rival-optimum check share.

    `scene` must have array leaves of one dtype (`jaxcontact.core.prepare`).
    """
    leaves, treedef = jax.tree_util.tree_flatten(scene)
    args = (np.asarray(stat, loads.dtype), leaves, loads, log_stiffness)
    key = (treedef, params, tuple((x.shape, x.dtype) for x in jax.tree_util.tree_leaves(args)))
    if key not in _PROGRAMS:

        def flat(stat, leaves, loads, log_stiffness):
            scene = jax.tree_util.tree_unflatten(treedef, leaves)

            def residuals(s):
                r, ok, status = residuals_and_status(s, scene, params, loads, log_stiffness)
                return r, (r, ok, status)

            J, (r, ok, status) = jax.jacfwd(residuals, has_aux=True)(stat)
            return r, ok, status, J

        static = f"fitting {[p.name for p in params]}"
        _PROGRAMS[key] = programs.program("residuals_and_jacobian", static, flat, args, closed_over=(treedef,))
    return _PROGRAMS[key](*args)


# Built programs, by scene structure, fitted parameters and argument shapes.
_PROGRAMS: dict = {}
