"""A posterior by NUTS where the Laplace approximation is poor (ridges, bounds, kinks): the fit's
parameters in its unconstrained coordinates, the model's exact gradients, blackjax's sampler
(docs/fitting.md, "Posterior by NUTS").

The log density in the optimiser coordinates `u` (statistical coordinate `s = low + (high − low)·
sigmoid(u)`) is `−½ Σ (r_i/σ)² + ln prior(s) + ln |ds/du|`: flat in the statistical coordinates
within the bounds (D and ν uniform, the scales log-uniform), times the Gaussian prior where one is
given. The residuals are the fit's own (`_residuals.observed_residuals`: ln K and/or the approach δ,
each divided by its σ), and σ their scale, held fixed: 1 where every observable's noise is stated,
else the weighted residuals' scale at the least-squares (or MAP) optimum.
"""

from __future__ import annotations

import dataclasses
import time

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

import jaxcontact as jc

from ._misfit import Misfit
from ._nuts import run_chains
from ._parameters import with_stat
from ._prior import residual_scale
from ._problem import Problem
from ._residuals import Observations
from ._statistics import inner_bounds

# Above this share of the draws divergent, NUTS has not explored the posterior (a funnel, a kink):
# the samples are not to be trusted. R-hat above MAX_RHAT: the chains disagree (Vehtari et al. 2021).
MAX_DIVERGENT_SHARE = 0.01
MAX_RHAT = 1.01


@dataclasses.dataclass(frozen=True)
class Posterior:
    """Samples of the fitted parameters and what they say.

    **Fields:** `params`; `samples` (by name, physical values, shape (chains, draws)); `mean`, `sd`,
    `ci95` (2.5 and 97.5 % quantiles) by name; `ess` and `rhat` by name; `acceptance`; `divergences`;
    `sigma` (the noise in ln K held fixed); `band` (loads, and the 2.5, 50 and 97.5 % quantiles of the
    predicted K over the samples); `times` (s: `start`, the least-squares start; `adaptation`, with its
    compilation; the sampler's `compilation`; `sampling`, the compiled run); `describes_data` (the
    least-squares fit's verdict: where False, the posterior is that of a model the data reject, and
    is shown only with that caveat); `success` (the model describes the data, its least-squares
    optimum is on no search bound (there the bounds, not the data, cut the posterior off), divergent
    transitions are at most `MAX_DIVERGENT_SHARE` of the draws, and every R-hat is at most `MAX_RHAT`);
    `warnings` (why not).
    """

    params: tuple[str, ...]
    samples: dict
    mean: dict
    sd: dict
    ci95: dict
    ess: dict
    rhat: dict
    acceptance: float
    divergences: int
    sigma: float
    band: tuple
    times: dict
    describes_data: bool = True
    success: bool = True
    warnings: tuple[str, ...] = ()

    def summary(self) -> str:
        lines = [
            f"posterior by NUTS: {next(iter(self.samples.values())).shape[0]} chains × "
            f"{next(iter(self.samples.values())).shape[1]} draws, acceptance {self.acceptance:.2f}, "
            f"{self.divergences} divergent; σ(ln K) = {self.sigma:.3g}; sampling {self.times['sampling']:.1f} s "
            f"(compiling it {self.times['compilation']:.1f} s, adaptation {self.times['adaptation']:.1f} s)"
        ]
        caveat = "" if self.describes_data else "   (of a model that does not describe the data)"
        for name in self.params:
            lo, hi = self.ci95[name]
            lines.append(
                f"  {name:6s} mean {self.mean[name]:.6g} sd {self.sd[name]:.3g}   95 % [{lo:.6g}, {hi:.6g}]   "
                f"ESS {self.ess[name]:.0f}, R-hat {self.rhat[name]:.3f}{caveat}"
            )
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {
            "params": list(self.params),
            "mean": self.mean,
            "sd": self.sd,
            "ci95": {k: list(v) for k, v in self.ci95.items()},
            "ess": self.ess,
            "rhat": self.rhat,
            "acceptance": self.acceptance,
            "divergences": self.divergences,
            "sigma": self.sigma,
            "band": {k: np.asarray(v).tolist() for k, v in zip(("load_N", "lower", "median", "upper"), self.band)},
            "times_s": self.times,
            "describes_data": self.describes_data,
            "success": self.success,
            "warnings": list(self.warnings),
        }


class LogDensity(eqx.Module):
    """The log density in optimiser coordinates `u`: `−½ Σ (r/σ)² − ½ |L⁻¹ (φ − μ)|²` (the misfit's
    loss times its number of residual entries) `+ ln |ds/du|`; a module, so that another curve's density
    runs the sampler's compiled programs again (`run_chains`)."""

    misfit: Misfit

    def __call__(self, u):
        entries = self.misfit.data.targets.size
        return -entries * self.misfit.loss(u) + jnp.sum(jax.nn.log_sigmoid(u) + jax.nn.log_sigmoid(-u))


