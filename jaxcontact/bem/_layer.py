"""The roughness of an interface as a compliant layer: local nominal pressure p ↦ the layer's closure
c(p) (m), increasing in p, between two smooth elastic bodies (`bem.solve_layered`, docs/in-service.md).

`WinklerLayer(stiffness)` is linear, `c = p/k`, open (p = 0) below zero closure. `TabulatedLayer`
carries a model's closure law on a table of pressures (`jaxcontact.interface_law`): a cubic
Hermite interpolant in ln p through the closures with the slopes `dc/dln p = p/k_n(p)`, continued
linearly in ln p beyond both ends, so that it opens without bound as p → 0 (every point then
carries some pressure) and is smooth; its `open_below` is the table's smallest pressure, below which
a point counts as out of contact.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..numerics import InputError


class AbstractLayer(eqx.Module):
    """A compliant layer's law: `closure(p)` (m) at pressures p (Pa, any shape), increasing;
    `opens` whether its closure at p = 0 is finite (the layer lets go: p = 0 where the bodies part);
    `open_below` (Pa), the pressure below which a point counts as out of contact."""

    opens: eqx.AbstractClassVar[bool]

    @abc.abstractmethod
    def closure(self, pressure):
        """The layer's closure (m) at `pressure` (Pa)."""

    @abc.abstractmethod
    def open_below(self):
        """The pressure (Pa) below which a point counts as out of contact."""

    def compliance(self, pressure):
        """`dc/dp` (m/Pa) at `pressure`, elementwise (forward-mode)."""
        return jax.jvp(self.closure, (pressure,), (jnp.ones_like(pressure),))[1]


class WinklerLayer(AbstractLayer):
    """A linear layer: closure `p/stiffness`, `stiffness` in Pa/m (a bed of independent springs)."""

    opens = True
    stiffness: Float[Array, ""]

    def __init__(self, stiffness):
        if isinstance(stiffness, (int, float)) and not stiffness > 0:
            raise InputError(f"stiffness = {stiffness!r} Pa/m must be in (0, inf)")
        self.stiffness = jnp.asarray(stiffness, float)

    def closure(self, pressure):
        return pressure / self.stiffness

    def open_below(self):
        return jnp.zeros((), self.stiffness.dtype)


class TabulatedLayer(AbstractLayer):
    """A closure law tabulated at increasing pressures (module docstring).

    **Arguments:** `pressure` (Pa, increasing, positive), `closure` (m, increasing), `stiffness` (the
    loading tangent per unit area `k_n = dp/dc`, Pa/m, positive). `from_law(law)` takes a
    `jaxcontact.InterfaceLaw` (its points with status 0).
    """

    opens = False
    log_pressure: Float[Array, " points"]
    closure_values: Float[Array, " points"]
    slopes: Float[Array, " points"]

    def __init__(self, pressure, closure, stiffness):
        p, c, k = (jnp.asarray(x, float) for x in (pressure, closure, stiffness))
        if p.ndim != 1 or p.shape[0] < 2 or c.shape != p.shape or k.shape != p.shape:
            raise InputError(
                f"pressure, closure and stiffness have shapes {p.shape}, {c.shape}, {k.shape}: give three "
                "1-D arrays of one length >= 2"
            )
        values = [np.asarray(x) for x in (p, c, k) if not isinstance(x, jax.core.Tracer)]
        if len(values) == 3 and not (
            np.all(values[0] > 0) and np.all(np.diff(values[0]) > 0) and np.all(values[2] > 0)
        ):
            raise InputError("pressure must be positive and increasing (Pa) and stiffness positive (Pa/m)")
        self.log_pressure, self.closure_values, self.slopes = jnp.log(p), c, p / k

    @classmethod
    def from_law(cls, law) -> TabulatedLayer:
        """The points of `law` (a `jaxcontact.InterfaceLaw`) with status 0; all of them under a trace,
        where the statuses are not known (a point that is not ok then makes the layer NaN)."""
        if isinstance(law.status, jax.core.Tracer):
            return cls(law.pressure, law.closure, law.normal_stiffness)
        ok = np.asarray(law.status) == 0
        if ok.sum() < 2:
            raise InputError("the interface law has fewer than 2 points with status 0: no layer to tabulate")
        return cls(law.pressure[ok], law.closure[ok], law.normal_stiffness[ok])

    def closure(self, pressure):
        t = jnp.log(jnp.maximum(pressure, jnp.finfo(self.closure_values.dtype).tiny))
        t0, c, m = self.log_pressure, self.closure_values, self.slopes
        k = jnp.clip(jnp.searchsorted(t0, t, side="right") - 1, 0, t0.shape[0] - 2)
        a, b = t0[k], t0[k + 1]
        h = b - a
        # Not clipped: a clip's derivative at its bound is halved (a tie), which a pressure on a
        # table point would meet; beyond the table this branch is not taken.
        u = (t - a) / h
        # Cubic Hermite between the table's points; linear in ln p (the end's slope) beyond them.
        inside = (
            (2 * u**3 - 3 * u**2 + 1) * c[k]
            + (u**3 - 2 * u**2 + u) * h * m[k]
            + (-2 * u**3 + 3 * u**2) * c[k + 1]
            + (u**3 - u**2) * h * m[k + 1]
        )
        below = c[0] + m[0] * (t - t0[0])
        above = c[-1] + m[-1] * (t - t0[-1])
        return jnp.where(t < t0[0], below, jnp.where(t > t0[-1], above, inside))

    def open_below(self):
        return jnp.exp(self.log_pressure[0])
