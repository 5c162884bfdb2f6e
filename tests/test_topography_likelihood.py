"""The band's power law by the likelihood of its bins' means: unbiased where bins hold few modes,
with a white floor fitted beside it (docs/topography.md, "How the fit works")."""

import numpy as np
import pytest
from scipy import optimize
from SurfaceTopography import UniformLineScan
from test_topography_band import make_profile

from jaxcontact import topography as tp
from jaxcontact.topography._binned import SYSTEMATIC, prepare
from jaxcontact.topography._likelihood import likelihood_fit
from jaxcontact.topography._whole import whole_spectrum


@pytest.fixture(scope="module")
def noisy_steep_profiles():
    """Ten profiles at D = 1.2 with white noise of 10 % of the rms: the floor leaves 1.3 decades."""
    return [make_profile(1.2, "noise", 0.10, seed) for seed in range(10)]


def test_noisy_steep_profiles_are_not_biased(noisy_steep_profiles):
    # The mean of ten estimates (standard deviation ~0.03 each) within 2.5 of its standard errors of
    # the truth; the debiased least-squares fit of ln C gave +0.05 here.
    errors = [tp.characterise(profile).D - 1.2 for profile in noisy_steep_profiles]
    assert abs(np.mean(errors)) < 0.025


@pytest.fixture(scope="module")
def prepared_profile(noisy_steep_profiles):
    heights = noisy_steep_profiles[0].heights()
    return prepare(whole_spectrum(heights, 1e-3 / heights.size, True), None)


def test_a_noisy_profile_has_few_mode_bins_beyond_the_long_end(prepared_profile):
    assert prepared_profile.long_end.shape.size > 0


def test_a_noisy_profile_has_bins_beyond_the_floors_margin(prepared_profile):
    assert prepared_profile.short_end.shape.size > 0


def test_scoring_reaches_the_maximum_that_scipy_finds(prepared_profile):
    """Over the whole prepared range (long-end bins, band, bins beyond the floor's margin with the
    floor free): Fisher scoring's slope against scipy's minimisation of the same objective."""
    p = prepared_profile
    last = p.x.size - 1
    start = np.polyfit(p.x, p.y, 1)[::-1]
    slope = likelihood_fit(p, 0, last, False, start)[0][1]
    rows = [(e.x, e.mean, e.shape) for e in (p.long_end, p, p.short_end)]
    x, mean, shape = (np.concatenate(c) for c in zip(*rows))
    weight = 1.0 / (1.0 / shape + SYSTEMATIC**2)

    def objective(theta):
        mu = np.exp(theta[0] + theta[1] * x) + np.exp(theta[2])
        return np.sum(weight * (np.log(mu) + mean / mu))

    theta = optimize.minimize(
        objective,
        [*start, np.log(p.floor)],
        method="Nelder-Mead",
        options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 20000},
    ).x
    theta = optimize.minimize(objective, theta, method="BFGS", options={"gtol": 1e-10}).x
    assert slope == pytest.approx(theta[1], abs=1e-5)


def _profile_with_a_wave(amplitude):
    """A D = 1.5 profile with a sinusoid of `amplitude` times its rms at its third-longest wavelength."""
    heights = tp.random_profile(1.5, 1e-10, 1e-3, 100_000, seed=0).heights()
    wave = np.sin(2 * np.pi * 3 * np.arange(heights.size) / heights.size)
    return UniformLineScan(heights + amplitude * heights.std() * wave, 1e-3, periodic=True)


def test_the_long_ends_few_mode_bins_join_a_band_that_reaches_them():
    assert tp.characterise(_profile_with_a_wave(0.0)).ends[0].startswith("the measurement's longest wavelength")


def test_a_wave_at_the_longest_wavelengths_keeps_them_out_of_the_fit():
    # A form error or waviness there is in no window's tests: their own Pearson statistic refuses it.
    assert tp.characterise(_profile_with_a_wave(3.0)).ends[0].startswith("fewer than 3 independent modes")
