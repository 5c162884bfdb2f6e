"""What characterising a topography gives: D, G, l_min, their uncertainty, and how they were found."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import stats

from ..quantities import Surface
from ._conventions import convert_G
from ._kind import AbstractKind


@dataclasses.dataclass(frozen=True)
class Characterisation:
    """What `characterise` found. Lengths in m; G in the W-M convention unless named otherwise.

    **Fields:** `D`; `G` (W-M, the model's); `G_structure_function` (the same surface's G in the
    structure-function convention of docs/model.md §8); `l_min` (the band's short end); `band` (short,
    long wavelength of the fit, m); `method`; `stderr` and `ci95` (dicts for D and G, Student-t over the
    groups; G's interval is exp(ln G ± t·se)); `covariance` of (D, ln G) and their `correlation`;
    `groups` (independent groups of line scans or segments whose scatter gave the covariance; 1 where it
    came from the whole spectrum's own scatter) and `estimates` (their (D, ln G)); `dof` (the
    covariance's degrees of freedom, for the Student-t and F quantiles); `spectrum` (x, y: `q` and the
    binned `C2D` of a map or `C1D` of a profile, or `τ` and `S(τ)`); `fit` (x, y of the fitted power law
    over the band); `diagnostics` (why D may not mean much; empty if none); `kind` (`Profile()`,
    `Areal()`, or `Stitched()` for several measurements); `reliability_cutoff` (m, from the tip radius,
    or None); `ends` (why the band's long and short end lie where they do); `rolloff` (σ in m of a
    Gaussian transfer function `exp(-(qσ)²)` corrected in the band, or None); `floor` (a white noise
    level of the spectrum subtracted, or 0); `local_slope` (q and the local D along the spectrum, for
    the plot, or None); `power_law` (the fitted `ln C = intercept + slope ln q` as (slope, intercept,
    their covariance), where the region of `covers` is formed, or None); `spectrum_variance` (the
    variance of each bin's ln C in `spectrum`, ψ'(modes/scatter) of its Gamma-distributed mean, where
    the PSD method gave it, else None).
    """

    D: float
    G: float
    G_structure_function: float
    l_min: float
    band: tuple[float, float]
    method: str
    stderr: dict
    ci95: dict
    covariance: np.ndarray
    correlation: float
    groups: int
    estimates: np.ndarray
    spectrum: tuple[np.ndarray, np.ndarray]
    fit: tuple[np.ndarray, np.ndarray]
    diagnostics: tuple[str, ...]
    kind: AbstractKind
    reliability_cutoff: float | None
    dof: int = 0
    ends: tuple[str, str] = ("", "")
    rolloff: float | None = None
    floor: float = 0.0
    local_slope: tuple[np.ndarray, np.ndarray] | None = None
    power_law: tuple[float, float, np.ndarray] | None = None
    spectrum_variance: np.ndarray | None = None

    @classmethod
    def fitted(cls, method: str, D: float, log_G: float, band, covariance, dof: int, held: bool = False, **rest):
        """A characterisation by `method` of (D, ln G) over `band` (short, long wavelength, m; l_min its
        short end), its intervals from `covariance` of (D, ln G) with `dof` (D's row and column zero
        where it was `held`); `rest` the other fields."""
        G = math.exp(log_G)
        if held:
            covariance = covariance.copy()
            covariance[0, :] = covariance[:, 0] = 0.0
            covariance[0, 0] = 1e-300  # held, not estimated; keeps the matrix invertible for `covers`
        return cls(
            D=D,
            G=G,
            G_structure_function=float(convert_G(G, D)),
            l_min=band[0],
            band=band,
            method=method,
            **intervals(D, G, covariance, dof, held),
            covariance=covariance,
            dof=dof,
            **rest,
        )

    @property
    def surface(self):
        """The `jaxcontact.Surface` (D, G, l_min) for a scene."""
        return Surface(D=self.D, G=self.G, l_min=self.l_min)

    def covers(self, D: float, G: float, level: float = 0.95) -> bool:
        """Whether (D, G) lies inside the joint `level` confidence region (Hotelling's T² with `dof`:
        over the groups, `dof` = groups − 1; for the whole spectrum's fit it tends to χ²₂)."""
        n = self.dof
        if self.power_law is not None and self.covariance[0, 0] > 1e-200:
            # In the fit's own coordinates, where the region is an ellipse: (D, ln G) is a nonlinear
            # map of them (ln G ∝ 1/(D - 1)), which a linearised ellipse misdescribes far from D.
            slope, intercept, covariance = self.power_law
            difference = np.array(
                [self.kind.spectral_slope(D) - slope, self.kind.log_prefactor(D, math.log(G)) - intercept]
            )
        else:
            covariance = self.covariance
            difference = np.array([D - self.D, math.log(G) - math.log(self.G)])
        t2 = difference @ np.linalg.solve(covariance, difference)
        return bool(t2 <= 2 * n / (n - 1) * stats.f.ppf(level, 2, n - 1))

    def scene_fragment(self) -> str:
        """The `[surface]` table of a scene file, with where each value came from."""
        lo, hi = self.ci95["D"]
        glo, ghi = self.ci95["G"]
        return (
            f"[surface]\n# from the {self.method} of a {self.kind.name} topography, fitted over wavelengths "
            f"{self.band[0]:.4g}-{self.band[1]:.4g} m\n"
            f"D = {self.D:.6g}  # 95 % interval [{lo:.6g}, {hi:.6g}]\n"
            f"G = {self.G:.6g}  # m, W-M convention (structure-function convention: "
            f"{self.G_structure_function:.6g} m); 95 % interval [{glo:.4g}, {ghi:.4g}]\n"
            f"l_min = {self.l_min:.6g}  # m, the short end of the fit band: K depends on it "
            "(K ∝ a_min^((1-D)/2))\n"
        )


def intervals(D: float, G: float, covariance: np.ndarray, dof: int, held: bool = False) -> dict:
    """`stderr`, `ci95` and `correlation` of a `Characterisation` from the covariance of (D, ln G):
    Student-t with `dof`, D's interval inside (1, 2), G's `exp(ln G ± t·se)`; no correlation for a
    `held` D."""
    t = stats.t.ppf(0.975, dof)
    se_D, se_logG = math.sqrt(covariance[0, 0]), math.sqrt(covariance[1, 1])
    return dict(
        stderr={"D": se_D, "G": G * se_logG},
        ci95={
            "D": (max(D - t * se_D, 1.0), min(D + t * se_D, 2.0)),
            "G": tuple(G * np.exp(np.array([-1.0, 1.0]) * min(t * se_logG, 700.0))),
        },
        correlation=0.0 if held else float(covariance[0, 1] / math.sqrt(covariance[0, 0] * covariance[1, 1])),
    )
