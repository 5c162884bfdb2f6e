"""A surface given by its measured roughness spectrum: the isotropic `C2D(q)` as a table over the
band where it was measured, and named choices beyond the table's long end (docs/model.md §8).

Between the table's points `C2D` is a power law (straight in `ln q`, `ln C2D`), the shape a binned
spectrum of self-affine roughness has. A joint is larger than the map that was measured: from the
joint's longest wavelength `√A_a` to the table's first point, `C2D` is continued by the long end's
law, `Rolloff()` (constant: the spectrum rolls off at the longest measured wavelength) or
`PowerLawEnd(D)` (the self-affine `q^-(6-2D)` extrapolated). The table's last point is the short
end: the reliability cutoff or l_min, as whoever measured the spectrum chose.

Greenwood–Williamson needs the spectrum's moments, Persson the cumulative `Q(q) = ∫_{q0}^{q} q'³ C_P dq'`
(`C_P = C2D/(2π)²`) and its inverse, both exact for piecewise power laws, in the scene's units
(lengths in `√A_a`, so that `q0 = 2π`).
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..numerics import InputError
from ..numerics._powerlaw import exponential_integral

LOG_2PI = math.log(2.0 * math.pi)


class AbstractLongEnd(eqx.Module):
    """How `C2D` continues from the table's longest wavelength to the joint's (`√A_a`).

    **Class attribute:** `name` (reports).
    """

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def slope(self, log_C: Float[Array, " bins"], log_q: Float[Array, " bins"]) -> Float[Array, ""]:
        """`d ln C2D / d ln q` below the table's first point."""


class Rolloff(AbstractLongEnd):
    """`C2D` constant below the longest measured wavelength: the spectrum rolls off there."""

    name: ClassVar[str] = "rolloff"

    def slope(self, log_C, log_q):
        return jnp.zeros_like(log_C[0])


class PowerLawEnd(AbstractLongEnd):
    """`C2D ∝ q^-(6-2D)` below the longest measured wavelength: the self-affine law extrapolated.

    **Arguments:** `D`, the fractal dimension whose slope is extended (1 < D < 2).
    """

    name: ClassVar[str] = "power-law"
    D: float = eqx.field(converter=float)

    def __check_init__(self):
        if not 1.0 < self.D < 2.0:
            raise InputError(f"D = {self.D!r} is outside its valid range (1, 2)")

    def slope(self, log_C, log_q):
        return jnp.full_like(log_C[0], -(6.0 - 2.0 * self.D))