def _scale(start, data: Observations, p: int) -> float:
    """The weighted residuals' scale at the fit's optimum: its residuals (NaN where a point was not
    used), each observable's weighted back."""
    weighted = np.asarray(start.residuals).reshape(len(start.residuals), -1) * np.asarray(data.weights)
    used = weighted[np.isfinite(weighted)]
    return residual_scale(used, used.size, p)


def sample(
    loads,
    stiffness,
    scene: jc.Scene,
    params=("D", "G"),
    *,
    prior=None,
    noise: float | dict[str, float] | None = None,
    approach=None,
    reference_load: float | None = None,
    chains: int = 4,
    draws: int = 500,
    warmup: int = 500,
    seed: int = 0,
    band_samples: int = 200,
) -> Posterior:
    """Sample the posterior of `params` given a stiffness curve, an approach curve or both (and a
    prior) by NUTS.

    **Arguments:** as `fitting.fit` (`loads`, `stiffness`, `scene`, `params`, `prior`, `noise`,
    `approach`, `reference_load`), and
    `chains`, `draws` (per chain), `warmup` (adaptation steps), `seed`, `band_samples` (samples, evenly
    thinned, through which the predicted K band is drawn).

    **Returns:** a `Posterior`. The chains start at the least-squares (or MAP) estimate of `fitting.fit`;
    `Posterior.success` is False, with a warning, for a model the data reject, for a least-squares
    optimum on a search bound, for divergent draws above 1 % and for R-hat above 1.01.
    """
    from ._fit import _multiple, fit_problem, model_stiffness

    for name, value, least in (
        ("chains", chains, 2),
        ("draws", draws, 10),
        ("warmup", warmup, 10),
        ("band_samples", band_samples, 1),
    ):
        if isinstance(value, bool) or not isinstance(value, int) or value < least:
            raise jc.InputError(f"{name} = {value!r} must be an integer >= {least}")
    t0 = time.perf_counter()
    observed = dict(approach=approach, reference_load=reference_load, multiple=_multiple(scene))
    # One problem: the least-squares start is fitted on it (padded as `fit` pads), and sampled.
    problem = Problem.of(loads, stiffness, scene, params, prior=prior, noise=noise, **observed)
    start = fit_problem(problem, n_starts=4, seed=seed)
    fitted, data, loads = problem.params, problem.data, problem.loads
    sigma = 1.0 if problem.stated else _scale(start, data, len(fitted))
    logdensity = LogDensity(problem.misfit(sigma))
    u0 = np.array([p.u_from_stat(np.clip(p.to_stat(start.values[p.name]), *inner_bounds(p))) for p in fitted])
    t1 = time.perf_counter()
    chains_ = run_chains(
        logdensity, jnp.asarray(u0, data.loads.dtype), chains=chains, warmup=warmup, draws=draws, seed=seed
    )
    stat = np.stack(
        [[p.stat_from_u(x) for p, x in zip(fitted, row)] for row in chains_.positions.reshape(-1, len(fitted))]
    )
    physical = {
        p.name: np.array([p.from_stat(s) for s in stat[:, i]]).reshape(chains, draws) for i, p in enumerate(fitted)
    }
    thinned = stat[np.linspace(0, stat.shape[0] - 1, min(band_samples, stat.shape[0])).astype(int)]
    curves = []
    for row in thinned:
        curves.append(model_stiffness(with_stat(scene, fitted, row), [p.name for p in fitted], loads))
    curves = np.array(curves)
    band = (loads, *np.nanpercentile(curves, [2.5, 50, 97.5], axis=0))
    names = [p.name for p in fitted]
    warnings = []
    if not start.describes_data:
        warnings.append(
            "the least-squares fit says the model does not describe these data: the posterior of a rejected model"
        )
    cut = "the least-squares optimum is on a search bound, where the posterior is cut off"
    warnings += [f"{cut}: {w}" for w in start.on_bound]
    if chains_.divergences > MAX_DIVERGENT_SHARE * chains * draws:
        warnings.append(
            f"{chains_.divergences} of {chains * draws} draws are divergent (more than {MAX_DIVERGENT_SHARE:.0%}): "
            "the sampler did not explore the posterior"
        )
    unmixed = [n for i, n in enumerate(names) if not float(chains_.rhat[i]) <= MAX_RHAT]
    if unmixed:
        warnings.append(f"R-hat above {MAX_RHAT} for {', '.join(unmixed)}: the chains disagree; draw more")
    return Posterior(
        params=tuple(names),
        samples=physical,
        mean={n: float(np.mean(physical[n])) for n in names},
        sd={n: float(np.std(physical[n])) for n in names},
        ci95={n: tuple(float(q) for q in np.percentile(physical[n], [2.5, 97.5])) for n in names},
        ess={n: float(chains_.ess[i]) for i, n in enumerate(names)},
        rhat={n: float(chains_.rhat[i]) for i, n in enumerate(names)},
        acceptance=chains_.acceptance,
        divergences=chains_.divergences,
        sigma=sigma,
        band=band,
        times={
            "start": t1 - t0,
            "adaptation": chains_.adaptation,
            "compilation": chains_.compilation,
            "sampling": chains_.sampling,
        },
        describes_data=start.describes_data,
        success=not warnings,
        warnings=tuple(warnings),
    )
