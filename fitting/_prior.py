"""What the user already knows, as a prior: the topography's (D, ln G) and their covariance, or stated
means and standard deviations, or bounds (docs/fitting.md, "Joint inference with the surface").

A stated Gaussian prior lives in the fit's statistical coordinates (D and ν linear; G, E, H, l_min,
area logarithmic: a stated sd of a scale is relative, sd/mean); a topography's prior on D and G in its
spectrum's own coordinates φ(D, ln G) (`_spectral_prior`). The fit then minimises
`Σ (r_i / σ)² + (φ(θ) − μ)ᵀ Σ_p⁻¹ (φ(θ) − μ)`, σ the curve's noise in ln K (given, or the residuals'
scale of the curve fitted alone), and the posterior covariance is `(JᵀJ/σ² + ∂φᵀ Σ_p⁻¹ ∂φ)⁻¹` (Laplace).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from jaxcontact import InputError
from jaxcontact.numerics import float_array
from jaxcontact.topography import AbstractMeasurementKind, Characterisation

from ._optimise import AbstractObjective, run_lm
from ._residuals import evaluated
from ._spectral_prior import decorrelated, spectral_coordinates
from ._statistics import NORMAL_975, stderr_and_interval, student_t

# Below this noise (ln K) a curve would outweigh any prior without limit: no measured curve is better.
NOISE_FLOOR = 1e-3


@dataclasses.dataclass(frozen=True)
class GaussianPrior:
    """`mean` and `covariance` of the parameters `index` (positions among the fitted ones); `source` says
    where it came from. In statistical coordinates, or (`kind` set: a spectrum's fit of D and ln G, both
    fitted) in that spectrum's own decorrelated coordinates (`_spectral_prior`), with `start` the
    estimate in statistical coordinates."""

    index: tuple[int, ...]
    mean: np.ndarray
    covariance: np.ndarray
    source: str
    kind: AbstractMeasurementKind | None = None
    log_q: float = 0.0
    start: np.ndarray | None = None

    @property
    def root(self) -> np.ndarray:
        """`L⁻¹` with `Σ_p = L Lᵀ`: the prior's residuals are `L⁻¹ (φ(θ) − μ)`."""
        return np.linalg.inv(np.linalg.cholesky(self.covariance))

    @property
    def first_start(self) -> np.ndarray:
        return self.mean if self.start is None else self.start

    def linearised(self, stat_all) -> tuple[np.ndarray, np.ndarray]:
        """The prior's residuals `L⁻¹ (φ(θ) − μ)` at all the fitted parameters' statistical coordinates
        `stat_all`, and their Jacobian (zero in the columns of parameters without a prior): the traced
        prior's (`traced_residuals`, the one the compiled programs run) and its forward-mode derivative."""
        return linearised_at(prior_arrays(self, jnp.result_type(1.0)), stat_all)

    def precision(self, stat_all) -> np.ndarray:
        """`∂φᵀ Σ_p⁻¹ ∂φ` at `stat_all`: the prior's precision in statistical coordinates, among all the
        fitted parameters (zero where no prior)."""
        J = self.linearised(stat_all)[1]
        return J.T @ J


@functools.partial(jax.jit, static_argnums=(2, 3))
def _linearised(arrays, stat, index, kind):
    def residuals(s):
        return traced_residuals(index, kind, *arrays, s)

    return residuals(stat), jax.jacfwd(residuals)(stat)


def linearised_at(parts, stat_all) -> tuple[np.ndarray, np.ndarray]:
    """`GaussianPrior.linearised` from the prior's `prior_arrays` (`parts`), made once by a caller
    that evaluates it often."""
    arrays, index, kind = parts
    found = _linearised(arrays, jnp.asarray(stat_all, arrays[0].dtype), index, kind)
    return tuple(np.asarray(x, dtype=float) for x in found)


def _characterisation_prior(c, fitted) -> GaussianPrior:
    names = [p.name for p in fitted]
    index = tuple(names.index(n) for n in ("D", "G") if n in names)
    if not index:
        raise InputError("prior: a characterisation gives D and G, and neither is fitted")
    chosen = [k for k, n in enumerate(("D", "G")) if n in names]
    mean = np.array([c.D, math.log(c.G)])[chosen]
    covariance = np.asarray(c.covariance, dtype=float)[np.ix_(chosen, chosen)]
    if not np.all(np.isfinite(covariance)) or np.any(np.diag(covariance) <= 0):
        raise InputError("prior: the characterisation has no usable covariance of (D, ln G) (D was held?)")
    source = f"the topography ({c.method}, band {c.band[0]:.3g}-{c.band[1]:.3g} m)"
    if len(index) == 2 and c.power_law is not None:
        spectral_mean, spectral_covariance, log_q = decorrelated(c.power_law)
        return GaussianPrior(index, spectral_mean, spectral_covariance, source, c.kind, log_q, mean)
    return GaussianPrior(index, mean, covariance, source)