class MeasuredSpectrum(eqx.Module):
    """The isotropic roughness spectrum `C2D(q)` as measured (module docstring).

    **Arguments:**

    - `q`: wavevectors, 1/m, increasing, at least 2 (the measured band, long wavelengths first).
    - `C2D`: the spectrum at each q, m⁴, positive (SurfaceTopography's convention,
      `<h²> = (2π)^-2 ∫ C2D d²q`).
    - `long_end`: `Rolloff()` (default) or `PowerLawEnd(D)`, the law from the table's first point
      down to the joint's `q0 = 2π/√A_a`.
    - `variance`: None, or the variance of each point's ln C2D (its measurement's uncertainty, for
      `jaxcontact.topography.spectrum_band`).

    The table's values are arrays: `jax.grad` reaches `log_C` (ln C2D) through `eqx.tree_at`.
    """

    log_q: Float[Array, " bins"]
    log_C: Float[Array, " bins"]
    long_end: AbstractLongEnd = Rolloff()
    variance: Float[Array, " bins"] | None = None

    def __init__(self, q, C2D, long_end: AbstractLongEnd = Rolloff(), variance=None):
        q_values, c_values = np.asarray(q, dtype=float), np.asarray(C2D, dtype=float)
        if q_values.ndim != 1 or q_values.shape != c_values.shape or q_values.size < 2:
            raise InputError(
                f"q and C2D have shapes {q_values.shape} and {c_values.shape}: give two 1-D tables of one length, "
                "at least 2"
            )
        if not (np.all(np.isfinite(q_values)) and np.all(q_values > 0) and np.all(np.diff(q_values) > 0)):
            raise InputError(
                "q must be finite, positive and increasing (1/m): the measured band, long wavelengths first"
            )
        if not (np.all(np.isfinite(c_values)) and np.all(c_values > 0)):
            raise InputError("C2D must be finite and positive (m⁴) at every q")
        if not isinstance(long_end, AbstractLongEnd):
            raise InputError(f"long_end = {long_end!r} must be Rolloff() or PowerLawEnd(D)")
        if variance is not None:
            variance = np.asarray(variance, dtype=float)
            if variance.shape != q_values.shape or not np.all(variance >= 0):
                raise InputError(f"variance has shape {variance.shape}: give one value >= 0 per q (var of ln C2D)")
            variance = jnp.asarray(variance)
        self.log_q, self.log_C = jnp.asarray(np.log(q_values)), jnp.asarray(np.log(c_values))
        self.long_end, self.variance = long_end, variance

    @classmethod
    def from_characterisation(
        cls, characterisation, long_end: AbstractLongEnd = Rolloff(), shortest: float | None = None
    ) -> MeasuredSpectrum:
        """The binned `C2D` of an areal map's characterisation (`jaxcontact.topography.characterise`)
        over its band (from `2π/band[1]` to `2π/band[0]`, the reliable one), with each bin's variance
        of ln C where the characterisation has it; cut at the wavelength `shortest` (m) where that is
        longer than the band's short end (a chosen l_min, a grid's resolution).

        **Raises:** `ValueError` for a profile's characterisation, and for a cut band of fewer than 2 bins."""
        if getattr(characterisation.kind, "name", "") != "areal":
            raise InputError(
                f"the characterisation is of a {characterisation.kind.name} measurement: a measured spectrum needs "
                "an areal map's C2D"
            )
        q, C = (np.asarray(x, dtype=float) for x in characterisation.spectrum)
        short, long = characterisation.band
        short = short if shortest is None else max(short, shortest)
        inside = (q >= 2 * math.pi / long * (1 - 1e-9)) & (q <= 2 * math.pi / short * (1 + 1e-9)) & (C > 0)
        if inside.sum() < 2:
            raise InputError(
                f"the band ({characterisation.band[0]:.3g}, {long:.3g}) m holds fewer than 2 bins longer than "
                f"{short:.3g} m"
            )
        variance = getattr(characterisation, "spectrum_variance", None)
        return cls(q[inside], C[inside], long_end, None if variance is None else np.asarray(variance)[inside])

    @classmethod
    def from_binned(
        cls, spectrum, long_end: AbstractLongEnd = Rolloff(), shortest: float | None = None
    ) -> MeasuredSpectrum:
        """Every bin with modes of an areal map's binned spectrum (`q`, `C`, `modes`, `log_variance`:
        the `spectrum` of `jaxcontact.topography.NoBandError`, what `characterise` measured on a map
        without a power-law band), from the map's longest wavelength to the wavelength `shortest`
        (m; default its shortest), each with its variance of ln C.

        **Raises:** `ValueError` for a profile's spectrum, and for fewer than 2 bins."""
        if getattr(spectrum.kind, "name", "") != "areal":
            raise InputError(
                f"the spectrum is a {spectrum.kind.name} one: a measured spectrum needs an areal map's C2D"
            )
        q, C = np.asarray(spectrum.q, dtype=float), np.asarray(spectrum.C, dtype=float)
        keep = (np.asarray(spectrum.modes) > 0) & (C > 0)
        if shortest is not None:
            keep &= q <= 2 * math.pi / shortest * (1 + 1e-9)
        if keep.sum() < 2:
            longer = "" if shortest is None else f" longer than {shortest:.3g} m"
            raise InputError(f"the spectrum holds fewer than 2 bins with modes{longer}: a table needs at least 2")
        return cls(q[keep], C[keep], long_end, np.asarray(spectrum.log_variance)[keep])

    def _pieces(self, log_length):
        """The piecewise power law in the scene's units: per piece (the long end's from `q0* = 2π`
        to the first point, then every bin) its ends in `t = ln q*`, cut at `q0*`, and `ln C*` as
        `log_C0 + slope t`."""
        log_q = self.log_q + log_length
        log_C = self.log_C - 4.0 * log_length
        start = jnp.full_like(log_q[0], LOG_2PI)
        slope = jnp.concatenate([self.long_end.slope(log_C, log_q)[None], jnp.diff(log_C) / jnp.diff(log_q)])
        anchor_q, anchor_C = jnp.concatenate([log_q[:1], log_q[:-1]]), jnp.concatenate([log_C[:1], log_C[:-1]])
        lower = jnp.clip(jnp.concatenate([start[None], log_q[:-1]]), start, None)
        return lower, jnp.maximum(log_q, lower), anchor_C - slope * anchor_q, slope

    def log_C_at(self, log_q, log_length):
        """`ln C*` at `ln q*` (any shape, ≥ ln 2π) on the piecewise power law, the last bin's law
        continued beyond the table (a caller cuts it there)."""
        lower, upper, log_C0, slope = self._pieces(log_length)
        k = jnp.clip(jnp.searchsorted(upper, log_q), 0, upper.shape[0] - 1)
        return log_C0[k] + slope[k] * log_q

    def profile_moments(self, log_length):
        """McCool's `(m0, m2, m4)` of a line scan (`m0 = M0`, `m2 = M2/2`, `m4 = 3 M4/8`, with
        `M_k = (1/2π) ∫ q^(k+1) C2D dq` over the whole band), in the scene's units, exact for the
        piecewise power law: what Greenwood–Williamson's summit statistics are made of."""
        lower, upper, log_C0, slope = self._pieces(log_length)

        def areal(order):
            return jnp.sum(exponential_integral(log_C0 - LOG_2PI, slope + order + 2.0, lower, upper))

        return areal(0), areal(2) / 2.0, areal(4) * 3.0 / 8.0

    def cumulative(self, log_length):
        """`(ln Q*(q1*), ln Q* ↦ ln q*)`: the cumulative `Q*` over the whole band, from `q0* = 2π` to
        the table's last point, and its inverse, exact for the piecewise power law (each piece's
        `∫ q³ C_P dq` solved for its upper end), in the units of a joint of side `exp(log_length)` m
        (`q* = q √A_a`, `C* = C2D/A_a²`). A table that starts below `q0*` is cut there."""
        lower, upper, log_C0, slope = self._pieces(log_length)
        # q³ C_P dq = exp(log_coeff + rate t) dt in t = ln q, with C_P = C*/(2π)².
        rate = 4.0 + slope
        log_coeff = log_C0 - 2.0 * LOG_2PI
        parts = exponential_integral(log_coeff, rate, lower, upper)
        ends = jnp.cumsum(parts)
        starts, total = ends - parts, ends[-1]

        def log_q_of_log_Q(log_Q):
            Q = jnp.minimum(jnp.exp(log_Q), total)
            k = jnp.clip(jnp.searchsorted(ends, Q), 0, ends.shape[0] - 1)
            # Within piece k: e^(rate t) = e^(rate t_a) + rate (Q − Q_a) e^(−log_coeff), so that
            # t = t_a + ln(1 + rate u)/rate with u = (Q − Q_a) e^(−log_coeff − rate t_a).
            r = rate[k]
            u = (Q - starts[k]) * jnp.exp(-log_coeff[k] - r * lower[k])
            small = jnp.abs(r * u) < 1e-6
            step = jnp.where(small, u * (1.0 - 0.5 * r * u), jnp.log1p(r * u) / jnp.where(small, 1.0, r))
            return lower[k] + step

        return jnp.log(total), log_q_of_log_Q
