"""One fitting problem: what is fitted (the parameters, in their coordinates), what it is fitted to
(the observables, each with its noise) and what is known besides (a prior). `fit`, `fit_batch` and
`sample` are drivers over it: each builds its problems here, so that each checks its input and lays
it out the same way, and each evaluates it through its one JAX residual function (`misfit`)."""

from __future__ import annotations

import dataclasses

import equinox as eqx
import jax.numpy as jnp
import numpy as np

import jaxcontact as jc
from jaxcontact import InputError
from jaxcontact.core import prepare

from ._misfit import Misfit
from ._observed import observations
from ._parameters import FitParameter, resolve
from ._prior import GaussianPrior, prior_arrays, resolve_prior
from ._residuals import Observations
from ._statistics import inner_bounds


@dataclasses.dataclass(frozen=True)
class Problem:
    """A curve, what is fitted to it, and what is known besides.

    **Fields:** `scene` (what is not fitted, and one start); `params` (the fitted `FitParameter`s,
    narrowed to a `Bounds` prior's range); `prior` (a Gaussian prior in the fit's coordinates, or
    None); `data` (the `Observations`: each observable's column and 1/σ); `loads` (the curve's loads
    as given, 1-D); `stated` (whether every observable's noise was stated, so that the weighted
    residuals are in units of the noise); `traced` (the scene with array leaves, which the compiled
    programs take).
    """

    scene: jc.Scene
    params: tuple[FitParameter, ...]
    prior: GaussianPrior | None
    data: Observations
    loads: np.ndarray
    stated: bool
    traced: jc.Scene = dataclasses.field(repr=False)

    @classmethod
    def of(
        cls,
        loads,
        stiffness,
        scene: jc.Scene,
        params=("D", "G"),
        *,
        approach=None,
        reference_load=None,
        noise=None,
        prior=None,
        multiple: int = 1,
    ) -> Problem:
        """The problem of fitting `params` of `scene` to a curve, as `fitting.fit` takes its arguments
        (`multiple`: the curve padded to a multiple of this many points).

        **Raises:** `InputError` for a curve that cannot determine the parameters: no more measured
        values than parameters, or no more distinct loads than parameters.
        """
        prior_, fitted = resolve_prior(prior, resolve(params))
        data, loads, stated = observations(
            loads, stiffness, approach, reference_load, noise, jnp.result_type(1.0), multiple
        )
        n_values = int(data.measured[: loads.size].sum())
        if n_values <= len(fitted):
            raise InputError(f"{n_values} data points cannot determine {len(fitted)} parameters")
        if np.unique(loads).size <= len(fitted):
            raise InputError(
                f"loads: {np.unique(loads).size} distinct values among {loads.size} points cannot determine "
                f"{len(fitted)} parameters (a curve needs at least {len(fitted) + 1} different loads)"
            )
        return cls(scene, fitted, prior_, data, loads, stated, prepare(scene, loads)[0])

    def own_start(self) -> np.ndarray:
        """The scene's own values (the prior's mean where there is one) in optimiser coordinates, kept
        2 % of each range inside its bounds."""
        stat = np.array([p.to_stat(float(p.get(self.scene))) for p in self.params])
        if self.prior is not None:
            stat[list(self.prior.index)] = self.prior.first_start
        return np.asarray([p.u_from_stat(np.clip(s, *inner_bounds(p))) for p, s in zip(self.params, stat)])

    def starts(self, n: int, seed: int) -> np.ndarray:
        """`n` starts in optimiser coordinates: the scene's own (`own_start`) and a Latin hypercube."""
        return starting_points(self.params, n, seed, include=self.own_start())

    def misfit(self, sigma: float = 1.0) -> Misfit:
        """The problem's JAX residual function at the noise scale `sigma` (its curve's weighted
        residuals over σ, and the prior's): `loss(u)` (½ Σ r² over the curve's entries, r in units
        of σ; its gradient exact, by `jax.grad`: the loss defines no forward-mode derivative, and its
        Gauss–Newton curvature is `evaluate`'s Jacobian), `value_and_grad(u)`, and `evaluate(u)` (residuals, valid mask,
        statuses and Jacobians), in optimiser coordinates `u`; `fit_batch` and `sample` run on it,
        and any JAX optimiser can (it is an `eqx.Module`: compile its methods with `eqx.filter_jit`)."""
        data, n = self.data, self.loads.size
        if data.loads.shape[0] != n:  # padding is for `fit`'s compiled program, not a part of the curve
            data = eqx.tree_at(lambda d: (d.loads, d.targets), data, (data.loads[:n], data.targets[:n]))
        dtype = data.loads.dtype
        arrays, index, kind = prior_arrays(self.prior, dtype)
        return Misfit(self.traced, data, jnp.asarray(sigma, dtype), arrays, self.params, index, kind)


def starting_points(params, n_starts: int, seed: int, include=None) -> np.ndarray:
    """Starts in optimiser coordinates: a Latin hypercube over 2 %…98 % of each bound (plus `include`)."""
    rng = np.random.default_rng(seed)
    fractions = (
        rng.permuted(np.tile(np.arange(n_starts), (len(params), 1)), axis=1).T
        + rng.uniform(size=(n_starts, len(params)))
    ) / n_starts
    fractions = 0.02 + 0.96 * fractions
    u = np.log(fractions) - np.log1p(-fractions)
    if include is not None:
        u = np.vstack([np.asarray(include)[None, :], u[:-1]])
    return u