class AbstractPrior(eqx.Module):
    """What is known of one fitted parameter besides the curve (`fit(..., prior={name: ...})`)."""


class Normal(AbstractPrior):
    """A Gaussian prior, `mean` ± `sd` in the parameter's units: in ln coordinates for a scale (G,
    l_min, E, H, area: its sd relative to its mean), as the fit's own coordinates are."""

    mean: float
    sd: float

    def __check_init__(self):
        for name in ("mean", "sd"):
            float_array(name, getattr(self, name), 0)
        if not (math.isfinite(self.sd) and self.sd > 0):
            raise InputError(f"Normal: sd = {self.sd!r} must be > 0 (valid range (0, inf))")


class Bounds(AbstractPrior):
    """A uniform prior on [`low`, `high`]: the fit's search range narrowed to it."""

    low: float
    high: float

    def __check_init__(self):
        for name in ("low", "high"):
            float_array(name, getattr(self, name), 0)


def _stated_prior(prior: dict, fitted):
    """Gaussian terms and narrowed bounds from `{name: Normal(mean, sd) or Bounds(low, high)}`."""
    names = [p.name for p in fitted]
    index, mean, variance, bounds = [], [], [], {}
    for name, spec in prior.items():
        if name not in names:
            raise InputError(f"prior on {name!r}, which is not fitted (params = {', '.join(names)})")
        p = fitted[names.index(name)]
        if not isinstance(spec, AbstractPrior):
            raise InputError(
                f"prior[{name!r}] = {spec!r} must be fitting.Normal(mean, sd) or fitting.Bounds(low, high)"
            )
        if isinstance(spec, Bounds):
            low, high = float(spec.low), float(spec.high)
            if not (p.low <= low < high <= p.high):
                raise InputError(
                    f"prior[{name!r}] bounds [{low:g}, {high:g}] must satisfy {p.low:g} <= low < high <= {p.high:g}"
                )
            bounds[name] = (low, high)
            continue
        m, sd = float(spec.mean), float(spec.sd)
        if not (p.low < m < p.high):
            raise InputError(f"prior[{name!r}]: mean = {m:g} must lie in ({p.low:g}, {p.high:g})")
        index.append(names.index(name))
        mean.append(math.log(m) if p.log else m)
        variance.append((sd / m) ** 2 if p.log else sd**2)
    gaussian = GaussianPrior(tuple(index), np.array(mean), np.diag(variance), "stated") if index else None
    return gaussian, bounds


def resolve_prior(prior, fitted):
    """`(GaussianPrior or None, the fitted parameters with the prior's bounds)` from a characterisation,
    a dict, or None."""
    if prior is None:
        return None, fitted
    if isinstance(prior, Characterisation):
        return _characterisation_prior(prior, fitted), fitted
    if not isinstance(prior, dict):
        raise InputError(
            f"prior = {type(prior).__name__} must be a topography Characterisation or a dict by parameter "
            "of fitting.Normal or fitting.Bounds"
        )
    gaussian, bounds = _stated_prior(prior, fitted)
    narrowed = tuple(
        dataclasses.replace(p, low=bounds[p.name][0], high=bounds[p.name][1]) if p.name in bounds else p for p in fitted
    )
    return gaussian, narrowed


class PriorObjective(AbstractObjective):
    """An objective whose residuals are `base`'s divided by the noise `sigma`, with the prior's
    `L⁻¹ (θ − μ)` appended."""

    def __init__(self, base: AbstractObjective, prior: GaussianPrior, sigma: float):
        self.base, self.params, self.n_points, self.settle = base, base.params, base.n_points, base.settle
        self.prior, self.sigma = prior, sigma
        self._parts = prior_arrays(prior, jnp.result_type(1.0))

    def residuals(self, u):
        r, J = self.base(u)
        stat, slope = zip(*(p.stat_and_slope_from_u(x) for p, x in zip(self.params, u)))
        r_prior, J_prior = linearised_at(self._parts, np.asarray(stat))
        return np.concatenate([r / self.sigma, r_prior]), np.vstack([J / self.sigma, J_prior * np.asarray(slope)])


def posterior(J: np.ndarray, sigma: float, prior: GaussianPrior, stat_hat) -> dict:
    """The Laplace covariance at `stat_hat` and, per parameter with a prior, where its information came
    from: standard errors (statistical coordinates) of the prior alone, the curve alone and both, and
    the curve's share `1 − var_both / var_prior`."""
    n = J.shape[1]
    curve = J.T @ J / sigma**2
    precision = prior.precision(stat_hat)
    covariance = np.linalg.inv(curve + precision)
    prior_covariance = np.linalg.inv(precision[np.ix_(prior.index, prior.index)])
    with np.errstate(divide="ignore", invalid="ignore"):
        curve_alone = np.sqrt(np.diag(np.linalg.pinv(curve)))
    shares = {}
    for k, i in enumerate(prior.index):
        var_prior, var_both = prior_covariance[k, k], covariance[i, i]
        shares[i] = dict(
            prior=math.sqrt(var_prior),
            curve=float(curve_alone[i]) if np.linalg.matrix_rank(curve) == n else math.inf,
            both=math.sqrt(var_both),
            curve_share=max(0.0, 1.0 - var_both / var_prior),
        )
    return {"covariance": covariance, "shares": shares}


