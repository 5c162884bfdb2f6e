"""Greenwood–Williamson with measured asperity statistics (`jc.MeasuredAsperities`) against closed
forms, scipy's quadrature of the tabulated PDF and central differences; on the Brake–Reuss joint's
measured statistics where ../shared/data is present."""

import math
import pathlib

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1
from scipy import integrate, optimize

import jaxcontact as jc
from jaxcontact.numerics import x64

E, AREA, R, ETA = 1e11, 1e-4, 1e-4, 1e9  # Pa, m², m, summits per m²
HEIGHTS = np.linspace(0.0, 2e-6, 201)  # m
GAUSSIAN = np.exp(-0.5 * ((HEIGHTS - 0.8e-6) / 0.3e-6) ** 2)  # normalised by the model
LOADS = np.array([0.3, 3.0, 30.0])  # N
JOINT = pathlib.Path(__file__).resolve().parents[2] / "shared" / "data" / "joints" / "brb_surface_data.mat"


def scene_of(model, area=AREA, E=E):
    surface = jc.Surface(D=TABLE1["D"], G=TABLE1["G"], l_min=TABLE1["l_min"])  # not used by the model
    return jc.Scene(surface, jc.Material(E=E, nu=0.3, H=3e9), area, model=model)


class ScipyGW:
    """Greenwood–Williamson on a tabulated summit-height PDF by scipy: each J_n(d) = ∫_d (z − d)^n φ dz
    by quad over the linear interpolant of the PDF (normalised by the trapezoidal rule), the flat's
    height d at a load F by brentq on F(d). `summit(w)`, where given, is one summit's (load, area) at
    the interference w (SI), whose integrals `summed` takes with `breaks`, the w where it jumps."""

    def __init__(self, z, pdf, radius, density, E, area, summit=None, breaks=()):
        self.z, self.pdf = z, pdf / np.trapezoid(pdf, z)
        self.scale = area * density * E * math.sqrt(radius)
        self.summit, self.breaks, self.count = summit, breaks, area * density

    def J(self, n, d):
        return self._integral(lambda w: w**n, d)

    def _integral(self, f, d):
        z = self.z
        if d >= z[-1]:
            return 0.0
        start = max(d, z[0])
        points = [x for x in np.concatenate([z, d + np.asarray(self.breaks)]) if start < x < z[-1]]
        integrand = lambda x: f(x - d) * np.interp(x, z, self.pdf)  # noqa: E731
        return integrate.quad(
            integrand, start, z[-1], points=sorted(points) or None, limit=8 * z.size, epsabs=0.0, epsrel=1e-12
        )[0]

    def summed(self, f, d):
        """Σ over the summits of `f(w)`, w = z − d (f of one summit's law: `self.summit(w)[i]`)."""
        return self.count * self._integral(f, d)

    def load(self, d):
        if self.summit is None:
            return self.scale * 4 / 3 * self._integral(lambda w: w**1.5, d)
        return self.summed(lambda w: self.summit(w)[0], d)

    def separation(self, F):
        low = self.z[0] - 10 * (self.z[-1] - self.z[0])  # below the lowest summit: every one in contact
        return optimize.brentq(lambda d: self.load(d) - F, low, self.z[-1], xtol=1e-18, rtol=1e-15)

    def stiffness(self, F):
        return self.scale * 2 * self.J(0.5, self.separation(F))


def _scipy_stiffness(F, z, pdf, radius, density, E, area):
    return ScipyGW(z, pdf, radius, density, E, area).stiffness(F)


def test_the_stiffness_is_scipys_quadrature_of_the_table():
    scene = scene_of(jc.MeasuredAsperities(R, ETA, HEIGHTS, GAUSSIAN))
    expected = [_scipy_stiffness(F, HEIGHTS, GAUSSIAN, R, ETA, E, AREA) for F in LOADS]
    np.testing.assert_allclose(jc.solve(scene, LOADS).stiffness, expected, rtol=1e-8)


def test_a_uniform_pdf_gives_k_proportional_to_f_to_the_three_fifths():
    """φ = 1/Δ on [0, Δ]: F = A η (4/3) E √R s^(5/2)/(5Δ/2), K = A η 2E √R s^(3/2)/(3Δ/2), s = Δ − d."""
    delta = HEIGHTS[-1]
    scene = scene_of(jc.MeasuredAsperities(R, ETA, HEIGHTS, np.ones_like(HEIGHTS)))
    s = (LOADS * 2.5 * delta / (AREA * ETA * 4 / 3 * E * math.sqrt(R))) ** 0.4
    expected = AREA * ETA * 2 * E * math.sqrt(R) * s**1.5 / (1.5 * delta)
    np.testing.assert_allclose(jc.solve(scene, LOADS).stiffness, expected, rtol=1e-10)


