"""What a curve determines: the Fisher information of a fit decomposed into the parameter combinations
it fixes and the one it leaves open, and profile likelihoods (docs/fitting.md, "Identifiability").

The Fisher information is the Gauss–Newton `JᵀJ / s²` in the fit's statistical coordinates (D and ν
linear; G, E, H, l_min, area logarithmic), whose eigenvectors are the combinations `Σ v_i θ_i` that the
curve determines independently, each with standard error `1/√λ`. A combination is *determined* when
its 95 % interval is shorter than a quarter of the span the search bounds allow along it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import optimize

from ._residuals import residuals_and_jacobian

# A combination whose 95 % interval spans more than this share of its extent within the bounds is
# not determined by the curve.
UNDETERMINED_SHARE = 0.25


@dataclasses.dataclass(frozen=True)
class Combination:
    """`Σ weights[name] · θ_name` (θ: D, ν as they are; the others' logarithms), its standard error, and
    whether the curve determines it."""

    weights: dict
    stderr: float
    determined: bool

    def __str__(self) -> str:
        terms = []
        for name, w in self.weights.items():
            if abs(w) >= 0.005:
                symbol = name if name in ("D", "nu") else f"ln {name}"
                terms.append(f"{w:+.2f} {symbol}")
        return " ".join(terms).lstrip("+")


def combinations(params, information: np.ndarray) -> tuple[Combination, ...]:
    """The eigen-combinations of the Fisher `information` (statistical coordinates), best determined first."""
    eigenvalues, vectors = np.linalg.eigh(information)
    spans = np.array([p.stat_bounds[1] - p.stat_bounds[0] for p in params])
    found = []
    for k in np.argsort(eigenvalues)[::-1]:
        v = vectors[:, k] * np.sign(vectors[np.argmax(np.abs(vectors[:, k])), k])
        stderr = 1.0 / math.sqrt(eigenvalues[k]) if eigenvalues[k] > 0 else math.inf
        extent = float(np.abs(v) @ spans)
        weights = {p.name: float(w) for p, w in zip(params, v)}
        found.append(Combination(weights, stderr, 2 * 1.96 * stderr < UNDETERMINED_SHARE * extent))
    return tuple(found)


def report(params, found: tuple[Combination, ...]) -> str:
    """One line: what the curve fixes and what it does not, in parameter terms."""
    fixed = [f"{c} (± {c.stderr:.2g})" for c in found if c.determined]
    open_ = [str(c) for c in found if not c.determined]
    if not open_:
        return "the curve determines every parameter: " + "; ".join(fixed)
    alone = [p.name for p in params if any(abs(c.weights[p.name]) > 0.3 for c in found if not c.determined)]
    text = f"the curve fixes {'; '.join(fixed) if fixed else 'no combination'}; it leaves {'; '.join(open_)} open"
    return text + (f" ({', '.join(alone)} alone undetermined)" if alone else "")


@dataclasses.dataclass(frozen=True)
class Profile:
    """The profile of one parameter: `values` (physical), `delta_chi2` (χ² above the optimum, the others
    re-optimised), and the 95 % interval where `delta_chi2` ≤ `threshold` (NaN where it is not reached
    within the bounds)."""

    name: str
    values: np.ndarray
    delta_chi2: np.ndarray
    ci95: tuple[float, float]
    threshold: float


def profile(scene, params, data, n_points: int, stat_hat, s2: float, index: int, stderr: float, threshold: float):
    """The profile likelihood of parameter `index` over ±4 standard errors (statistical coordinates,
    clipped to the bounds), 17 points, the other parameters re-optimised by least squares from the optimum."""
    loads, log_stiffness = data
    p = params[index]
    lo, hi = p.stat_bounds
    half = 4 * stderr if math.isfinite(stderr) and stderr > 0 else 0.25 * (hi - lo)
    grid = np.linspace(max(stat_hat[index] - half, lo + 1e-9), min(stat_hat[index] + half, hi - 1e-9), 17)
    others = [k for k in range(len(params)) if k != index]
    bounds = ([params[k].stat_bounds[0] for k in others], [params[k].stat_bounds[1] for k in others])

    def full(value, rest):
        stat = np.array(stat_hat, dtype=float)
        stat[index] = value
        stat[others] = rest
        return stat

    def rss(stat):
        r = np.asarray(residuals_and_jacobian(stat, scene, params, loads, log_stiffness)[0])[:n_points]
        return float(r @ r)

    def residuals(rest, value):
        return np.asarray(residuals_and_jacobian(full(value, rest), scene, params, loads, log_stiffness)[0])[:n_points]

    def jacobian(rest, value):
        J = np.asarray(residuals_and_jacobian(full(value, rest), scene, params, loads, log_stiffness)[3])
        return J[:n_points][:, others]

    best = rss(np.asarray(stat_hat, dtype=float))
    profile_rss, rest = [], np.asarray(stat_hat, dtype=float)[others]
    for value in grid:
        if others:
            start = np.clip(rest, np.array(bounds[0]) + 1e-9, np.array(bounds[1]) - 1e-9)
            rest = optimize.least_squares(residuals, start, jac=jacobian, bounds=bounds, args=(value,)).x
        profile_rss.append(rss(full(value, rest)))
    delta = (np.array(profile_rss) - best) / s2
    return Profile(
        p.name, np.array([p.from_stat(v) for v in grid]), delta, _crossings(grid, delta, threshold, p), threshold
    )


def _crossings(grid, delta, threshold, p) -> tuple[float, float]:
    """Where the profile crosses `threshold` either side of its minimum (linear interpolation)."""
    centre = int(np.argmin(delta))
    ends = []
    for side in (range(centre, -1, -1), range(centre, grid.size)):
        side = list(side)
        value = math.nan
        for a, b in zip(side, side[1:]):
            if delta[a] <= threshold < delta[b]:
                value = grid[a] + (threshold - delta[a]) * (grid[b] - grid[a]) / (delta[b] - delta[a])
                break
        ends.append(float(p.from_stat(value)) if math.isfinite(value) else math.nan)
    return ends[0], ends[1]
