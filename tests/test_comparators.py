"""The comparators of docs/model.md §9 against independent evaluations of their formulas (scipy), and
the Sneddon option's exact relation to the paper's spot stiffness."""

import math

import numpy as np
import pytest
from helpers import BEM_L, BEM_SETTING, TABLE1, make_scene
from scipy import integrate, optimize, special

import jaxcontact as jc
from jaxcontact.models._greenwood_williamson import log_tail_moment
from jaxcontact.physics._spectrum import profile_moments
from jaxcontact.quantities import nondimensionalise
from jaxcontact.topography import areal_prefactor

L = BEM_L


def quad(f, lo, hi):
    return integrate.quad(f, lo, hi, epsabs=0.0, epsrel=1e-13, limit=500)[0]


def psd_moment_by_quadrature(v, power):
    """(1/2π) ∫ q^(power) C2D(q) dq over [2π/L, 2π/l_min], C2D from topography.conventions (SI)."""
    C0 = areal_prefactor(v["D"], v["G"])
    q0, q1 = 2 * math.pi / math.sqrt(v["area"]), 2 * math.pi / v["l_min"]
    # in ln q: many decades
    return quad(lambda t: C0 * math.exp((power + 1 - (6 - 2 * v["D"])) * t), math.log(q0), math.log(q1)) / (2 * math.pi)


@pytest.mark.parametrize("order", [0.5, 1.0, 1.5])
@pytest.mark.parametrize("h", [-1.0, 0.0, 1.3, 4.0, 9.0])
def test_gaussian_tail_moment_matches_scipy(order, h):
    expected = quad(lambda t: t**order * math.exp(-((h + t) ** 2) / 2) / math.sqrt(2 * math.pi), 0.0, np.inf)
    np.testing.assert_allclose(math.exp(float(log_tail_moment(order, np.float64(h)))), expected, rtol=1e-10)


@pytest.mark.parametrize("index, power", [(0, 1), (1, 3), (2, 5)])
def test_spectral_moments_are_the_power_law_psd_integrals(index, power):
    """m0, m2, m4 (SI) against the integrals of C2D = C0 q^-(6-2D) by quadrature, with the
    directional averages 1, 1/2, 3/8 of a line scan of an isotropic surface."""
    v = BEM_SETTING
    s = nondimensionalise(make_scene(**v))
    moment = float(profile_moments(s.D, s.log_G, s.log_a_min)[index]) * L ** (2 - 2 * index)
    expected = psd_moment_by_quadrature(v, power) * (1.0, 0.5, 3.0 / 8.0)[index]
    np.testing.assert_allclose(moment, expected, rtol=1e-10)


def test_rms_slope_of_the_moments_matches_synthesised_surfaces():
    """<|∇h|²> = 2 m2 against the spectra of three synthesised 512² maps (their FFT slope)."""
    from jaxcontact.bem import synthesised_surface

    v = BEM_SETTING
    s = nondimensionalise(make_scene(**v))
    predicted = math.sqrt(2 * float(profile_moments(s.D, s.log_G, s.log_a_min)[1]))
    measured = []
    for seed in range(3):
        h = synthesised_surface(v["D"], v["G"], v["l_min"], L, 512, seed).heights()
        q = 2 * np.pi * np.fft.fftfreq(512, L / 512)
        power = np.abs(np.fft.fft2(h) / h.size) ** 2
        measured.append(math.sqrt(np.sum(power * (q[:, None] ** 2 + q[None, :] ** 2))))
    np.testing.assert_allclose(np.mean(measured), predicted, rtol=0.05)


def gw_by_scipy(v, F):
    """Greenwood–Williamson from McCool's relations, its integrals by quadrature, d by brentq."""
    m0 = psd_moment_by_quadrature(v, 1)
    m2 = psd_moment_by_quadrature(v, 3) / 2
    m4 = psd_moment_by_quadrature(v, 5) * 3 / 8
    alpha = m0 * m4 / m2**2
    eta = m4 / (6 * math.pi * math.sqrt(3) * m2)
    R = 0.375 * math.sqrt(math.pi / m4)
    sigma = math.sqrt(1 - 0.8968 / alpha) * math.sqrt(m0)
    E, A = v["E"], v["area"]

    def phi(z):
        return math.exp(-0.5 * (z / sigma) ** 2) / (sigma * math.sqrt(2 * math.pi))

    def load(d):
        return 4 / 3 * E * eta * A * math.sqrt(R) * quad(lambda z: (z - d) ** 1.5 * phi(z), d, d + 40 * sigma)

    d = optimize.brentq(lambda d: math.log(load(d) / F), -sigma, 12 * sigma, xtol=1e-16 * sigma, rtol=1e-14)
    return 2 * E * eta * A * math.sqrt(R) * quad(lambda z: (z - d) ** 0.5 * phi(z), d, d + 40 * sigma)


