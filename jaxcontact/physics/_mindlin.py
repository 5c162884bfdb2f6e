"""One spot under a tangential displacement: Cattaneo–Mindlin partial slip and Masing's rules.

A spot of normal load P, friction coefficient μ and full-stick tangential stiffness `k_t = 8G*r`
(`_in_service`), displaced tangentially by u at constant P, carries (Cattaneo 1938, Mindlin 1949;
Johnson 1985, §7.2)

    Q(u) = μP [1 − (1 − u/u*)^{3/2}]  for u < u* = 3μP/(2k_t) = 3μP/(16G*r),   μP beyond,

the backbone: its slope at u = 0 is `k_t`, and at `u*` the slip annulus has reached the centre and
the spot slides. Cycled between ±u₀, each branch is the backbone doubled in both axes from its
turning point (Masing's rule, which the Mindlin–Deresiewicz loop obeys exactly), and the loop
encloses, with `x = u₀/u*` and `m = min(x, 1)`,

    W = μP u* [4x − (16/5)(1 − (1 − m)^{5/2}) + 4x(1 − m)^{3/2}],

`μP u* x³/2` at small amplitude (∝ Q₀³) and `4μP(u₀ − 4u*/5)` in gross slip. Functions of
`x = u/u*`, in units of μP and μP u*.
"""

from __future__ import annotations

import jax.numpy as jnp


def slip_displacement(mu, load, tangential_stiffness):
    """`u* = 3μP / (2k_t)`: the tangential displacement at which a spot of load P and full-stick
    tangential stiffness `k_t` slides."""
    return 1.5 * mu * load / tangential_stiffness


def _stuck_root(x):
    """`(m, r)`: `m = min(x, 1)` and `r = √(1 − m)`, the latter with a finite derivative at every x
    (at and beyond slip, where `r = 0`, its derivative would be infinite and meet a zero one)."""
    sticking = x < 1.0
    m = jnp.where(sticking, x, 1.0)
    r = jnp.where(sticking, jnp.sqrt(jnp.where(sticking, 1.0 - m, 1.0)), 0.0)
    return m, r


def backbone(x):
    """`Q/(μP) = 1 − (1 − x)^{3/2}` for `x = u/u* < 1`, 1 beyond: the first loading of a spot.

    Written `m (1 + r + r²)/(1 + r)` with `r = √(1 − m)`, without the cancellation of `1 − r³` at small x."""
    m, r = _stuck_root(x)
    return m * (1.0 + r + r * r) / (1.0 + r)


def loop_energy(x):
    """`W/(μP u*)`, the energy a spot dissipates per cycle of amplitude `x = u₀/u*` (module docstring).

    Factored as `(4/5)(1 − r)³(r² + 3r + 1) + 4 max(x − 1, 0)` with `r = √(1 − m)` and
    `1 − r = m/(1 + r)`: the loop's x³/2 at small amplitude keeps full relative precision, where the
    expanded form loses it to the cancellation of terms of order x."""
    m, r = _stuck_root(x)
    open_ = m / (1.0 + r)
    return 0.8 * open_**3 * (r * r + 3.0 * r + 1.0) + jnp.where(x < 1.0, 0.0, 4.0 * (x - 1.0))


def masing_branches(u, amplitude, backbone_at):
    """The two branches of the loop between ±`amplitude` at the displacements `u` (|u| ≤ amplitude):
    `(rising, falling)`, `−Q₀ + 2B((u₀ + u)/2)` and `Q₀ − 2B((u₀ − u)/2)`, for any backbone
    `backbone_at(u)` (Masing's rule)."""
    top = backbone_at(amplitude)
    return -top + 2.0 * backbone_at(0.5 * (amplitude + u)), top - 2.0 * backbone_at(0.5 * (amplitude - u))
