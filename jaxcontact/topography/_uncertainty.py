"""The stiffness curve of a characterised surface, with the band its (D, G) uncertainty gives."""

from __future__ import annotations

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from scipy import stats

from ..core import solve
from ..numerics import InputError
from ..quantities import Surface


@dataclasses.dataclass(frozen=True)
class StiffnessBand:
    """K(F) (N/m) at the characterised (D, G), and its 95 % band (`lower`, `upper`), per load;
    `status` as `jaxcontact.solve` gives it."""

    load: np.ndarray
    stiffness: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    status: np.ndarray


def _log_stiffness(moved, loads):
    """`x ↦ (ln K at loads of the scene `moved(x)`, its solution)`, for `jax.jacfwd(has_aux=True)`."""

    def log_stiffness(x):
        solution = solve(moved(x), loads)
        # K = 0 (every spot plastic) has no logarithm; its band is [0, 0].
        usable = solution.ok & (solution.stiffness > 0)
        return jnp.log(jnp.where(usable, solution.stiffness, 1.0)), solution

    return log_stiffness


def _band(loads, solution, spread) -> StiffnessBand:
    """K at the solution's points with the band `K e^(±spread)` (K = 0: [0, 0]; flagged: NaN)."""
    ok = np.asarray(solution.ok)
    K = np.where(ok, np.asarray(solution.stiffness), np.nan)
    spread = np.where(K > 0, spread, 0.0)
    return StiffnessBand(
        load=loads,
        stiffness=K,
        lower=np.where(ok, K * np.exp(-spread), np.nan),
        upper=np.where(ok, K * np.exp(spread), np.nan),
        status=np.asarray(solution.status),
    )


def stiffness_band(characterisation, scene, loads) -> StiffnessBand:
    """K(F) on `scene` with its surface replaced by the characterised one, and a 95 % band.

    The band is the delta method: `var ln K = ∇ᵀ Σ ∇`, with `Σ` the covariance of (D, ln G) from
    the characterisation and `∇` the gradient of ln K with respect to (D, ln G) by forward-mode
    differentiation through the solve; `ln K ± t·sd` with the Student-t quantile of its `dof`.

    **Arguments:** `characterisation` (from `characterise`), `scene` (material, area and model),
    `loads` (N). **Returns:** a `StiffnessBand`.
    """
    surface = characterisation.surface
    scene = eqx.tree_at(lambda s: s.surface, scene, Surface(D=surface.D, G=surface.G, l_min=surface.l_min))
    loads = np.asarray(loads, dtype=float)
    dtype = jnp.result_type(1.0)

    log_stiffness = _log_stiffness(
        lambda theta: eqx.tree_at(lambda s: (s.surface.D, s.surface.G), scene, (theta[0], jnp.exp(theta[1]))), loads
    )
    theta = jnp.asarray([characterisation.D, np.log(characterisation.G)], dtype)
    gradient, solution = jax.jacfwd(log_stiffness, has_aux=True)(theta)
    variance = jnp.einsum("ni,ij,nj->n", gradient, jnp.asarray(characterisation.covariance, dtype), gradient)
    spread = stats.t.ppf(0.975, characterisation.dof) * np.sqrt(np.maximum(np.asarray(variance), 0.0))
    return _band(loads, solution, spread)


def spectrum_band(scene, loads) -> StiffnessBand:
    """K(F) on `scene`, whose model solves on a `MeasuredSpectrum` with a `variance`, and a 95 % band
    from the table's own uncertainty.

    The delta method over the bins, taken as independent: `var ln K = Σ_i (∂ ln K/∂ ln C_i)² var_i`,
    the derivatives by forward-mode differentiation through the solve; `ln K ± 1.96 sd`.

    **Arguments:** `scene` (its model's `spectrum` has a `variance`), `loads` (N).
    **Returns:** a `StiffnessBand`. **Raises:** `ValueError` for a model without such a spectrum.
    """
    spectrum = getattr(scene.model, "spectrum", None)
    if spectrum is None or spectrum.variance is None:
        raise InputError(
            f"model = {scene.model.name!r} has no measured spectrum with a variance: give it "
            "spectrum=MeasuredSpectrum.from_characterisation(c)"
        )
    loads = np.asarray(loads, dtype=float)

    log_stiffness = _log_stiffness(lambda log_C: eqx.tree_at(lambda s: s.model.spectrum.log_C, scene, log_C), loads)
    gradient, solution = jax.jacfwd(log_stiffness, has_aux=True)(spectrum.log_C)
    # A bin without modes (infinite variance) that K does not depend on adds nothing.
    weights = jnp.where(gradient != 0, gradient**2 * spectrum.variance, 0.0)
    spread = 1.959963984540054 * np.sqrt(np.asarray(jnp.sum(weights, axis=-1)))
    return _band(loads, solution, spread)
