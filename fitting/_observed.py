"""What a fit is given, checked and laid out: a stiffness curve K(F), an approach curve δ(F), or both.

Each observable is one column of `Observations.targets` (ln K; δ − δ(F0) in m), NaN where a load
has no value of it, weighted by 1/σ of its noise: stated (`noise`), or for one observable alone
σ = 1 in ln K and the curve's rms in δ (any common scale: the fit's `s²` absorbs it), or for both
together each one's point-to-point scatter (`point_scatter`: its deviation from the straight
line through its neighbours in ln F), which is what weighs one against the other.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from jaxcontact import InputError
from jaxcontact.numerics import float_array

from ._observables import Approach, Stiffness
from ._residuals import Observations
from ._statistics import point_scatter

# Curves are padded to a multiple of this many points (the padding points are cut off before the
# optimiser sees them), so that fits of curves of different lengths and with different fixed
# parameter values (the scene's floats are traced) share one compiled model. A padding point costs
# run time in each of a fit's hundreds of evaluations: a 30-point curve padded to 64 took a quarter
# longer to fit than padded to 32.
POINTS_MULTIPLE = 32
# A scatter estimate of a smooth, noiseless curve is its round-off and curvature: below this share of
# the observable's size (0.1 % of K; 0.1 % of the rms approach) no weight is believed.
_SCATTER_FLOOR = 1e-3


def _padded(values: np.ndarray, multiple: int) -> np.ndarray:
    """`values` (along the first axis), padded to a multiple of `multiple` with copies of the first."""
    return np.concatenate([values, np.repeat(values[:1], -len(values) % multiple, axis=0)])


def _column(name: str, values, size: int) -> np.ndarray:
    values = float_array(name, values).reshape(-1)
    if values.size != size:
        raise InputError(f"loads ({size}) and {name} ({values.size}) differ in length")
    return values


def _stated_noise(noise, columns) -> dict:
    """σ by observable's name from `noise`: a number (the one observable's), or a dict by name."""
    if noise is None:
        return {}
    by_name = {c.name: c for c in columns}
    if not isinstance(noise, dict):
        if len(columns) > 1:
            raise InputError(
                f"noise = {noise!r}: with both observables, give a dict {{'stiffness': σ of ln K, 'approach': σ in m}}"
            )
        noise = {columns[0].name: noise}
    for name, value in noise.items():
        if name not in by_name:
            raise InputError(f"noise: {name!r} is not an observable of this fit (valid: {', '.join(by_name)})")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value > 0):
            raise InputError(f"noise = {value!r} must be > 0 (valid range (0, inf)): {by_name[name].noise_units}")
    return {k: float(v) for k, v in noise.items()}


def observations(loads, stiffness, approach, reference_load, noise, dtype, multiple: int):
    """`(data, loads, stated)`: the padded `Observations`, the loads as given (1-D), and whether every
    σ was stated (then the weighted residuals are in units of the noise)."""
    loads = float_array("loads", loads).reshape(-1)
    if stiffness is None and approach is None:
        raise InputError("stiffness = None and approach = None: give at least one measured curve")
    if not np.all(np.isfinite(loads) & (loads > 0)):
        raise InputError("loads must be positive and finite (valid range (0, inf))")
    columns, values = [], []
    if stiffness is not None:
        columns.append(Stiffness())
        values.append(columns[-1].target(_column("stiffness", stiffness, loads.size)))
    if approach is not None:
        columns.append(Approach())
        delta = columns[-1].target(_column("approach", approach, loads.size))
        F0 = float(np.min(loads) if reference_load is None else reference_load)
        if not (math.isfinite(F0) and F0 > 0):
            raise InputError(f"reference_load = {reference_load!r} must be positive and finite (valid range (0, inf))")
        at_reference = loads == F0
        if np.any(at_reference & np.isfinite(delta) & (delta != 0)):
            raise InputError(
                f"approach at the reference load {F0:.6g} N must be 0 (it is measured relative to that load)"
            )
        values.append(np.where(at_reference, np.nan, delta))  # zero by definition: no information
    else:
        F0 = float(np.min(loads))
    targets = np.stack(values, axis=1)
    if len(columns) == 1:
        missing = np.isnan(targets[:, 0]) & ~((loads == F0) & (approach is not None))
        if missing.any():
            raise InputError(f"{columns[0].name} must be finite at every load when it is the only curve fitted")
    stated = _stated_noise(noise, columns)
    sigma = [stated.get(c.name, _default_sigma(c, loads, targets[:, k], len(columns))) for k, c in enumerate(columns)]
    flagged = [c.flagged(targets[:, k]) for k, c in enumerate(columns)]
    data = Observations(
        loads=jnp.asarray(_padded(loads, multiple), dtype),
        targets=jnp.asarray(_padded(targets, multiple), dtype),
        weights=jnp.asarray(1.0 / np.asarray(sigma), dtype),
        flagged=jnp.asarray(flagged, dtype),
        reference_load=jnp.asarray(F0, dtype),
        columns=tuple(columns),
    )
    return data, loads, len(stated) == len(columns)


def _default_sigma(column, loads, values, n_columns: int) -> float:
    """σ of an observable whose noise was not stated (see the module's docstring)."""
    keep = np.isfinite(values)
    size = column.scale(values)
    if n_columns == 1:
        return size
    scatter = point_scatter(np.log(loads[keep]), values[keep]) if keep.sum() >= 3 else math.nan
    floor = _SCATTER_FLOOR * size
    return max(scatter, floor) if math.isfinite(scatter) else size
