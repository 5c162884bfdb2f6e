"""What a curve determines: the Fisher information of a fit decomposed into the parameter combinations
it fixes and the one it leaves open, and profile likelihoods (docs/fitting.md, "Identifiability").

The Fisher information is the Gauss–Newton `JᵀJ / s²` in the fit's statistical coordinates (D and ν
linear; G, E, H, l_min, area logarithmic), whose eigenvectors are the combinations `Σ v_i θ_i` that the
curve determines independently, each with standard error `1/√λ`. A combination is *determined* when
its 95 % interval is shorter than a tenth of the span the search bounds allow along it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import optimize, special

from ._residuals import bound_program, evaluated_by

# A combination whose 95 % interval spans more than this share of its extent within the bounds is
# not determined by the curve.
UNDETERMINED_SHARE = 0.1


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
    re-optimised), the 95 % interval where `delta_chi2` ≤ `threshold`, and whether each end was `reached`
    (where not, the profile stays below the threshold out to the parameter's bound, which is the end)."""

    name: str
    values: np.ndarray
    delta_chi2: np.ndarray
    ci95: tuple[float, float]
    threshold: float
    reached: tuple[bool, bool]


def profile(scene, params, data, rows: int, stat_hat, s2: float, index: int, stderr: float, threshold: float):
    """The profile likelihood of parameter `index`: 8 points each side out to 4 standard errors
    (statistical coordinates), and on to the bound in 6 more where the threshold is not reached, the
    other parameters re-optimised by least squares from the neighbouring point."""
    p = params[index]
    lo, hi = p.stat_bounds
    centre = float(stat_hat[index])
    half = 4 * stderr if math.isfinite(stderr) and stderr > 0 else 0.25 * (hi - lo)
    others = [k for k in range(len(params)) if k != index]
    bounds = (
        np.array([params[k].stat_bounds[0] for k in others]),
        np.array([params[k].stat_bounds[1] for k in others]),
    )

    def full(value, rest):
        stat = np.array(stat_hat, dtype=float)
        stat[index] = value
        stat[others] = rest
        return stat

    last, program, measured = {}, bound_program(scene, params, data), data.measured[:rows].reshape(-1)

    def evaluate(stat):
        # scipy asks for the residuals and then the Jacobian at the same point: one program call serves both.
        key = stat.tobytes()
        if key not in last:
            e = evaluated_by(program, stat, rows, measured)
            last.clear()
            last[key] = (e.r, e.J[:, others])
        return last[key]

    def rss_at(value, rest):
        if others:
            start = np.clip(rest, bounds[0] + 1e-9, bounds[1] - 1e-9)
            rest = optimize.least_squares(
                lambda x: evaluate(full(value, x))[0], start, jac=lambda x: evaluate(full(value, x))[1], bounds=bounds
            ).x
        r = evaluate(full(value, rest))[0]
        return float(r @ r), rest

    best = rss_at(centre, np.asarray(stat_hat, dtype=float)[others])[0]
    sides = []
    for direction, limit in ((-1, lo + 1e-9), (1, hi - 1e-9)):
        values, deltas, rest = [], [], np.asarray(stat_hat, dtype=float)[others]
        near = centre + direction * np.linspace(0, half, 9)[1:]
        for value in near[(near - limit) * direction < 0]:
            rss, rest = rss_at(value, rest)
            values.append(value)
            deltas.append((rss - best) / s2)
        if not deltas or max(deltas) <= threshold:
            for value in np.linspace(values[-1] if values else centre, limit, 7)[1:]:
                rss, rest = rss_at(value, rest)
                values.append(value)
                deltas.append((rss - best) / s2)
        sides.append((values, deltas))
    grid = np.array(sides[0][0][::-1] + [centre] + sides[1][0])
    delta = np.array(sides[0][1][::-1] + [0.0] + sides[1][1])
    ci, reached = _crossings(grid, delta, threshold, p)
    return Profile(p.name, np.array([p.from_stat(v) for v in grid]), delta, ci, threshold, reached)


def _crossings(grid, delta, threshold, p):
    """Where the profile first crosses `threshold` either side of the optimum (linear interpolation),
    or the last point (the bound) where it does not; and whether each side crossed."""
    centre = int(np.flatnonzero(delta == 0.0)[0])
    ends, reached = [], []
    for side in (list(range(centre, -1, -1)), list(range(centre, grid.size))):
        value = grid[side[-1]]
        crossed = False
        for a, b in zip(side, side[1:]):
            if delta[a] <= threshold < delta[b]:
                value = grid[a] + (threshold - delta[a]) * (grid[b] - grid[a]) / (delta[b] - delta[a])
                crossed = True
                break
        ends.append(float(p.from_stat(value)))
        reached.append(crossed)
    return (ends[0], ends[1]), (reached[0], reached[1])


def profiles_of(result, fitted, scene, data, rows, stat_hat, replace: bool) -> tuple:
    """Each parameter's profile likelihood (of the curve alone), and the statistics `result` with the
    profiles' warnings: where a parameter's interval differs from the parabolic one by more than 10 %
    of the latter's half-width on either side, and no prior enters the interval (`replace`), the
    interval is the profile's."""
    if not (result.describes_data and math.isfinite(result.s2) and result.s2 > 0):
        return {}, result
    warnings, ci95 = list(result.warnings), dict(result.ci95)
    dof = result.n_used - len(fitted)
    threshold = float(special.stdtrit(dof, 0.975)) ** 2
    profiles = {}
    for i, p in enumerate(fitted):
        se = math.sqrt(result.covariance[i, i]) if np.isfinite(result.covariance[i, i]) else math.inf
        if p.log:
            se = result.stderr[p.name] / result.values[p.name] if np.isfinite(se) else se
        prof = profile(scene, fitted, data, rows, stat_hat, result.s2, i, se, threshold)
        profiles[p.name] = prof
        lo, hi = result.ci95[p.name]
        half = (hi - lo) / 2
        for end, reached in zip(("below", "above"), prof.reached):
            if not reached:
                bound = prof.ci95[0] if end == "below" else prof.ci95[1]
                warnings.append(
                    f"the curve does not bound {p.name} {end}: its profile stays under the 95 % level out to "
                    f"{p.name} = {bound:.4g}, the end of its range"
                )
        far = max(abs(prof.ci95[0] - lo), abs(prof.ci95[1] - hi)) > 0.1 * half
        if replace and far:
            ci95[p.name] = prof.ci95
            warnings.append(f"{p.name}'s interval is its profile likelihood's: the misfit is not parabolic")
    return profiles, dataclasses.replace(result, warnings=tuple(warnings), ci95=ci95)
