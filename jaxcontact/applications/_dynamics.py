"""A dynamic joint scene: a mass on the rough joint, preloaded and harmonically driven (diffrax).

A mass m rests on the joint under a preload F0 and a harmonic force F1 sin(Ωt), with viscous
damping c. The contact force follows the joint's tangent stiffness, so with state (x, v, F_c)

    dx/dt = v,   m dv/dt = F0 + F1 sin(Ωt) - F_c - c v,   dF_c/dt = K(F_c) v,

starting at rest in equilibrium (x = v = 0, F_c = F0). It is integrated in dimensionless form,
τ = ω0 t with ω0 = sqrt(K(F0)/m), u = x K(F0)/F1, w = v K(F0)/(F1 ω0), f = (F_c - F0)/F1:

    du/dτ = w,   dw/dτ = sin(r τ) - f - 2ζ w,   df/dτ = K(F0 + F1 f)/K(F0) · w,

with r = Ω/ω0 and 2ζ = c/(m ω0). The joint must stay closed: F1 < F0 (no separation).

Which K (`stiffness`, docs/in-service.md): `Unloading()` (the default) is the joint about a preload
reached by loading. A model that unloads as it loads (GW, Persson, measured Hertz summits, the
elastic BEM) follows its loading law K(F_c), exact at any amplitude below the preload; a model
whose spots flow (the seed model, JZZ) vibrates elastically about its state at the preload with
its initial unloading tangent K_u(F0), a linear law, right for amplitudes small against the
preload (its unloading curve beyond the tangent is not modelled). `Loading()` follows the loading
law K(F_c) reversibly whatever the model: the behaviour of jaxcontact 0.4.
The steady-state amplitude is the first Fourier coefficient of x at Ω over the last periods,
a smooth (differentiable) functional of the response.
"""

from __future__ import annotations

import math

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float, Int

from ..core import Outputs, Scene, point_solver, prepare, solve
from ..numerics._validate import InputError, as_array, check_range, concrete
from ..physics import AbstractStiffness, Loading, Unloading
from ..quantities import Scales, Status
from ..quantities._parameters import Parameter


class Drive(eqx.Module):
    """The mass, damping and loading of the dynamic scene (float fields are pytree leaves).

    **Arguments:**

    - `mass`: m, kg, > 0.
    - `damping`: c, N s/m, ≥ 0.
    - `preload`: F0, N, > 0.
    - `amplitude`: F1, N, 0 < F1 < F0 (the joint must not open).
    - `frequency`: drive frequency Ω/(2π), Hz, > 0.
    """

    mass: Parameter = eqx.field(converter=as_array)
    damping: Parameter = eqx.field(converter=as_array)
    preload: Parameter = eqx.field(converter=as_array)
    amplitude: Parameter = eqx.field(converter=as_array)
    frequency: Parameter = eqx.field(converter=as_array)

    def __check_init__(self):
        check_range("mass", self.mass, 0.0, meaning="kg")
        check_range("damping", self.damping, 0.0, low_open=False, meaning="N s/m")
        check_range("preload", self.preload, 0.0, meaning="N")
        check_range("frequency", self.frequency, 0.0, meaning="Hz")
        F0, F1 = concrete(self.preload), concrete(self.amplitude)
        if F0 is not None and F1 is not None and not ((0 < F1) & (F1 < F0)).all():
            raise InputError(
                f"amplitude = {F1} N must satisfy 0 < amplitude < preload = {F0} N "
                "(a larger amplitude would open the joint)"
            )


class Response(eqx.Module):
    """Time history of the dynamic scene: t (s), x (m, from equilibrium), v (m/s), contact force (N);
    `linear_frequency` = sqrt(K(F0)/m)/(2π) (Hz) with the law's K (the dynamic stiffness by
    default); `status` of the preload point (0 = ok)."""

    t: Float[Array, " n"]
    x: Float[Array, " n"]
    v: Float[Array, " n"]
    contact_force: Float[Array, " n"]
    linear_frequency: Float[Array, ""]
    status: Int[Array, ""]


def check_law(stiffness) -> None:
    """`ValueError` unless `stiffness` is a normal law of the joint: `Loading()` or `Unloading()`."""
    if not isinstance(stiffness, (Loading, Unloading)):
        raise InputError(
            f"stiffness = {stiffness!r} must be Unloading() (the joint about its preload) or Loading() "
            "(the reversible loading law): a normal vibration has no tangential law"
        )


def _stiffness_ratio(scene: Scene, preload, stiffness: AbstractStiffness):
    """`F ↦ K(F)/K(F0)` and K(F0) in N/m of the law the contact force follows (module docstring),
    sharing one per-scene setup."""
    scales = Scales.of(scene)
    reversible = isinstance(stiffness, Loading) or scene.model.unloads_as_it_loads()
    one_point = point_solver(scene, Loading() if reversible else stiffness)
    reference = one_point(preload / scales.load)
    K0_star = reference.stiffness_star

    def ratio(F):
        if not reversible:
            return jnp.ones_like(K0_star)
        return one_point(F / scales.load).stiffness_star / K0_star

    return ratio, K0_star * scales.stiffness, reference.status