def noise_scale(objective, u0, noise, max_iter: int, tol: float, p: int) -> float:
    """σ of ln K: `noise` if given, else the residuals' scale of the curve alone, `√(Σr²/(N − p))` at its
    least-squares optimum from `u0` (a ridge leaves the parameters open, not the misfit)."""
    if noise is not None:
        if not (isinstance(noise, (int, float)) and math.isfinite(noise) and noise > 0):
            raise InputError(f"noise = {noise!r} must be > 0 (valid range (0, inf)): σ of ln K")
        return float(noise)
    r = objective(run_lm(objective, u0, max_iter, tol).u)[0]
    return residual_scale(r, objective.n_points, p)


def residual_scale(r: np.ndarray, n: int, p: int) -> float:
    """The residuals' scale `√(Σr²/(N − p))` over `n` measured values and `p` parameters, no lower
    than `NOISE_FLOOR`."""
    return max(math.sqrt(float(r @ r) / max(n - p, 1)), NOISE_FLOOR)


def traced_residuals(index: tuple[int, ...], kind, root, mean, log_q, stat):
    """`L⁻¹ (φ(θ) − μ)` of a `GaussianPrior` (its `index` and `kind` static; `root`, `mean`, `log_q` as
    arrays) at all the fitted parameters' statistical coordinates `stat`, as a JAX function: inside a
    compiled program (`fit_batch`'s loss, `sample`'s log density)."""
    chosen = stat[jnp.asarray(index)]
    phi = chosen if kind is None else jnp.stack(spectral_coordinates(kind, log_q, *chosen))
    return root @ (phi - mean)


def prior_arrays(prior: GaussianPrior | None, dtype) -> tuple:
    """`(arrays, index, kind)` of `prior` for `traced_residuals`: `(root, mean, log_q)` as arrays of
    `dtype`, and the static `index` and `kind`; `(None, None, None)` without a prior."""
    if prior is None:
        return None, None, None
    return tuple(jnp.asarray(x, dtype) for x in (prior.root, prior.mean, prior.log_q)), prior.index, prior.kind


def with_prior(result, fitted, scene, data, rows, stat_hat, gaussian, sigma, dof=None):
    """`result` with the Laplace posterior's covariance and intervals (`with_prior_of`), and the
    information report by parameter name."""
    e = evaluated(stat_hat, scene, fitted, data, rows)
    return with_prior_of(result, e, fitted, stat_hat, gaussian, sigma, dof)


def posterior_quantile(curve_share: float, dof: int | None) -> float:
    """The 97.5 % quantile of a Laplace interval whose curve part has the share `curve_share` of the
    parameter's precision, the curve's σ estimated with `dof` degrees of freedom (None: σ stated).

    The precision `λ = a/σ̂² + b` inherits the relative variance `2 s²/ν` of `1/σ̂²` through its curve
    share `s = a/(σ² λ)`: Satterthwaite's `ν/s²` degrees of freedom, Student's t of the curve alone
    (`s = 1`) down to the prior's normal quantile (`s = 0`)."""
    if dof is None or curve_share <= 0.0:
        return NORMAL_975
    return student_t(dof / min(curve_share, 1.0) ** 2)


def with_prior_of(result, e, fitted, stat_hat, gaussian, sigma, dof=None):
    """`with_prior` from the residuals and Jacobian `e` at the optimum `stat_hat`; `dof`: the degrees of
    freedom of σ's estimate (None where the noise was stated), for each interval's quantile
    (`posterior_quantile`; a parameter without a prior of its own counts as the curve's alone)."""
    post = posterior(e.J[e.used], sigma, gaussian, stat_hat)
    covariance = post["covariance"]
    spread = np.sqrt(np.diag(covariance))
    stderr, ci95 = {}, {}
    for i, p in enumerate(fitted):
        share = post["shares"][i]["curve_share"] if i in post["shares"] else 1.0
        quantile = posterior_quantile(share, dof)
        stderr[p.name], ci95[p.name] = stderr_and_interval(p, stat_hat[i], spread[i], quantile)
    if not result.describes_data:  # no interval for a model that does not describe the curve
        stderr = dict.fromkeys(stderr, math.nan)
        ci95 = dict.fromkeys(ci95, (math.nan, math.nan))
    information = {fitted[i].name: share for i, share in post["shares"].items()}
    updated = dataclasses.replace(
        result, covariance=covariance, stderr=stderr, ci95=ci95, correlation=covariance / np.outer(spread, spread)
    )
    return updated, information
