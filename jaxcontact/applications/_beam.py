"""A lap-jointed beam's first bending frequency through its joint's rotational stiffness: a simple
structural model for a joint's stiffness (docs/bolted-joint.md).

Two identical uniform Euler–Bernoulli beams (free outer ends) joined end to end by a rotational
spring k (N·m/rad) that resists their relative rotation; the joint has no length, mass or
compliance of its own otherwise. In the first symmetric bending mode each half (0 ≤ x ≤ ℓ from the
joint) has no shear at the joint, `EI w''(0) = 2k w'(0)` there and a free end at ℓ. With
`w = A cosh βx + B sinh βx + C cos βx + D sin βx`, `z = βℓ` and `κ = 4kℓ/(EI z)` the frequency
equation is `(ch − c)(κ sh + ch − c) − (sh + s)(κ ch + sh − s) = 0` (ch = cosh z, …); its first
root lies between 0 (k → 0: the halves turn on a hinge) and 2.365 (k → ∞: the free–free beam of
length 2ℓ, `βL = 4.730`). The frequency is `z² √(EI/(ρA)) / (2π ℓ²)`.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp

from ..numerics import check_positive

_RIGID = 2.3650203724  # the free–free beam's first root, halved (βL = 4.7300407449)


def _equation(z, spring):
    """The frequency equation times z (`spring = 4kℓ/EI`): finite as z → 0."""
    ch, sh, c, s = jnp.cosh(z), jnp.sinh(z), jnp.cos(z), jnp.sin(z)
    return (ch - c) * (spring * sh + z * (ch - c)) - (sh + s) * (spring * ch + z * (sh - s))


def lap_beam_frequency(rotational_stiffness, *, half_length, width, height, modulus, density):
    """The first bending frequency (Hz) of two beams joined by a rotational spring (module docstring).

    **Arguments:** `rotational_stiffness` k (N·m/rad, e.g. `bem.solve_layered`'s tilt stiffness
    about the axis across the beam); each half's `half_length` ℓ (m); the rectangular section's
    `width` and `height` (m, bending about the width); `modulus` E (Pa) and `density` ρ (kg/m³).

    **Returns:** the frequency, Hz. Differentiable in every argument (the root by bisection, its
    derivative by the implicit rule); `vmap`s.
    """
    for name, value in (
        ("half_length", half_length),
        ("width", width),
        ("height", height),
        ("modulus", modulus),
        ("density", density),
    ):
        check_positive(name, value, "", name)
    bending = modulus * width * height**3 / 12.0
    spring = 4.0 * rotational_stiffness * half_length / bending
    held = jax.lax.stop_gradient(spring)

    def bisect(_, bracket):
        low, high = bracket
        middle = 0.5 * (low + high)
        # The equation is negative between 0 and the first root for k > 0.
        below = _equation(middle, held) < 0
        return jnp.where(below, middle, low), jnp.where(below, high, middle)

    low, high = jax.lax.fori_loop(0, 80, bisect, (jnp.full_like(held, 1e-9), jnp.full_like(held, _RIGID)))
    root = jax.lax.stop_gradient(0.5 * (low + high))
    # One Newton correction from the held root: its derivative is the implicit one, −F_k/F_z.
    slope = jax.grad(_equation)(root, held)
    z = root - _equation(root, spring) / slope
    return z**2 * jnp.sqrt(bending / (density * width * height)) / (2 * math.pi * half_length**2)