def persson_by_scipy(v, F, gamma=0.45):
    """docs/model.md §9's formula as printed, in q, by quadrature (SI units)."""
    C0 = areal_prefactor(v["D"], v["G"]) / (2 * math.pi) ** 2
    q0, q1 = 2 * math.pi / math.sqrt(v["area"]), 2 * math.pi / v["l_min"]
    e = 2 * v["D"] - 2
    p, E = F / v["area"], v["E"]

    def w(q):
        return (math.pi * C0 * (q**e - q0**e) / e) ** -0.5

    def integrand(t):  # in t = ln q
        q = math.exp(t)
        x = w(q) * p / E
        return (
            q**3
            * C0
            * q ** -(6 - 2 * v["D"])
            * w(q)
            * (gamma + 3 * (1 - gamma) * special.erf(x) ** 2)
            * math.exp(-x * x)
        )

    # The cut-off near q0 sits where w(q) p/E ~ 1: split there so that quad sees it.
    split = math.log(q0) + (p / E) ** 2 * 1e3
    lo = math.log(q0) * (1 + 1e-15)
    J = math.sqrt(math.pi) * (
        quad(integrand, lo, min(split, math.log(q1))) + quad(integrand, min(split, math.log(q1)), math.log(q1))
    )
    return v["area"] * p / J


@pytest.mark.parametrize("F_star", [1e-5, 3e-4])
@pytest.mark.parametrize("model, oracle, rtol", [("gw", gw_by_scipy, 1e-8), ("persson", persson_by_scipy, 1e-7)])
def test_comparator_matches_its_formula_by_scipy(model, oracle, rtol, F_star):
    v = BEM_SETTING
    F = F_star * v["E"] * v["area"]
    sol = jc.solve(make_scene(**v, model=model), F)
    np.testing.assert_allclose(float(sol.stiffness), oracle(v, F), rtol=rtol)


def test_persson_stiffness_is_linear_in_pressure_at_small_loads():
    v = BEM_SETTING
    F = np.array([1e-9, 1e-8]) * v["E"] * v["area"]
    K = np.asarray(jc.solve(make_scene(**v, model="persson"), F).stiffness)
    np.testing.assert_allclose(K[1] / K[0], 10.0, rtol=1e-3)


def test_sneddon_elastic_stiffness_is_the_papers_over_the_family_factor():
    """Interaction "none": each regime's stiffness; in the elastic one exactly (2π/3)(3-D)/(2-D)."""
    loads = np.array([1e-7, 1e-5]) * TABLE1["E"] * TABLE1["area"]
    paper = jc.solve(make_scene(**TABLE1, interaction="none"), loads)
    sneddon = jc.solve(make_scene(**TABLE1, interaction="none", spot_stiffness="sneddon"), loads)
    elastic_paper = np.asarray(paper.stiffness * paper.stiffness_share[:, 0])
    elastic_sneddon = np.asarray(sneddon.stiffness * sneddon.stiffness_share[:, 0])
    D = TABLE1["D"]
    np.testing.assert_allclose(elastic_paper / elastic_sneddon, 2 * math.pi / 3 * (3 - D) / (2 - D), rtol=1e-12)


def test_sneddon_leaves_the_load_and_the_largest_spot_alone():
    loads = np.array([1e-7, 1e-5]) * TABLE1["E"] * TABLE1["area"]
    paper = jc.solve(make_scene(**TABLE1, interaction="series"), loads)
    sneddon = jc.solve(make_scene(**TABLE1, interaction="series", spot_stiffness="sneddon"), loads)
    np.testing.assert_allclose(np.asarray(sneddon.a_l), np.asarray(paper.a_l), rtol=1e-13)


def test_an_unknown_spot_stiffness_names_the_choices():
    with pytest.raises(ValueError, match="spot_stiffness = 'hertz' is not one of 'paper', 'sneddon'"):
        make_scene(**TABLE1, spot_stiffness="hertz")


def persson_area_by_scipy(v, F):
    """A_r/A_a = erf(w(q1) p/E) of docs/model.md §9, w(q1) by the power law's closed form (SI units)."""
    C0 = areal_prefactor(v["D"], v["G"]) / (2 * math.pi) ** 2
    q0, q1 = 2 * math.pi / math.sqrt(v["area"]), 2 * math.pi / v["l_min"]
    e = 2 * v["D"] - 2
    w1 = (math.pi * C0 * (q1**e - q0**e) / e) ** -0.5
    return special.erf(w1 * F / v["area"] / v["E"])


CLOSING_LOADS = np.geomspace(1e-3, 0.05, 12)


def test_a_closed_persson_interface_is_flagged_and_an_open_one_is_not():
    """A load at which Persson's own A_r/A_a (by scipy) reaches 0.99 is out of range; below, valid.
    (GW's summits leave its range, the flat past the mean summit plane, at A_r/A_a of 0.3-0.5.)"""
    v = BEM_SETTING
    loads = CLOSING_LOADS * v["E"] * v["area"]
    status = np.asarray(jc.solve(make_scene(**v, model="persson"), loads).status)
    closed = np.array([persson_area_by_scipy(v, F) >= jc.models.CLOSED_INTERFACE for F in loads])
    np.testing.assert_array_equal(status, np.where(closed, jc.Status.LOAD_OUT_OF_RANGE, jc.Status.OK))


def test_the_closing_sweep_reaches_both_sides_of_the_threshold():
    """The sweep above tests something: it holds open and closed interfaces."""
    v = BEM_SETTING
    fractions = [persson_area_by_scipy(v, F) for F in CLOSING_LOADS * v["E"] * v["area"]]
    assert min(fractions) < 0.5 and max(fractions) >= jc.models.CLOSED_INTERFACE
