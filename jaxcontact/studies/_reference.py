"""A high-precision reference for the xia2024 stiffness (mpmath, 30 digits), for the accuracy study.

Independent of the JAX code: F_t(a_l) from the power-law closed forms, a_l by `mpmath.findroot`,
the stiffness without interaction in closed form, and the interaction part by `mpmath.quad`
(tanh-sinh) in log-area. Slow (tens of milliseconds per load); only `jaxcontact accuracy` and the
tests use it.
"""

from __future__ import annotations

import mpmath as mp

# ω = ξ + sign · σ (docs/model.md §3), written here again: an oracle shares nothing with what it checks.
SIGNS = {"none": 0, "paper": -1, "series": 1}


M1 = mp.mpf("1.425") / mp.mpf("1.136")
M2 = mp.mpf("1.263") / mp.mpf("1.146")


def _laws(D, G, E, nu, H):
    kappa = mp.mpf("0.454") + mp.mpf("0.41") * nu
    a_c = G**2 * (kappa * H / (2 * E)) ** (2 / (1 - D))
    laws = [
        (4 * mp.sqrt(mp.pi) / 3 * E * G ** (D - 1), (3 - D) / 2),
        (mp.mpf(2) / 3 * kappa * H * mp.mpf("1.03") * mp.mpf("0.93") ** (-M1) * a_c ** (1 - M1), M1),
        (mp.mpf(2) / 3 * kappa * H * mp.mpf("1.40") * mp.mpf("0.94") ** (-M2) * a_c ** (1 - M2), M2),
        (H, mp.mpf(1)),
    ]
    edges = [
        mp.mpf(0),
        a_c,
        mp.mpf("0.93") * 6 ** mp.mpf("1.136") * a_c,
        mp.mpf("0.94") * 110 ** mp.mpf("1.146") * a_c,
        mp.inf,
    ]
    return laws, edges


def _power_integral(c, q, lo, hi):
    if hi <= lo:
        return mp.mpf(0)
    if q == -1:
        return c * mp.log(hi / lo)
    return c * (hi ** (q + 1) - lo ** (q + 1)) / (q + 1)


def stiffness(D, G, E, nu, H, area, l_min, load, interaction="paper", dps=30):
    """K (N/m) of model xia2024, distribution "mb", at one load (N), to `dps` digits."""
    with mp.workdps(dps):
        D, G, E, nu, H, area, l_min, load = (mp.mpf(x) for x in (D, G, E, nu, H, area, l_min, load))
        laws, edges = _laws(D, G, E, nu, H)
        a_min = l_min**2
        n_exp = -(D + 2) / 2

        def clipped(i, a_l):
            return max(edges[i], a_min), min(edges[i + 1], a_l)

        def total_load(log_a_l):
            a_l = mp.e**log_a_l
            n_coeff = D / 2 * a_l ** (D / 2)
            return sum(_power_integral(c * n_coeff, m + n_exp, *clipped(i, a_l)) for i, (c, m) in enumerate(laws))

        log_a_l = mp.findroot(
            lambda x: mp.log(total_load(x)) - mp.log(load),
            mp.log(a_min) / 2 + mp.log(area) / 2,
            tol=mp.mpf(10) ** (-dps + 5),
        )
        a_l = mp.e**log_a_l
        n_coeff = D / 2 * a_l ** (D / 2)
        xi_slope = G ** (D - 1) * (2 - D) / 2  # ξ'(a) = xi_slope a^(-D/2)
        sign = SIGNS[interaction]
        pressure = load / area
        K = mp.mpf(0)
        for i, (c, m) in enumerate(laws[:3]):
            lo, hi = clipped(i, a_l)
            if hi <= lo:
                continue
            k0 = c * m / xi_slope  # k₀(a) = f'(a)/ξ'(a) = k0 a^(m - 1 + D/2)
            K += _power_integral(k0 * n_coeff, m - 1 + D / 2 + n_exp, lo, hi)
            if sign:
                ratio = mp.mpf("1.12") * mp.sqrt(c * pressure) / E * (m / 2) / xi_slope  # r(a) = ratio a^((m+D)/2 - 1)
                e = (m + D) / 2 - 1

                def correction(t):
                    a = mp.e**t
                    sr = sign * ratio * a**e
                    return k0 * n_coeff * a ** (m - 1 + D / 2 + n_exp + 1) * (-sr / (1 + sr))

                K += mp.quad(correction, [mp.log(lo), mp.log(hi)])
        return float(K), float(a_l)
