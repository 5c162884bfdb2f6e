"""A lap-jointed beam's first bending frequency (`applications.lap_beam_frequency`): the free–free
beam for a rigid joint, rigid halves on a hinge for a soft one, and its derivative."""

import math

import jax
import numpy as np

from jaxcontact.applications import lap_beam_frequency

BEAM = dict(half_length=0.3556, width=0.0254, height=0.0254, modulus=192.31e9, density=7800.0)
EI = BEAM["modulus"] * BEAM["width"] * BEAM["height"] ** 3 / 12
MASS = BEAM["density"] * BEAM["width"] * BEAM["height"]  # per metre


def test_a_rigid_joint_gives_the_free_free_beam():
    length = 2 * BEAM["half_length"]
    expected = 4.730040744862704**2 / (2 * math.pi * length**2) * math.sqrt(EI / MASS)
    np.testing.assert_allclose(float(lap_beam_frequency(1e13, **BEAM)), expected, rtol=1e-6)


def test_a_soft_joint_gives_rigid_halves_turning_on_a_hinge():
    # Each half turns about its own centre: ω² = 2k / (ρA ℓ³/12).
    k = 1.0
    expected = math.sqrt(24 * k / (MASS * BEAM["half_length"] ** 3)) / (2 * math.pi)
    np.testing.assert_allclose(float(lap_beam_frequency(k, **BEAM)), expected, rtol=1e-4)


def test_the_derivative_in_the_joint_stiffness_matches_central_differences():
    k, h = 1e6, 1e-3
    central = (lap_beam_frequency(k + h * k, **BEAM) - lap_beam_frequency(k - h * k, **BEAM)) / (2 * h * k)
    exact = jax.grad(lambda x: lap_beam_frequency(x, **BEAM))(k)
    np.testing.assert_allclose(float(exact), float(central), rtol=1e-5)
