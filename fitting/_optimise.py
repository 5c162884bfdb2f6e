"""The optimisers: scipy's Levenberg–Marquardt (MINPACK) and BFGS (L-BFGS-B), driving one compiled model.

The model is compiled once per static configuration, as residuals *and* their Jacobian
(`_residuals.residuals_and_jacobian`, forward mode over the fitted parameters), and the
optimisers run on the host, one call per trial point. The same compiled function then gives
the Gauss–Newton statistics at the optimum and the misfit of rival optima. An optimiser compiled
around the model (optimistix's, inside `jit`) compiles the model inside its loop, and the
statistics compile it once more: about three times the compilation (docs/fitting.md). With two
to seven parameters a step on the host costs nothing next to the model.
"""

from __future__ import annotations

import abc
import dataclasses
import math
import typing
from typing import ClassVar

import equinox as eqx
import numpy as np
from scipy import optimize

from ._parameters import FitParameter
from ._residuals import Observations, bound_program, evaluated_by

# A model of finite precision (K moving in steps, a grid point of contact at a time) has a loss with
# kinks and a Jacobian that jumps at each: the loss's progress cannot end its fits (BFGS's line
# searches run on at the optimum), and the Gauss–Newton step from the optimum is itself resolved only
# to a few hundredths of a standard error (on the boundary-element model's 256² D, G fit, χ²
# decrements of 6e-4 to 1.2e-3 over its last twenty evaluations). Such a fit ends when a further step
# would lower χ² by less than this: the parameters are then within 0.1 standard errors of the optimum.
SETTLED_STEPPED = 1e-2


@dataclasses.dataclass(frozen=True)
class Outcome:
    """One start's end: optimiser coordinates `u`, `loss` (½ mean r²), `iterations`, `converged`."""

    u: np.ndarray
    loss: float
    iterations: int
    converged: bool


class AbstractObjective(abc.ABC):
    """What the optimisers and the fit's checks see of a fit: `(r, J) = objective(u)`, the residuals
    and their Jacobian `∂r/∂u` in the optimiser coordinates `u`, and the loss ½ Σr²/N.

    **Attributes:** `params` (the fitted `FitParameter`s), `n_points` (N, the measured values),
    `settle` (the χ² decrement below which a fit is done, `settled`; 0 for never), `lowest` (the
    lowest loss evaluated and where: a fit that ends above it has stalled, `stalled`).
    """

    params: tuple
    n_points: int
    settle: float = 0.0
    lowest: tuple = (math.inf, None)
    _last: tuple | None = None

    @abc.abstractmethod
    def residuals(self, u) -> tuple[np.ndarray, np.ndarray]:
        """The residuals and their Jacobian `∂r/∂u` at `u`."""

    @typing.final
    def __call__(self, u) -> tuple[np.ndarray, np.ndarray]:
        u = np.array(u, dtype=float)  # a copy: scipy may update its own array in place
        # scipy asks for the residuals and then the Jacobian at the same point: one evaluation serves both.
        if self._last is not None and np.array_equal(self._last[0], u):
            return self._last[1]
        r, J = self.residuals(u)
        loss = half_mean_square(r, self.n_points)
        if math.isfinite(loss) and loss < self.lowest[0]:
            self.lowest = (loss, u)
        self._last = (u, (r, J))
        return r, J

    @typing.final
    def loss(self, u) -> float:
        return half_mean_square(self(u)[0], self.n_points)


def half_mean_square(r: np.ndarray, n: int) -> float:
    """The loss ½ Σr²/N of residuals `r` over `n` measured values."""
    return 0.5 * float(r @ r) / n


