"""The tangential boundary-element stiffness in full stick (`bem.solve(..., poisson=ν)`): the pixel
kernel's closed form against scipy's quadrature, a Hertz contact against Mindlin's 8G*a / (2E*a),
ridges against the plane-strain and antiplane half-space, a rough surface against Campañá, Persson
& Müser's ratio, the derivative in ν against central differences, float32, bad ν."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import BEM_L as L
from helpers import BEM_SETTING
from scipy import integrate

import jaxcontact as jc
from jaxcontact import bem
from jaxcontact.bem._tangential import pixel_anisotropy
from jaxcontact.numerics import x64

E = BEM_SETTING["E"]
NU = 0.3
N = 64


def centred_grid(n):
    x = (np.arange(n) + 0.5) / n - 0.5
    return x[:, None], x[None, :]


@pytest.mark.parametrize("x, y", [(0, 0), (1, 0), (0, 1), (3, -2), (-7, 5)])
def test_the_pixel_kernel_is_the_integral_of_x2_over_r3(x, y):
    # Split at the pixel's centre so that quadrature never meets the self pixel's singularity at a node.
    def f(t, s):
        return s * s / (s * s + t * t) ** 1.5 / math.pi

    quarters = [
        integrate.dblquad(f, sx0, sx1, ty0, ty1, epsabs=1e-12, epsrel=1e-11)[0]
        for sx0, sx1 in ((x - 0.5, x), (x, x + 0.5))
        for ty0, ty1 in ((y - 0.5, y), (y, y + 0.5))
    ]
    np.testing.assert_allclose(pixel_anisotropy(float(x), float(y)), sum(quarters), rtol=1e-8)


@pytest.fixture(scope="module")
def hertz():
    # A paraboloid (R = 1, E* = 1) on a free half-space, two loads: contact radii of 9 and 13 cells.
    x, y = centred_grid(N)
    heights = jnp.asarray(-(x * x + y * y) / 2)
    loads = 4 * np.array([0.14, 0.2]) ** 3 / 3
    return bem.solve(heights, 1.0, 1.0, jnp.asarray(loads), poisson=NU, substrate=bem.Free())


def test_a_hertz_contact_in_full_stick_has_mindlins_ratio(hertz):
    # Mindlin: 8G*a in full stick against Sneddon's 2E*a, 2(1 − ν)/(2 − ν) for like materials.
    ratio = np.asarray(hertz.tangential_stiffness / hertz.stiffness)
    np.testing.assert_allclose(ratio, 2 * (1 - NU) / (2 - NU), rtol=2e-3)


def test_a_hertz_contact_in_full_stick_has_mindlins_stiffness(hertz):
    a = np.sqrt(np.asarray(hertz.contact_fraction) / math.pi)
    shear = (1 - NU) / (2 * (2 - NU))  # G*/E* of like materials
    np.testing.assert_allclose(np.asarray(hertz.tangential_stiffness), 8 * shear * a, rtol=3e-2)


def ridge(axis):
    # A periodic ridge (a cosine along one axis, constant along the other): a strip of contact.
    x = (np.arange(N) + 0.5) / N
    profile = np.cos(2 * math.pi * x) * 1e-7
    return jnp.asarray(np.broadcast_to(profile[:, None] if axis == 0 else profile[None, :], (N, N)))


LOADS = jnp.asarray([0.002, 0.02]) * E * L * L


def test_a_traction_across_a_ridge_is_plane_strain():
    # Heights varying along the rows: the shear along the rows is in-plane, compliance 2/(E*|q|), K_t = K_n.
    solution = bem.solve(ridge(0), L, E, LOADS, poisson=NU)
    np.testing.assert_allclose(np.asarray(solution.tangential_stiffness), np.asarray(solution.stiffness), rtol=1e-7)


def test_a_traction_along_a_ridge_is_antiplane():
    # Heights varying along the columns: the shear along the rows is antiplane, compliance 2/((1 − ν)E*|q|).
    solution = bem.solve(ridge(1), L, E, LOADS, poisson=NU)
    np.testing.assert_allclose(
        np.asarray(solution.tangential_stiffness), (1 - NU) * np.asarray(solution.stiffness), rtol=1e-7
    )


@pytest.fixture(scope="module")
def rough():
    return bem.synthesised_surface(1.5, 1e-10, L / 16, L, N, seed=1).heights()


# 0.1-3 % contact on the rough map (F* = F/(E* A_a) times its rms slope 0.34).
ROUGH_LOADS = jnp.asarray([7e-5, 7e-4, 7e-3]) * E * L * L


def test_a_rough_contact_in_full_stick_has_mindlins_ratio(rough):
    # Campañá, Persson & Müser (2011): K_t/K_n of an elastic rough contact is the spot's ratio, for
    # an isotropic surface. One realisation on a periodic square is not isotropic at its longest
    # wavelengths (one direction alone differs by up to 5 %): its two directions averaged are.
    along, across = (bem.solve(h, L, E, ROUGH_LOADS, poisson=NU) for h in (rough, rough.T))
    assert np.asarray(along.contact_fraction).min() > 5e-4
    ratio = (along.tangential_stiffness + across.tangential_stiffness) / (along.stiffness + across.stiffness)
    np.testing.assert_allclose(np.asarray(ratio), 2 * (1 - NU) / (2 - NU), rtol=1e-2)


def test_the_derivative_in_poisson_matches_central_differences(rough):
    def stick(nu):
        return bem.solve(rough, L, E, ROUGH_LOADS[1:], poisson=nu).tangential_stiffness[0]

    step = 1e-3
    fd = (stick(NU + step) - stick(NU - step)) / (2 * step)
    np.testing.assert_allclose(float(jax.grad(stick)(jnp.asarray(NU))), float(fd), rtol=1e-5)


def test_float32_agrees_with_float64(rough):
    expected = bem.solve(rough, L, E, ROUGH_LOADS, poisson=NU).tangential_stiffness
    with x64(False):
        arguments = (np.float32(x) for x in (rough, L, E, ROUGH_LOADS))
        got = bem.solve(*arguments, poisson=np.float32(NU))
        np.testing.assert_allclose(np.asarray(got.tangential_stiffness), np.asarray(expected), rtol=1e-3)


@pytest.mark.parametrize("nu", [-0.1, 0.5, float("nan")])
def test_a_poisson_ratio_outside_its_range_is_refused(rough, nu):
    with pytest.raises(ValueError, match="poisson"):
        bem.solve(rough, L, E, ROUGH_LOADS, poisson=nu)


def test_a_traced_poisson_ratio_outside_its_range_is_flagged(rough):
    solution = jax.jit(lambda nu: bem.solve(rough, L, E, ROUGH_LOADS, poisson=nu))(jnp.asarray(0.6))
    assert np.asarray(solution.status).tolist() == [jc.Status.INVALID_PARAMETERS] * 3