def _solve(scene, drive: Drive, stiffness, periods: int, samples_per_period: int, rtol, max_steps: int, window: int):
    ratio, K0, status = _stiffness_ratio(scene, drive.preload, stiffness)
    omega0 = jnp.sqrt(K0 / drive.mass)
    r = 2 * jnp.pi * drive.frequency / omega0
    two_zeta = drive.damping / (drive.mass * omega0)
    F0, F1 = drive.preload, drive.amplitude

    def field(tau, y, args):
        u, w, f = y
        return w, jnp.sin(r * tau) - f - two_zeta * w, ratio(F0 + F1 * f) * w

    period = 2 * jnp.pi / r
    tau_end = periods * period
    n = window * samples_per_period + 1
    ts = tau_end - period * window * jnp.linspace(1.0, 0.0, n)
    zero = jnp.zeros_like(omega0)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(field),
        diffrax.Tsit5(),
        t0=zero,
        t1=tau_end,
        dt0=None,
        y0=(zero, zero, zero),
        saveat=diffrax.SaveAt(ts=ts),
        stepsize_controller=diffrax.PIDController(rtol=rtol, atol=1e-3 * rtol),
        max_steps=max_steps,
        throw=False,
    )
    ok = (status == Status.OK) & (sol.result == diffrax.RESULTS.successful)
    status = jnp.where((status == Status.OK) & ~ok, Status.NOT_CONVERGED, status).astype(jnp.int32)
    u, w, f = (jnp.where(ok, y, jnp.nan) for y in sol.ys)
    return Response(
        t=ts / omega0,
        x=u * F1 / K0,
        v=w * F1 * omega0 / K0,
        contact_force=F0 + F1 * f,
        linear_frequency=omega0 / (2 * jnp.pi),
        status=status,
    )


def _prepare(scene, drive):
    scene, _ = prepare(scene, 1.0)
    dtype = jnp.result_type(scene.area)
    return scene, jax.tree.map(lambda x: jnp.asarray(x, dtype), drive)


def _tolerance(dtype, rtol):
    return rtol if rtol is not None else (1e-9 if dtype == jnp.float64 else 1e-5)


@eqx.filter_jit
def _simulate(scene, drive, stiffness, periods, samples_per_period, rtol, max_steps):
    return _solve(scene, drive, stiffness, periods, samples_per_period, rtol, max_steps, window=periods)


def simulate(
    scene: Scene,
    drive: Drive,
    *,
    stiffness: AbstractStiffness = Unloading(),
    periods: int = 40,
    samples_per_period: int = 32,
    rtol: float | None = None,
    max_steps: int = 100_000,
) -> Response:
    """Time history of the driven joint over `periods` drive periods (`samples_per_period` saved each).

    **Arguments:** the joint's `scene`; the `drive`; `stiffness`, the law the contact force follows
    (module docstring): `Unloading()`, the joint about a preload reached by loading, or `Loading()`,
    the reversible loading law; `periods`, `samples_per_period`; the integrator's `rtol` (default
    1e-9 in float64, 1e-5 in float32) and `max_steps`.

    **Returns:** a `Response`. **Raises:** `ValueError` for another `stiffness`.
    """
    check_law(stiffness)
    scene, drive = _prepare(scene, drive)
    tolerance = _tolerance(scene.area.dtype, rtol)
    return _simulate(scene, drive, stiffness, periods, samples_per_period, tolerance, max_steps)


def _fourier_amplitude(response: Response, drive: Drive):
    # Trapezoid over whole periods of a periodic signal: spectrally accurate.
    t, x = response.t, response.x
    phase = 2 * jnp.pi * drive.frequency * t
    span = t[-1] - t[0]
    a = 2 / span * jnp.trapezoid(x * jnp.cos(phase), t)
    b = 2 / span * jnp.trapezoid(x * jnp.sin(phase), t)
    return jnp.sqrt(a * a + b * b)


@eqx.filter_jit
def _steady_amplitude(scene, drive, stiffness, periods, window, samples_per_period, rtol, max_steps):
    response = _solve(scene, drive, stiffness, periods, samples_per_period, rtol, max_steps, window)
    return _fourier_amplitude(response, drive), response.status


def steady_amplitude(
    scene: Scene,
    drive: Drive,
    *,
    stiffness: AbstractStiffness = Unloading(),
    periods: int = 80,
    window: int = 10,
    samples_per_period: int = 32,
    rtol: float | None = None,
    max_steps: int = 100_000,
):
    """Steady-state displacement amplitude (m) at the drive frequency, and the status.

    The first Fourier coefficient of x(t) over the last `window` of `periods` periods (the
    transient has decayed by exp(-2π ζ (periods - window)) by then), with the law `stiffness` (as
    `simulate`'s). Differentiable with respect to every float field of the scene and of the drive.
    """
    check_law(stiffness)
    scene, drive = _prepare(scene, drive)
    tolerance = _tolerance(scene.area.dtype, rtol)
    return _steady_amplitude(scene, drive, stiffness, periods, window, samples_per_period, tolerance, max_steps)


def frequency_response(scene: Scene, drive: Drive, frequencies, **kw):
    """Steady amplitudes (m) and statuses over drive frequencies (Hz), vmapped; `kw` as `steady_amplitude`'s."""
    scene, drive = _prepare(scene, drive)
    frequencies = jnp.asarray(frequencies, scene.area.dtype)
    return jax.vmap(lambda f: steady_amplitude(scene, eqx.tree_at(lambda d: d.frequency, drive, f), **kw))(frequencies)


def resonance_frequency(scene: Scene, mass: float, preloads, *, stiffness: AbstractStiffness = Unloading()):
    """Small-amplitude resonance frequency sqrt(K(F0)/m)/(2π) (Hz) against preload F0 (N), and
    statuses: K the dynamic stiffness about each preload (`jc.dynamic_stiffness`), or with
    `stiffness=Loading()` the loading tangent there."""
    check_range("mass", mass, 0.0, meaning="kg")
    check_law(stiffness)
    solution = solve(scene, preloads, outputs=Outputs(regime_shares=False, stiffness=stiffness))
    return jnp.sqrt(solution.stiffness / mass) / (2 * math.pi), solution.status