class Objective(AbstractObjective):
    """The residuals `r(u)` and their Jacobian `∂r/∂u` at the curve's points (the padding cut off;
    every observable's column, flattened by load).

    `u` are the optimiser coordinates (`FitParameter.stat_from_u`); `r` and `∂r/∂stat` come from
    the one compiled `residuals_and_jacobian`, bound to the scene and data once, and `∂stat/∂u` is
    applied here. `n_points` counts the measured values (the loss is their mean squared residual); `settle` is the
    χ² decrement below which a fit is done (`settled`; 0, never, for a model smooth to round-off).
    """

    def __init__(self, scene, params: tuple[FitParameter, ...], data: Observations, rows: int):
        self.params, self.rows = params, rows
        self.n_points = int(data.measured[:rows].sum())
        self.settle = 0.0 if scene.model.precision == 0 else SETTLED_STEPPED
        self._program, self._measured = bound_program(scene, params, data), data.measured[:rows].reshape(-1)

    def residuals(self, u) -> tuple[np.ndarray, np.ndarray]:
        stat, slope = zip(*(p.stat_and_slope_from_u(x) for p, x in zip(self.params, u)))
        e = evaluated_by(self._program, stat, self.rows, self._measured)
        return e.r.astype(float), e.J.astype(float) * np.asarray(slope)


def stalled(objective: AbstractObjective, loss: float, p: int) -> str | None:
    """A warning when the fit ended at `loss` although the optimiser evaluated a point lower by more
    than one unit of χ² (in the best loss's own s² = Σr²/(N − p)), else None."""
    lowest, u = objective.lowest
    n = objective.n_points
    rss, rss_lowest = 2.0 * n * loss, 2.0 * n * lowest
    s2 = rss / max(n - p, 1)
    if u is None or not (s2 > 0 and (rss - rss_lowest) / s2 > 1.0):
        return None
    where = ", ".join(f"{q.name} = {float(q.from_stat(q.stat_from_u(x))):.4g}" for q, x in zip(objective.params, u))
    return (
        f"the optimiser stalled: it evaluated {where}, which fits better (Δχ² = {(rss - rss_lowest) / s2:.3g}) "
        "than where it ended"
    )


def run_lm(objective: AbstractObjective, u0, max_iter: int, tol: float) -> Outcome:
    """Levenberg–Marquardt (MINPACK's `lmder` through `scipy.optimize.least_squares`).

    `tol` is MINPACK's `xtol`, `ftol` and `gtol` (relative step, relative reduction of the sum of
    squares, cosine between the residuals and the Jacobian's columns); `max_iter` caps the
    evaluations of the residuals.
    """
    sol = optimize.least_squares(
        lambda u: objective(u)[0],
        u0,
        jac=lambda u: objective(u)[1],
        method="lm",
        xtol=tol,
        ftol=tol,
        gtol=tol,
        max_nfev=max_iter,
    )
    return Outcome(sol.x, objective.loss(sol.x), int(sol.njev or sol.nfev), bool(sol.status > 0))


def run_bfgs(objective: AbstractObjective, u0, max_iter: int, tol: float) -> Outcome:
    """Quasi-Newton BFGS on the loss `½ mean r²`, with the gradient `Jᵀr / N` (scipy's L-BFGS-B,
    without bounds: with two to seven parameters its memory of ten steps is the full BFGS matrix).

    It stops when an iteration lowers the loss by less than `tol` (relative) or the gradient's
    largest component is below `tol`, or when the fit is settled (`settled`: nothing the
    parameters can still explain is worth a further step). This model's loss has kinks (where a
    point's `a_l` crosses a regime boundary) and an optimum can sit on one: there the gradient
    never vanishes, and only the loss's progress can tell the end (scipy's dense BFGS, whose line
    search gives up at a kink before that, stopped short of such optima). A line search that can
    lower the loss no further elsewhere ("abnormal termination") ends at a converged point when
    the Gauss–Newton step from it is below `√tol` (relative): near a smooth minimum the loss is
    flat to round-off over that distance.
    """

    def loss_and_gradient(u):
        r, J = objective(u)
        return objective.loss(u), J.T @ r / objective.n_points

    stopped = []

    def callback(intermediate_result):
        if settled(objective, intermediate_result.x):
            stopped.append(True)
            raise StopIteration

    sol = optimize.minimize(
        loss_and_gradient,
        u0,
        jac=True,
        method="L-BFGS-B",
        callback=callback,
        options=dict(ftol=tol, gtol=tol, maxiter=max_iter, maxfun=10 * max_iter),
    )
    converged = (
        bool(sol.success)
        or bool(stopped)
        or (sol.status == 2 and _gauss_newton_step(objective, sol.x) <= math.sqrt(tol))
    )
    return Outcome(sol.x, objective.loss(sol.x), int(sol.nit), converged)


