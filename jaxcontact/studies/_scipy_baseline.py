"""A plain scipy implementation of the same model (`scipy.integrate.quad` + `scipy.optimize.brentq`).

This is what a user would write without jaxcontact, straight from `docs/model.md`: every integral is
evaluated by adaptive quadrature in the physical area `a` (no closed forms, no log-space
tricks beyond the substitution `a = exp(t)` that quad needs to resolve twelve decades), and
the largest spot `a_l` is found by bracketing. It shares no code with the JAX model on purpose,
so that the tests can use it as an independent oracle, and `jaxcontact bench` as the baseline
that speed is measured against.

Everything is float64 numpy; nothing here is differentiable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy import integrate, optimize

_M1 = 1.425 / 1.136
_M2 = 1.263 / 1.146
_EP1_END = 0.93 * 6.0**1.136
_EP2_END = 0.94 * 110.0**1.146


@dataclass(frozen=True)
class BaselineParameters:
    """Inputs of docs/model.md §1, in SI units."""

    D: float
    G: float
    E: float
    nu: float
    H: float
    area: float
    l_min: float
    model: str = "xia2024"
    interaction: str = "paper"
    distribution: str = "mb"


def _psi(D: float) -> float:
    """Wang–Komvopoulos domain-extension factor (docs/model.md §4)."""

    def eq(psi):
        x = (2 - D) / D
        return (psi ** ((2 - D) / 2) - (1 + psi ** (-D / 2)) ** (-x)) / x - 1

    return optimize.brentq(eq, 1.0 + 1e-12, 100.0, xtol=1e-15, rtol=1e-15)


def _density_factor(p: BaselineParameters) -> float:
    return _psi(p.D) ** ((2 - p.D) / 2) if p.distribution == "wk" else 1.0


def critical_area(p: BaselineParameters) -> float:
    kappa = 0.454 + 0.41 * p.nu
    phi = kappa * p.H / (2 * p.E)
    return p.G**2 * phi ** (2 / (1 - p.D))


def _regimes(p: BaselineParameters):
    """(lo, hi, f(a), f'(a)) for e, ep1, ep2, p, in the paper's ordering."""
    kappa = 0.454 + 0.41 * p.nu
    ac = critical_area(p)
    ce = 4 * math.sqrt(math.pi) / 3 * p.E * p.G ** (p.D - 1)
    me = (3 - p.D) / 2
    c1 = 2 / 3 * kappa * p.H * 1.03 * 0.93 ** (-_M1) * ac ** (1 - _M1)
    c2 = 2 / 3 * kappa * p.H * 1.40 * 0.94 ** (-_M2) * ac ** (1 - _M2)
    laws = [(ce, me), (c1, _M1), (c2, _M2), (p.H, 1.0)]
    edges = [0.0, ac, _EP1_END * ac, _EP2_END * ac, math.inf]
    out = []
    for i, (c, m) in enumerate(laws):
        out.append((edges[i], edges[i + 1], c, m))
    return out


def _log_quad(fun, lo, hi):
    """∫_lo^hi fun(a) da by quad in t = ln a (the integrands span many decades)."""
    if not hi > lo:
        return 0.0
    u, v = math.log(lo), math.log(hi)
    if v - u < 1e-6:
        # brentq probes a_l within a hair of a_min: the midpoint rule is exact to O((v-u)^3).
        t = 0.5 * (u + v)
        return fun(math.exp(t)) * math.exp(t) * (v - u)
    val, _ = integrate.quad(lambda t: fun(math.exp(t)) * math.exp(t), u, v, epsabs=0.0, epsrel=1e-13, limit=200)
    return val


def xia_totals(p: BaselineParameters, a_l: float, load: float, stiffness: bool = True):
    """(F_t, K_t, A_r) of Eqs. (31)–(39) for a given largest spot a_l, by quadrature.

    With `stiffness=False` only F_t is computed (K_t and A_r are NaN): the root search needs no
    more, and a trial a_l past the interaction breakdown would put a pole in the K_t integrand.
    """
    a_min = p.l_min**2
    dens = _density_factor(p)

    def n(a):
        return dens * (p.D / 2) * a_l ** (p.D / 2) * a ** (-(p.D + 2) / 2)

    G1 = p.G ** (p.D - 1)
    pm = load / p.area
    sign = {"none": 0.0, "paper": -1.0, "series": 1.0}[p.interaction]
    F = K = 0.0
    for i, (lo, hi, c, m) in enumerate(_regimes(p)):
        lo, hi = max(lo, a_min), min(hi, a_l)
        if not hi > lo:
            continue
        F += _log_quad(lambda a: c * a**m * n(a), lo, hi)
        if i == 3 or not stiffness:
            continue

        def k(a, c=c, m=m):
            dxi = G1 * (2 - p.D) / 2 * a ** (-p.D / 2)
            dsigma = 1.12 * math.sqrt(pm * c) / p.E * (m / 2) * a ** (m / 2 - 1)
            return c * m * a ** (m - 1) / (dxi + sign * dsigma)

        K += _log_quad(lambda a: k(a) * n(a), lo, hi)
    if not stiffness:
        return F, math.nan, math.nan
    A = _log_quad(lambda a: a * n(a), a_min, a_l)
    return F, K, A


def xia_breakdown(p: BaselineParameters, a_l: float, load: float) -> bool:
    """True where omega'(a) <= 0 somewhere in the stiffness range (interaction "paper")."""
    if p.interaction != "paper":
        return False
    a_min = p.l_min**2
    G1 = p.G ** (p.D - 1)
    pm = load / p.area
    for lo, hi, c, m in _regimes(p)[:3]:
        lo, hi = max(lo, a_min), min(hi, a_l)
        if not hi > lo:
            continue
        # omega'/xi' = 1 - r(a), r increasing in a: the worst point is the regime's upper end.
        dxi = G1 * (2 - p.D) / 2 * hi ** (-p.D / 2)
        dsigma = 1.12 * math.sqrt(pm * c) / p.E * (m / 2) * hi ** (m / 2 - 1)
        if dsigma >= dxi:
            return True
    return False


def jzz_totals(p: BaselineParameters, a_l: float):
    """(F_t, K_t, A_r) of the JZZ comparator (docs/model.md §5), by quadrature, no cutoff."""
    ac = critical_area(p)
    dens = _density_factor(p)

    def n(a):
        return dens * (p.D / 2) * a_l ** (p.D / 2) * a ** (-(p.D + 2) / 2)

    ce = 4 * math.sqrt(math.pi) / 3 * p.E * p.G ** (p.D - 1)
    # Plastic spots run down to a = 0 with the integrable weight a^(-D/2): quad's algebraic rule.
    weight = dens * (p.D / 2) * a_l ** (p.D / 2)

    def from_zero(upper):
        val, _ = integrate.quad(
            lambda a: weight, 0.0, upper, weight="alg", wvar=(-p.D / 2, 0.0), epsabs=0.0, epsrel=1e-13
        )
        return val

    F = p.H * from_zero(min(ac, a_l))
    K = 0.0
    if a_l > ac:
        F += _log_quad(lambda a: ce * a ** ((3 - p.D) / 2) * n(a), ac, a_l)
        K = _log_quad(lambda a: 2 * p.E * math.sqrt(a / math.pi) * n(a), ac, a_l)
    A = from_zero(a_l)
    return F, K, A


def solve_point(p: BaselineParameters, load: float):
    """Solve F_t(a_l) = load by brentq in ln a_l; return (a_l, K, A_r, status string)."""
    a_min = p.l_min**2

    def total(a_l, stiffness=True):
        if p.model == "jzz2010":
            return jzz_totals(p, a_l)
        return xia_totals(p, a_l, load, stiffness)

    def residual(x):
        return total(math.exp(x), stiffness=False)[0] - load

    lo = math.log(a_min) + 1e-12
    hi = math.log(p.area)
    if residual(hi) < 0 or residual(lo) > 0:
        return math.nan, math.nan, math.nan, "load_out_of_range"
    x = optimize.brentq(residual, lo, hi, xtol=1e-15, rtol=1e-15, maxiter=200)
    a_l = math.exp(x)
    if p.model == "xia2024" and xia_breakdown(p, a_l, load):
        # The stiffness integrand has a pole inside the range: there is no number to report.
        no_interaction = BaselineParameters(**{**p.__dict__, "interaction": "none"})
        return a_l, math.nan, xia_totals(no_interaction, a_l, load)[2], "interaction_breakdown"
    _, K, A = total(a_l)
    return a_l, K, A, "ok"


def solve_curve(p: BaselineParameters, loads):
    """`solve_point` over a list of loads: lists of a_l, K, A_r and status."""
    rows = [solve_point(p, float(F)) for F in loads]
    return tuple(list(col) for col in zip(*rows))
