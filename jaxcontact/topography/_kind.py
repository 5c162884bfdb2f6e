"""What a measurement is: a line scan (`Profile`) or an areal map (`Areal`), each with its spectrum's
convention for the Weierstrass–Mandelbrot surface (docs/model.md §8) and how its heights are cut into
line scans and independent groups; and `Stitched`, several measurements characterised together.

A profile's PSD is `C1D(q) = K1 q^-(5-2D)` with `K1 = G^(2(D-1)) (2π)^(5-2D) / (4 ln γ)`; the isotropic
map with those line scans has `C2D(q) = C0 q^-(6-2D)`, `C0 = K1 · 2 √π Γ(3-D) / Γ(5/2-D)`.
"""

from __future__ import annotations

import abc
import typing
from typing import ClassVar

import equinox as eqx
import numpy as np
from scipy import special

from ..physics._spectrum import log_areal_prefactor, log_profile_prefactor


class AbstractKind(eqx.Module):
    """How a characterisation's measurements are named in reports.

    **Class attributes:** `name` (reports and JSON: "profile", "areal", "stitched"), `noun` ("profile",
    "map", ...), `psd_label` (the axis label of its spectrum).
    """

    name: eqx.AbstractClassVar[str]
    noun: eqx.AbstractClassVar[str]
    psd_label: eqx.AbstractClassVar[str]


class AbstractMeasurementKind(AbstractKind):
    """One measurement's kind: its spectrum's W-M convention and how its heights are laid out.

    **Class attributes:** `piece` (the longest stretch of one line of it: "segment", "scan"), `groups_noun`
    (its independent groups for the structure function: "segments", "tiles"), `slope_offset` (the W-M
    spectrum's log-log slope is `-(slope_offset - 2D)`).
    """

    piece: eqx.AbstractClassVar[str]
    groups_noun: eqx.AbstractClassVar[str]
    slope_offset: eqx.AbstractClassVar[float]

    @abc.abstractmethod
    def log_prefactor(self, D, log_G, gammaln=special.gammaln):
        """ln of the W-M spectrum's prefactor for (D, ln G): linear in ln G, with slope 2 (D − 1).
        `gammaln` may be JAX's, for a traced D."""

    @abc.abstractmethod
    def heights(self, rows: np.ndarray) -> np.ndarray:
        """The measurement's heights from its line scans as rows (a profile's one row; a map (x, y))."""

    @abc.abstractmethod
    def groups(self, rows: np.ndarray, count: int | None) -> list:
        """Independent groups of the line scans `rows` for the structure function (`count` or a default)."""

    @typing.final
    def spectral_slope(self, D):
        """The log-log slope of the W-M spectrum: `-(6 - 2D)` for a map's `C2D`, `-(5 - 2D)` for a profile's `C1D`."""
        return -(self.slope_offset - 2.0 * D)

    @typing.final
    def log_G_of_prefactor(self, D, log_prefactor):
        """ln G (W-M) from the spectrum's ln prefactor: the inverse of `log_prefactor` at fixed D."""
        return (log_prefactor - self.log_prefactor(D, 0.0)) / (2 * (D - 1))


class Profile(AbstractMeasurementKind):
    """A line scan: `C1D(q) = K1 q^-(5-2D)`; independent groups are segments of it."""

    name: ClassVar[str] = "profile"
    noun: ClassVar[str] = "profile"
    psd_label: ClassVar[str] = "C1D (m³)"
    piece: ClassVar[str] = "segment"
    groups_noun: ClassVar[str] = "segments"
    slope_offset: ClassVar[float] = 5.0

    def log_prefactor(self, D, log_G, gammaln=special.gammaln):
        return log_profile_prefactor(D, log_G)

    def heights(self, rows):
        return rows[0]

    def groups(self, rows, count):
        count = count or 8
        usable = rows.shape[1] - rows.shape[1] % count
        return list(rows[:, :usable].reshape(count, -1)[:, None, :])


class Areal(AbstractMeasurementKind):
    """An areal map, isotropic: `C2D(q) = C0 q^-(6-2D)`; independent groups are blocks of whole line
    scans (its short lags do not reach across a block)."""

    name: ClassVar[str] = "areal"
    noun: ClassVar[str] = "map"
    psd_label: ClassVar[str] = "C2D (m⁴)"
    piece: ClassVar[str] = "scan"
    groups_noun: ClassVar[str] = "tiles"
    slope_offset: ClassVar[float] = 6.0

    def log_prefactor(self, D, log_G, gammaln=special.gammaln):
        return log_areal_prefactor(D, log_G, gammaln)

    def heights(self, rows):
        return rows.T

    def groups(self, rows, count):
        return np.array_split(rows, min(count or 16, rows.shape[0]), axis=0)


class Stitched(AbstractKind):
    """Several measurements of profiles and maps together (`characterise_stitched`): each keeps its own
    spectrum's convention; the whole has none of its own."""

    name: ClassVar[str] = "stitched"
    noun: ClassVar[str] = "set of measurements"
    psd_label: ClassVar[str] = "C1D (m³) and C2D (m⁴)"