def gauss_newton(r, J):
    """The Gauss–Newton step for residuals `r` with Jacobian `J`."""
    return np.linalg.lstsq(J, -r, rcond=None)[0]


def _gauss_newton_step(objective: AbstractObjective, u) -> float:
    """The largest component of the Gauss–Newton step from `u`, relative to `1 + |u|`."""
    step = gauss_newton(*objective(u))
    return float(np.max(np.abs(step) / (1.0 + np.abs(u))))


def settled(objective: AbstractObjective, u) -> bool:
    """Whether the fit at `u` is statistically done: the Gauss–Newton step from it would lower χ²
    (the residuals in units of their own scale `s² = Σr²/(N − p)`) by less than `objective.settle`,
    i.e. the parameters are within `√settle` standard errors of the optimum of the linearised problem.

    A noiseless curve has no such scale beyond the model's own precision, where this test does not
    fire: the loss's progress ends those fits.
    """
    if not objective.settle > 0:
        return False
    r, J = objective(u)
    dof = r.size - J.shape[1]
    rss = float(r @ r)
    if dof <= 0 or not rss > 0 or not np.all(np.isfinite(J)):
        return False
    step = gauss_newton(r, J)
    explained = float(np.sum((J @ step) ** 2))
    return explained < objective.settle * rss / dof


class AbstractMethod(eqx.Module):
    """How `fit` searches from each start: scipy's optimisers on the host, around the one compiled
    residual program.

    **Class attributes:** `name` (reports, and the command line's `--method`), `tolerance` (the
    default `tol` in float64), `precision_power` (a model smooth only to a relative precision ε
    stops the search no finer than ε to this power).
    """

    name: eqx.AbstractClassVar[str]
    tolerance: eqx.AbstractClassVar[float]
    precision_power: eqx.AbstractClassVar[int]

    @abc.abstractmethod
    def run(self, objective: AbstractObjective, u0, max_iter: int, tol: float) -> Outcome:
        """The search from `u0`, at most `max_iter` steps, to the tolerance `tol`."""


class BFGS(AbstractMethod):
    """Quasi-Newton BFGS on the mean squared log residual (scipy's L-BFGS-B; `run_bfgs`).

    It stops on the loss's relative progress, which is not relative to the loss (½ mean r², far
    below 1): a model of precision ε stops at ε², the loss's own resolution (at ε a noiseless fit
    of the boundary-element model stopped at D = 1.5047 for 1.5, its interval excluding the truth).
    At an optimum on a kink of the loss, 1e-12 left D 1e-6 short of it: hence 1e-15.
    """

    name: ClassVar[str] = "bfgs"
    tolerance: ClassVar[float] = 1e-15
    precision_power: ClassVar[int] = 2

    def run(self, objective: AbstractObjective, u0, max_iter: int, tol: float) -> Outcome:
        return run_bfgs(objective, u0, max_iter, tol)


class LevenbergMarquardt(AbstractMethod):
    """Levenberg–Marquardt on the residual vector (MINPACK through `scipy.optimize.least_squares`;
    `run_lm`). MINPACK's tests are relative (a step, a reduction of the sum of squares, a cosine),
    so a model of precision ε stops at ε; in float64 they must sit above the round-off of steps
    along the ill-conditioned D–G valley: hence 1e-10.
    """

    name: ClassVar[str] = "lm"
    tolerance: ClassVar[float] = 1e-10
    precision_power: ClassVar[int] = 1

    def run(self, objective: AbstractObjective, u0, max_iter: int, tol: float) -> Outcome:
        return run_lm(objective, u0, max_iter, tol)


# The command line's names ("lbfgs", the name of earlier versions, is BFGS).
METHODS = {"bfgs": BFGS, "lbfgs": BFGS, "lm": LevenbergMarquardt}
