"""What a fit returns: estimates, their uncertainty, what the curve determines, and how the fit went."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

import jaxcontact as jc


@dataclasses.dataclass(frozen=True)
class Statistics:
    """What an optimum says (`statistics_of`), before a driver adds how its search went.

    **Fields:** `values`, `stderr`, `ci95` (dicts by parameter name, physical units); `covariance` and
    `correlation` (statistical coordinates); `condition` (of the scaled Gauss–Newton matrix);
    `warnings`; `flagged` (indices of the loads with a point outside the model); `residuals` (in each
    observable's units, NaN where not used); `n_used` (residual entries used); `describes_data`;
    `usable` (on no search bound, and some combination determined); `bounds` (the on-bound warnings);
    `identifiability` (the Fisher combinations); `s2` (the residuals' variance Σr²/(N − p)); `used`
    (mask of the entries used); `rss` (Σr² over them).
    """

    values: dict
    stderr: dict
    ci95: dict
    covariance: np.ndarray
    correlation: np.ndarray
    condition: float
    warnings: tuple[str, ...]
    flagged: np.ndarray
    residuals: np.ndarray
    n_used: int
    describes_data: bool
    usable: bool
    bounds: tuple[str, ...]
    identifiability: tuple
    s2: float
    used: np.ndarray
    rss: float

    @property
    def curve_loss(self) -> float:
        """½ mean r² over the used entries (the curve alone: a prior's terms left out)."""
        return 0.5 * self.rss / max(self.n_used, 1)


@dataclasses.dataclass(frozen=True)
class FitResult:
    """Estimates, their uncertainty, and how the fit went.

    **Fields:** `values`, `stderr`, `ci95` (dicts by parameter name; stderr of a log-coordinate
    parameter is the delta-method value · se(ln value), its interval is exp(ln value ± t·se));
    `correlation` and `covariance` (in statistical coordinates, ordered as `params`); stderr and
    ci95 are NaN where the model does not describe the data (`describes_data` False: the misfit is
    far beyond the data's own scatter, and a warning says so), and a linear parameter's interval
    never leaves its domain (D's stays in (1, 2));
    `residuals` (ln K_model − ln K_data at the optimum, NaN at flagged points; with an approach
    curve, δ_model − δ_data in m, and with both a column each: (load, [stiffness, approach])); `flagged`
    (indices of data points outside the model at the optimum); `success` (the optimiser converged, not
    on a parameter's search bound, not stalled above a point it evaluated, and the curve determines
    some combination of the parameters; the warnings say which failed); `iterations` (of the
    best start); `wall_time` (s, compilation included); `warnings`; `condition_number` (of the
    scaled Gauss–Newton matrix); `start_losses`; `scene` (the fitted scene); `identifiability`
    (the combinations of parameters the curve determines, best first, each a
    `fitting.Combination` with its standard error, docs/fitting.md); `profiles` (by name, a
    `fitting.Profile` where asked for); `information` (with a prior: by name, the standard errors of
    the prior alone, the curve alone and both, and the curve's share of the information); `prior`
    (where the prior came from, or None); `observables` (what was fitted: "stiffness", "approach" or both;
    with an approach curve the loss is over residuals divided by each observable's σ); `on_bound` (the
    warnings of the parameters whose optimum is on a search bound, also among `warnings`).
    """

    params: tuple[str, ...]
    values: dict
    stderr: dict
    ci95: dict
    correlation: np.ndarray
    covariance: np.ndarray
    residuals: np.ndarray
    flagged: np.ndarray
    success: bool
    iterations: int
    wall_time: float
    warnings: tuple[str, ...]
    condition_number: float
    loss: float
    start_losses: np.ndarray
    method: str
    scene: jc.Scene = dataclasses.field(repr=False)
    describes_data: bool = True
    identifiability: tuple = ()
    profiles: dict = dataclasses.field(default_factory=dict)
    information: dict = dataclasses.field(default_factory=dict)
    prior: str | None = None
    observables: tuple[str, ...] = ("stiffness",)
    on_bound: tuple[str, ...] = ()

    @classmethod
    def of(cls, stats, params, scene: jc.Scene, *, prior=None, **run) -> FitResult:
        """The result of an optimum's statistics `stats` (a `Statistics`), the fitted `params`, the fitted
        `scene`, the `prior` (a `GaussianPrior` or None) and how the search went (`run`: `success`,
        `iterations`, `wall_time`, `warnings`, `loss`, `start_losses`, `method`, `observables`, and
        `profiles` and `information` where there are any): `fit`'s, and each of `fit_batch`'s curves'."""
        return cls(
            params=tuple(p.name for p in params),
            values=stats.values,
            stderr=stats.stderr,
            ci95=stats.ci95,
            correlation=stats.correlation,
            covariance=stats.covariance,
            residuals=stats.residuals,
            flagged=stats.flagged,
            condition_number=stats.condition,
            scene=scene,
            describes_data=stats.describes_data,
            identifiability=stats.identifiability,
            prior=None if prior is None else prior.source,
            on_bound=stats.bounds,
            **run,
        )

    def summary(self) -> str:
        lines = [
            f"fit by {self.method}: {'converged' if self.success else 'NOT a success'} in {self.iterations} "
            f"iterations, {self.wall_time:.2f} s; {_RMS_LABEL.get(self.observables, 'rms weighted residual')} "
            f"{math.sqrt(2 * self.loss):.3g}"
        ]
        for name in self.params:
            lo, hi = self.ci95[name]
            spread = (
                f"± {self.stderr[name]:.3g}   95% CI [{lo:.6g}, {hi:.6g}]"
                if self.describes_data
                else "  95% CI not reported: the model does not describe the data"
            )
            lines.append(f"  {name:6s} = {self.values[name]:.6g} {spread}")
        if self.identifiability and not any("the curve fixes" in w for w in self.warnings):
            from ._identifiability import report

            lines.append(f"  identifiability: {report(self.params, self.identifiability)}")
        for name, share in self.information.items():
            lines.append(
                f"  {name}: prior ± {share['prior']:.3g}, curve alone ± {share['curve']:.3g}, "
                f"both ± {share['both']:.3g} "
                f"(statistical coordinates): {100 * share['curve_share']:.0f} % of its information from the curve, "
                f"{100 * (1 - share['curve_share']):.0f} % from the prior ({self.prior})"
            )
        for name, prof in self.profiles.items():
            lines.append(f"  profile of {name}: 95 % [{prof.ci95[0]:.6g}, {prof.ci95[1]:.6g}]")
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {
            "params": list(self.params),
            "values": self.values,
            "stderr": self.stderr,
            "ci95": {k: list(v) for k, v in self.ci95.items()},
            "correlation": self.correlation.tolist(),
            "residuals": self.residuals.tolist(),
            "flagged": self.flagged.tolist(),
            "success": self.success,
            "iterations": self.iterations,
            "wall_time_s": self.wall_time,
            "warnings": list(self.warnings),
            "condition_number": self.condition_number,
            "loss": self.loss,
            "method": self.method,
            "describes_data": self.describes_data,
            "identifiability": [
                {"combination": str(c), "weights": c.weights, "stderr": c.stderr, "determined": c.determined}
                for c in self.identifiability
            ],
            "profiles": {
                name: {
                    "values": p.values.tolist(),
                    "delta_chi2": p.delta_chi2.tolist(),
                    "ci95": list(p.ci95),
                    "ends_reached": list(p.reached),
                }
                for name, p in self.profiles.items()
            },
            "information": self.information,
            "prior": self.prior,
            "observables": list(self.observables),
        }


# The loss's unit, by what was fitted: ln K alone, else residuals divided by their noise.
_RMS_LABEL = {("stiffness",): "rms log residual"}
