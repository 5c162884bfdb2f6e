"""The roughness of an interface as a compliant layer: local nominal pressure p ↦ the layer's closure
c(p) (m), increasing in p, between two smooth elastic bodies (`bem.solve_layered`, docs/bolted-joint.md).

Every layer has a finite closure at p = 0, below which it lets go (the point carries no pressure),
and a highest pressure at which its law holds (a point pressed beyond it is flagged).
`WinklerLayer(stiffness)` is linear, `c = p/k`. `TabulatedLayer` carries a model's closure law on a
table of pressures (`jaxcontact.interface_law`): a cubic Hermite interpolant in ln p through the
closures with the slopes `dc/dln p = p/k_n(p)`; below the table it continues with its tangent
`1/k_n(p₀)` at the smallest pressure p₀, and lets go at `c(p₀) − p₀/k_n(p₀)`. Persson's law
would open without bound as p → 0 (its pressure falls as `e^(−u/u₀)`); below p₀ it carries so
little that the choice changes nothing but whether a point counts as in contact. Its highest
pressure is the table's last (the model's own range ends somewhere, at a closed interface if not
before). A layer that flowed unloads stiffer than it loaded: `unloading_compliance` is `1/k_n,dyn`
about a pressure reached by loading (a `TabulatedLayer` given the law's dynamic stiffness:
a cubic Hermite interpolant of ln k_n,dyn in ln p), which `solve_layered`'s dynamic stiffnesses use.
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
    """A compliant layer's law: `closure(p)` (m) at pressures p ≥ 0 (Pa, any shape), increasing and
    finite at p = 0 (module docstring)."""

    @abc.abstractmethod
    def closure(self, pressure):
        """The layer's closure (m) at `pressure` (Pa)."""

    @abc.abstractmethod
    def highest(self):
        """The highest pressure (Pa) at which the law holds (a point above it is flagged)."""

    def compliance(self, pressure):
        """`dc/dp` (m/Pa) at `pressure`, elementwise (forward-mode)."""
        return jax.jvp(self.closure, (pressure,), (jnp.ones_like(pressure),))[1]

    @abc.abstractmethod
    def unloads_as_it_loads(self) -> bool:
        """Whether the layer unloads along its loading curve (then `unloading_compliance` is `compliance`)."""

    @abc.abstractmethod
    def unloading_compliance(self, pressure):
        """The initial compliance `1/k_n,dyn` (m/Pa) on unloading from `pressure` reached by loading."""


class WinklerLayer(AbstractLayer):
    """A linear layer: closure `p/stiffness`, `stiffness` in Pa/m (a bed of independent springs)."""

    stiffness: Float[Array, ""]

    def __init__(self, stiffness):
        if isinstance(stiffness, (int, float)) and not stiffness > 0:
            raise InputError(f"stiffness = {stiffness!r} Pa/m must be in (0, inf)")
        self.stiffness = jnp.asarray(stiffness, float)

    def closure(self, pressure):
        return pressure / self.stiffness

    def highest(self):
        return jnp.asarray(jnp.inf, self.stiffness.dtype)

    def unloads_as_it_loads(self):
        return True

    def unloading_compliance(self, pressure):
        return self.compliance(pressure)