def test_the_gradient_in_the_radius_is_central_differences():
    scene = scene_of(jc.MeasuredAsperities(R, ETA, HEIGHTS, GAUSSIAN))

    @jax.jit
    @jax.value_and_grad
    def K(radius):
        return jc.solve(eqx.tree_at(lambda s: s.model.radius, scene, radius), 3.0).stiffness

    h = 1e-6 * R
    central = (K(jnp.asarray(R + h))[0] - K(jnp.asarray(R - h))[0]) / (2 * h)
    np.testing.assert_allclose(K(jnp.asarray(R))[1], central, rtol=1e-6)


def test_float32_agrees_with_float64():
    reference = jc.solve(scene_of(jc.MeasuredAsperities(R, ETA, HEIGHTS, GAUSSIAN)), LOADS).stiffness
    with x64(False):
        model = jc.MeasuredAsperities(R, ETA, HEIGHTS, GAUSSIAN)
        single = jc.solve(scene_of(model), LOADS.astype(np.float32)).stiffness
    np.testing.assert_allclose(single, reference, rtol=1e-4)


def test_a_load_beyond_every_summit_in_contact_is_scipys():
    """The flat below the lowest summit: every summit in contact, GW's sums over the whole table."""
    scene = scene_of(jc.MeasuredAsperities(R, ETA, HEIGHTS, GAUSSIAN))
    reference = ScipyGW(HEIGHTS, GAUSSIAN, R, ETA, E, AREA)
    assert reference.separation(2e5) < HEIGHTS[0]
    expected = reference.scale * 2 * reference.J(0.5, reference.separation(2e5))
    np.testing.assert_allclose(float(jc.solve(scene, 2e5).stiffness), expected, rtol=1e-8)


def test_a_load_beyond_a_closed_interface_is_flagged():
    """At 1e6 N the summits' contact areas would add up to more than the nominal area."""
    scene = scene_of(jc.MeasuredAsperities(R, ETA, HEIGHTS, GAUSSIAN))
    assert int(jc.solve(scene, 1e6).status) == jc.Status.LOAD_OUT_OF_RANGE


@pytest.mark.parametrize(
    "arguments, message",
    [
        ((-1.0, ETA, HEIGHTS, GAUSSIAN), r"radius = -1.0 must be in \(0, inf\)"),
        ((R, ETA, HEIGHTS[::-1], GAUSSIAN), r"heights must be finite and increasing"),
        ((R, ETA, HEIGHTS, -GAUSSIAN), r"pdf must be finite, >= 0 and not all 0"),
        ((R, ETA, HEIGHTS, GAUSSIAN[:-1]), r"heights and pdf have shapes \(201,\) and \(200,\)"),
    ],
)
def test_bad_statistics_are_refused_by_name(arguments, message):
    with pytest.raises(ValueError, match=message):
        jc.MeasuredAsperities(*arguments)


@pytest.mark.skipif(not JOINT.is_file(), reason=f"{JOINT} is absent: the measured joint data live beside the project")
def test_the_brake_reuss_joint_at_its_bolt_preload_is_scipys():
    """The measured statistics (Porter & Brake 2023) over the patch of 362 summits, at 12.25 kN; the
    file's `normzinterp · z_max` is each summit's initial gap, as tmdsimpy's example reads it."""
    from scipy import io

    data = io.loadmat(JOINT)
    gaps = data["normzinterp"].ravel() * data["z_max"].item()
    pdf = data["pzinterp"].ravel() / data["z_max"].item()
    radius, density = data["Re"].item(), data["area_density"].item()
    E_star, area = 192.31e9 / (2 * (1 - 0.3**2)), 362 / density
    scene = scene_of(jc.MeasuredAsperities.from_gaps(radius, density, gaps, pdf), area=area, E=E_star)
    z, pdf = gaps[-1] - gaps[::-1], pdf[::-1]
    expected = _scipy_stiffness(12250.0, z, pdf, radius, density, E_star, area)
    np.testing.assert_allclose(float(jc.solve(scene, 12250.0).stiffness), expected, rtol=1e-8)
