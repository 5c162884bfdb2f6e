"""Partial slip and friction loops of a boundary-element contact (`bem.friction_loops`): a rough
map against a dense box-constrained least-squares solve of the same Coulomb problem (scipy's BVLS),
a Hertz contact against Cattaneo–Mindlin and Mindlin–Deresiewicz, derivatives against central
differences, gross slip flagged, float32, bad input refused by name."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import refused_type
from scipy import linalg, optimize

import jaxcontact as jc
from jaxcontact import bem
from jaxcontact.numerics import x64

NU, MU = 0.3, 0.4
N = 16  # the dense oracle's grid


@pytest.fixture(scope="module")
def rough():
    """A 16² periodic map in grid units (E* = 1, spacing 1) at 11 % contact, and its loops."""
    heights = np.asarray(bem.realisation(1.5, 1e-2, 4.0, float(N), N, 3).heights())
    load = 0.03 * N * N * heights.std()
    pressure = np.asarray(bem.solve(heights, float(N), 1.0, np.array([load]), pressure=True).pressure[0])
    forces = np.array([0.2, 0.5, 0.8]) * MU * load
    loops = bem.friction_loops(heights, float(N), 1.0, load, MU, forces, poisson=NU)
    return heights, load, pressure, forces, loops


def dense_slip(pressure, displacement):
    """The tractions `0 ≤ q ≤ μp` on the contact set that minimise `½ qᵀCq − δ Σq`: the tangential
    compliance C of the periodic half-space (Johnson's point load along x, Fourier transformed:
    `(2/|q|)(1 + ν/(1 − ν) q_y²/|q|²)`) as a dense matrix, and BVLS on its Cholesky factor."""
    k = np.fft.fftfreq(N) * 2 * math.pi
    k_y = np.fft.rfftfreq(N) * 2 * math.pi
    q2 = k[:, None] ** 2 + k_y[None, :] ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        kernel = np.where(q2 > 0, 2 / np.sqrt(q2) * (1 + NU / (1 - NU) * k_y[None, :] ** 2 / q2), 0.0)
    columns = [np.fft.irfft2(np.fft.rfft2(e.reshape(N, N)) * kernel, s=(N, N)).ravel() for e in np.eye(N * N)]
    contact = pressure.ravel() > 0
    factor = linalg.cholesky(np.stack(columns, axis=1)[np.ix_(contact, contact)], lower=True)
    target = linalg.solve_triangular(factor, displacement * np.ones(contact.sum()), lower=True)
    cap = MU * pressure.ravel()[contact]
    return optimize.lsq_linear(factor.T, target, bounds=(0, cap), method="bvls", tol=1e-15).x, cap


def test_every_amplitude_below_gross_slip_is_ok(rough):
    assert np.all(np.asarray(rough[4].status) == 0)


def test_the_tip_displacement_carries_the_force_in_the_dense_solve(rough):
    """At the loop's tip u₀ the dense solve's tractions add up to Q₀."""
    _, _, pressure, forces, loops = rough
    carried = [dense_slip(pressure, u)[0].sum() for u in np.asarray(loops.displacement)]
    np.testing.assert_allclose(carried, forces, rtol=1e-8)


def test_the_stick_share_is_the_dense_solves(rough):
    _, _, pressure, _, loops = rough
    shares = []
    for u in np.asarray(loops.displacement):
        q, cap = dense_slip(pressure, u)
        shares.append(np.mean((q > 0) & (q < cap * (1 - 1e-9))))
    np.testing.assert_allclose(loops.stick_share, shares, atol=1e-12)


def test_a_force_beyond_gross_slip_is_flagged_and_leaves_the_others(rough):
    heights, load, _, forces, loops = rough
    mixed = bem.friction_loops(heights, float(N), 1.0, load, MU, np.append(forces, 1.1 * MU * load), poisson=NU)
    assert int(mixed.status[-1]) == jc.Status.LOAD_OUT_OF_RANGE
    np.testing.assert_allclose(mixed.dissipation[:-1], loops.dissipation, rtol=1e-6)  # warm starts differ


def loops_at(heights, load, x):
    """The dissipation at 0.5 μF and the tip displacement at 0.8 μF as a function of
    `x = (load factor, μ, force factor, ν, a step of the heights along a fixed direction)`."""
    direction = np.cos(np.arange(N * N).reshape(N, N))
    forces = np.array([0.2, 0.5, 0.8]) * MU * load
    loops = bem.friction_loops(
        heights + x[4] * direction, float(N), 1.0, load * x[0], x[1], forces * x[2], poisson=x[3]
    )
    return jnp.stack([loops.dissipation[1], loops.displacement[2]])


def test_the_derivatives_are_central_differences(rough):
    heights, load = rough[0], rough[1]
    x0 = jnp.array([1.0, MU, 1.0, NU, 0.0])
    derivatives = jax.jacfwd(lambda x: loops_at(heights, load, x))(x0)
    steps = np.array([1e-6, 1e-6 * MU, 1e-6, 1e-6 * NU, 1e-6])
    expected = np.stack(
        [
            (loops_at(heights, load, x0 + e) - loops_at(heights, load, x0 - e)) / (2 * h)
            for e, h in zip(np.diag(steps), steps)
        ],
        axis=1,
    )
    np.testing.assert_allclose(derivatives, expected, rtol=1e-5)


def test_float32_follows_float64(rough):
    heights, load, _, forces, loops = rough
    with x64(False):
        single = bem.friction_loops(*(np.float32(x) for x in (heights, N, 1.0, load, MU)), forces, poisson=NU)
    np.testing.assert_allclose(single.displacement, loops.displacement, rtol=1e-3)


# A Hertz contact on a free half-space, 64², contact radius 13 cells (E* = 1, unit side).
HERTZ_N, RADIUS = 64, 4.0
AMPLITUDES = np.array([0.3, 0.5, 0.7, 0.9])  # of μF


@pytest.fixture(scope="module")
def hertz():
    x = (np.arange(HERTZ_N) - HERTZ_N / 2 + 0.5) / HERTZ_N
    heights = -(x[:, None] ** 2 + x[None, :] ** 2) / (2 * RADIUS)
    a = 13 / HERTZ_N
    load = 4 * a**3 / (3 * RADIUS)
    loops = bem.friction_loops(
        heights, 1.0, 1.0, load, MU, AMPLITUDES * MU * load, poisson=NU, substrate=bem.Free(), nodes=16
    )
    # Two like bodies of E* = 1: E = 2(1 − ν²), and Mindlin's 1/G* = 2(2 − ν)/G.
    shear = 2 * (1 - NU**2) / (2 * (1 + NU))
    g_star = shear / (2 * (2 - NU))
    u_star = 3 * MU * load / (16 * g_star * a)
    return loops, load, u_star, g_star, a


def cattaneo_mindlin(Q, load, u_star):
    return u_star * (1 - (1 - Q / (MU * load)) ** (2 / 3))


def test_the_hertz_stick_stiffness_is_mindlins(hertz):
    loops, _, _, g_star, a = hertz
    np.testing.assert_allclose(loops.stick_stiffness, 8 * g_star * a, rtol=0.01)


def test_the_hertz_backbone_is_cattaneo_mindlins(hertz):
    loops, load, u_star, _, _ = hertz
    np.testing.assert_allclose(loops.displacement, cattaneo_mindlin(AMPLITUDES * MU * load, load, u_star), rtol=0.01)


def test_the_hertz_loop_encloses_mindlin_deresiewiczs_energy(hertz):
    """Mindlin & Deresiewicz (1953) at the displacement amplitude x = u₀/u* < 1 the backbone reaches:
    W = μP u* [4x − (16/5)(1 − (1 − x)^(5/2)) + 4x (1 − x)^(3/2)]."""
    loops, load, u_star, _, _ = hertz
    x = 1 - (1 - AMPLITUDES) ** (2 / 3)
    expected = MU * load * u_star * (4 * x - 16 / 5 * (1 - (1 - x) ** 2.5) + 4 * x * (1 - x) ** 1.5)
    np.testing.assert_allclose(loops.dissipation, expected, rtol=0.05)


def test_the_hertz_stick_zone_is_mindlins(hertz):
    """The stick zone's radius c: (c/a)² = (1 − Q/μP)^(2/3)."""
    loops = hertz[0]
    np.testing.assert_allclose(loops.stick_share, (1 - AMPLITUDES) ** (2 / 3), atol=0.03)


@pytest.mark.parametrize("change, name", [({"mu": 0.0}, "mu"), ({"nodes": 1}, "nodes"), ({"poisson": 0.5}, "poisson")])
def test_bad_input_is_refused_by_name(change, name):
    arguments = dict(ARGUMENTS, **change)
    with pytest.raises(ValueError, match=name):
        bem.friction_loops(**arguments)


def test_forces_that_are_not_1d_are_refused():
    with refused_type("forces", r"forces has shape \(2, 2\)"):
        bem.friction_loops(**dict(ARGUMENTS, forces=np.ones((2, 2))))


ARGUMENTS = dict(heights=np.ones((8, 8)), size=1.0, modulus=1.0, load=1.0, mu=0.3, forces=np.array([0.1]), poisson=0.3)