class TabulatedLayer(AbstractLayer):
    """A closure law tabulated at increasing pressures (module docstring).

    **Arguments:** `pressure` (Pa, increasing, positive), `closure` (m, increasing), `stiffness` (the
    loading tangent per unit area `k_n = dp/dc`, Pa/m, positive), and optionally `unloading_stiffness`
    (`k_n,dyn`, Pa/m, positive: the initial unloading tangent about each pressure reached by loading;
    between the table's points a cubic Hermite interpolant of its logarithm in ln p, beyond them the
    end's value; None for a layer that unloads as it loads). `from_law(law)` takes a `jaxcontact.InterfaceLaw`
    (its points with status 0, and its `dynamic_stiffness` where the model has one: give pressures
    within the model's range, since under a trace every point is taken).
    """

    log_pressure: Float[Array, " points"]
    closure_values: Float[Array, " points"]
    slopes: Float[Array, " points"]
    log_unloading: Float[Array, " points"] | None

    def __init__(self, pressure, closure, stiffness, unloading_stiffness=None):
        given = (pressure, closure, stiffness) + (() if unloading_stiffness is None else (unloading_stiffness,))
        p, c, k, *u = (jnp.asarray(x, float) for x in given)
        if p.ndim != 1 or p.shape[0] < 2 or any(x.shape != p.shape for x in (c, k, *u)):
            raise InputError(
                f"pressure, closure and stiffness have shapes {p.shape}, {c.shape}, {k.shape}"
                + (f" and unloading_stiffness {u[0].shape}" if u else "")
                + ": give 1-D arrays of one length >= 2"
            )
        values = [np.asarray(x) for x in (p, k, *u) if not isinstance(x, jax.core.Tracer)]
        if len(values) == 2 + len(u) and not (
            np.all(values[0] > 0) and np.all(np.diff(values[0]) > 0) and all(np.all(v > 0) for v in values[1:])
        ):
            raise InputError(
                "pressure must be positive and increasing (Pa), stiffness and unloading_stiffness positive (Pa/m)"
            )
        self.log_pressure, self.closure_values, self.slopes = jnp.log(p), c, p / k
        self.log_unloading = jnp.log(u[0]) if u else None

    @classmethod
    def from_law(cls, law) -> TabulatedLayer:
        """The points of `law` (a `jaxcontact.InterfaceLaw`) with status 0; all of them under a trace,
        where the statuses are not known (a point that is not ok then makes the layer NaN)."""
        if isinstance(law.status, jax.core.Tracer):
            return cls(law.pressure, law.closure, law.normal_stiffness, law.dynamic_stiffness)
        ok = np.asarray(law.status) == 0
        if ok.sum() < 2:
            raise InputError("the interface law has fewer than 2 points with status 0: no layer to tabulate")
        unloading = np.asarray(law.unloading_status)[ok] == 0
        if not unloading.all() and unloading.any():
            raise InputError(
                "the interface law's dynamic_stiffness is not ok at every point where its closure is: give "
                "pressures where both are, or interface_law(..., in_service=False) for a layer without unloading"
            )
        dynamic = law.dynamic_stiffness[ok] if unloading.all() else None
        concrete = not any(isinstance(x, jax.core.Tracer) for x in (law.dynamic_stiffness, law.normal_stiffness))
        if (
            dynamic is not None
            and concrete
            and np.array_equal(np.asarray(dynamic), np.asarray(law.normal_stiffness[ok]))
        ):
            dynamic = None  # a model that unloads as it loads
        return cls(law.pressure[ok], law.closure[ok], law.normal_stiffness[ok], dynamic)

    def closure(self, pressure):
        t0, c, m = self.log_pressure, self.closure_values, self.slopes
        p0 = jnp.exp(t0[0])
        # The logarithm of a pressure below the table, which its branch does not use, would give
        # the derivatives of the iteration's compliance (a second derivative) an infinite factor.
        t = jnp.log(jnp.where(pressure < p0, p0, pressure))
        below = c[0] + m[0] * (pressure / p0 - 1.0)
        above = c[-1] + m[-1] * (t - t0[-1])  # for the iteration's way there: a point left here is flagged
        return jnp.where(pressure < p0, below, jnp.where(t > t0[-1], above, _hermite(t0, c, m, t)))

    def highest(self):
        return jnp.exp(self.log_pressure[-1])

    def unloads_as_it_loads(self):
        return self.log_unloading is None

    def unloading_compliance(self, pressure):
        if self.log_unloading is None:
            return self.compliance(pressure)
        t0, log_k = self.log_pressure, self.log_unloading
        t = jnp.log(jnp.clip(pressure, jnp.exp(t0[0]), jnp.exp(t0[-1])))
        # Slopes by centred differences (one-sided at the ends): a C¹ curve, so that the stiffness
        # has no kinks in the load between the table's points.
        secant = jnp.diff(log_k) / jnp.diff(t0)
        slopes = jnp.concatenate([secant[:1], 0.5 * (secant[1:] + secant[:-1]), secant[-1:]])
        return jnp.exp(-_hermite(t0, log_k, slopes, t))


def _hermite(t0, values, slopes, t):
    """The cubic Hermite interpolant through `(t0, values)` with `slopes`, at `t` (the end intervals'
    cubics continue beyond the table)."""
    k = jnp.clip(jnp.searchsorted(t0, t, side="right") - 1, 0, t0.shape[0] - 2)
    a, b = t0[k], t0[k + 1]
    h = b - a
    # Not clipped: a clip's derivative at its bound is halved (a tie), which a pressure on a
    # table point would meet.
    u = (t - a) / h
    return (
        (2 * u**3 - 3 * u**2 + 1) * values[k]
        + (u**3 - 2 * u**2 + u) * h * slopes[k]
        + (-2 * u**3 + 3 * u**2) * values[k + 1]
        + (u**3 - u**2) * h * slopes[k + 1]
    )
