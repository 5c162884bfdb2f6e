"""The band found from the data: maps and profiles made the way instruments make them (a sharp
cutoff inside the grid, a Gaussian transfer function, a white noise floor), with known D and G."""

import dataclasses
import functools
import json

import numpy as np
import pytest
from helpers import ROOT
from SurfaceTopography import Topography, UniformLineScan

from jaxcontact import topography as tp
from jaxcontact.cli import main
from jaxcontact.topography._binned import FACTORIALS, ORDERS, rolloff_offset
from jaxcontact.topography._whole import whole_spectrum

G_TRUE = 1e-10
SIZE = 1e-3
GRID = 1024
TOPOGRAPHIES = ROOT.parent / "shared" / "data" / "topographies"


def _artefact(heights, kind: str, amount: float, seed: int):
    """`heights` (a periodic grid, any dimension) blurred by a Gaussian of `amount` spacings, or with
    white noise of `amount` times their rms."""
    if kind == "blur":
        axes = [np.fft.fftfreq(n) for n in heights.shape[:-1]] + [np.fft.rfftfreq(heights.shape[-1])]
        q2 = sum(a**2 for a in np.meshgrid(*(2 * np.pi * a for a in axes), indexing="ij"))
        return np.fft.irfftn(
            np.fft.rfftn(heights) * np.exp(-q2 * amount**2 / 2), heights.shape, axes=range(heights.ndim)
        )
    return heights + amount * heights.std() * np.random.default_rng(seed).standard_normal(heights.shape)


@functools.lru_cache(maxsize=24)
def _synthesised(D, grid, seed):
    """A map's heights before its artefact, kept: the coverage tests put three artefacts on the same
    20 maps, and the synthesis costs three times the characterisation."""
    heights = tp.areal_map(D, G_TRUE, SIZE, grid, seed=seed).heights()
    heights.flags.writeable = False
    return heights


def make_map(D, kind, amount, seed, grid=GRID):
    if kind == "cut":
        return tp.areal_map(D, G_TRUE, SIZE, grid, l_min=amount * SIZE / grid, seed=seed)
    return Topography(_artefact(_synthesised(D, grid, seed), kind, amount, seed), (SIZE, SIZE), periodic=True)


def make_profile(D, kind, amount, seed, points=100_000):
    if kind == "cut":
        return tp.random_profile(D, G_TRUE, SIZE, points, l_min=amount * SIZE / points, seed=seed)
    heights = tp.random_profile(D, G_TRUE, SIZE, points, seed=seed).heights()
    return UniformLineScan(_artefact(heights, kind, amount, seed), SIZE, periodic=True)


# (kind, amount): D within ±0.03 at seed 0. Of 60 seeds, three maps cut off at 16 spacings miss it, by
# up to 0.031, inside their own intervals (docs/topography.md, "How well the band is found").
MAP_CASES = [
    ("cut", 6),
    ("cut", 10),
    ("cut", 16),
    ("blur", 1.0),
    ("blur", 2.5),
    ("blur", 4.0),
    ("noise", 0.01),
    ("noise", 0.05),
    ("noise", 0.10),
]


@pytest.mark.parametrize("kind, amount", MAP_CASES)
@pytest.mark.parametrize("D", [1.2, 1.5, 1.8])
def test_D_of_a_map_with_an_instrument_artefact(kind, amount, D):
    # One seed per case here; the coverage tests below add 20 seeds per kind at D = 1.5.
    assert abs(tp.characterise(make_map(D, kind, amount, 0)).D - D) < 0.03


@pytest.mark.parametrize("kind, amount", [("cut", 10), ("blur", 2.5), ("noise", 0.05)])
def test_G_with_D_held_at_the_truth(kind, amount):
    ratio = tp.characterise(make_map(1.5, kind, amount, 0), D=1.5).G / G_TRUE
    assert 1 / 1.5 < ratio < 1.5


def test_the_roll_off_of_a_gaussian_transfer_function_is_found():
    c = tp.characterise(make_map(1.5, "blur", 2.5, 0))
    assert c.rolloff == pytest.approx(2.5 * SIZE / GRID, rel=0.1)


@pytest.mark.parametrize("amount, seed", [(2.5, 106), (4.0, 113)])
def test_a_straight_line_tilted_by_a_roll_off_gives_way_to_the_corrected_fit(amount, seed):
    """Maps where a straight window short of the roll-off fits within its scatter (D = 1.34 and 1.26
    for 1.5, their intervals excluding it) while the corrected window finds the roll-off."""
    assert tp.characterise(make_map(1.5, "blur", amount, seed)).rolloff is not None


@pytest.mark.parametrize("amount, seed", [(2.5, 106), (4.0, 113)])
def test_D_of_a_map_whose_straight_window_is_tilted_by_a_roll_off(amount, seed):
    assert abs(tp.characterise(make_map(1.5, "blur", amount, seed)).D - 1.5) < 0.03


@pytest.mark.parametrize("seed", [5, 17])
def test_D_of_a_map_blurred_by_four_spacings_whose_band_was_short(seed):
    """Seeds whose D was 0.056 and 0.043 low while a roll-off was corrected by at most e⁴."""
    assert abs(tp.characterise(make_map(1.5, "blur", 4.0, seed)).D - 1.5) < 0.03


def _unit_modes_rolled_off(sigma, grid=256):
    """A map whose every Fourier mode has periodogram exp(-(qσ)²) exactly (real coefficients, so that
    the half-spectrum is Hermitian): its binned spectrum is each bin's mean of the roll-off over its modes."""
    q = [2 * np.pi * np.fft.fftfreq(grid, SIZE / grid), 2 * np.pi * np.fft.rfftfreq(grid, SIZE / grid)]
    q2 = q[0][:, None] ** 2 + q[1][None, :] ** 2
    # C = Δx² |Σ h e^(-iq·r)|² / N² (`whole_spectrum`), and irfft2 divides by N².
    return np.fft.irfft2(np.exp(-q2 * sigma**2 / 2) * grid**2 / SIZE, (grid, grid))


@pytest.fixture(scope="module")
def rolled_off_bins():
    """σ (m), the binned spectrum of `_unit_modes_rolled_off` at σ = 4 spacings of 256, and its bins
    where κ⟨q²⟩ runs to 12 (`ROLLOFF_CAP`)."""
    sigma = 4.0 * SIZE / 256
    spectrum = whole_spectrum(_unit_modes_rolled_off(sigma), SIZE / 256, periodic=True)
    return sigma, spectrum, sigma**2 * spectrum.q_squared <= 12


def test_a_bins_mean_of_a_roll_off_is_its_cumulant_series(rolled_off_bins):
    """ln of each bin's mean of exp(-κq²) over its modes (computed from the modes themselves) against
    -κ⟨q²⟩ plus the series that `_band` corrects with."""
    sigma, spectrum, inside = rolled_off_bins
    z = spectrum.q_squared_cumulants * (-1.0) ** ORDERS / FACTORIALS
    predicted = -(sigma**2) * spectrum.q_squared + rolloff_offset(sigma**2, z)
    assert np.max(np.abs(np.log(spectrum.C) - predicted)[inside]) < 0.003


def test_without_the_cumulant_series_the_mean_over_a_bin_departs(rolled_off_bins):
    """The same bins against -κ⟨q²⟩ alone: what the series corrects is more than 0.1 in ln C."""
    sigma, spectrum, inside = rolled_off_bins
    assert np.max(np.abs(np.log(spectrum.C) + sigma**2 * spectrum.q_squared)[inside]) > 0.1


def _noise_free_map(D, sigma, grid=GRID):
    """A periodic map whose every Fourier mode lies exactly on `C2D ∝ q^-(6-2D) exp(-(qσ)²)`, σ in grid
    spacings (unit-modulus phases of a white field's transform: Hermitian as a real map's must be)."""
    q = [2 * np.pi * np.fft.fftfreq(grid, SIZE / grid), 2 * np.pi * np.fft.rfftfreq(grid, SIZE / grid)]
    q2 = q[0][:, None] ** 2 + q[1][None, :] ** 2
    q2[0, 0] = 1.0
    amplitude = q2 ** (-(6 - 2 * D) / 4) * np.exp(-q2 * (sigma * SIZE / grid) ** 2 / 2)
    amplitude[0, 0] = 0.0
    transform = np.fft.rfft2(np.random.default_rng(0).standard_normal((grid, grid)))
    return Topography(
        np.fft.irfft2(amplitude * transform / np.abs(transform), (grid, grid)), (SIZE, SIZE), periodic=True
    )


def test_a_noise_free_spectrum_under_a_strong_roll_off_gives_its_D():
    """Without sampling scatter, what is left is the correction's own error: 0.0005 at σ = 4 spacings
    (with κ⟨q²⟩ alone, −0.011)."""
    assert abs(tp.characterise(_noise_free_map(1.5, 4.0)).D - 1.5) < 0.002


def test_a_bin_that_a_sharp_cutoff_halves_is_not_in_the_band():
    """Seed 12: the band ended in the bin that straddles the cutoff, and D was 0.046 low."""
    assert abs(tp.characterise(make_map(1.5, "cut", 10, 12)).D - 1.5) < 0.03


def test_the_band_stops_short_of_a_sharp_cutoff():
    c = tp.characterise(make_map(1.5, "cut", 10, 0))
    assert c.band[0] >= 10 * SIZE / GRID


@pytest.mark.parametrize("kind, amount", [("cut", 10), ("blur", 2.5), ("blur", 4.0), ("noise", 0.05)])
def test_the_joint_95_percent_region_covers_the_truth(kind, amount):
    """20 seeds at D = 1.5."""
    covered = sum(tp.characterise(make_map(1.5, kind, amount, 100 + s)).covers(1.5, G_TRUE) for s in range(20))
    assert covered >= 17


@pytest.mark.parametrize("kind, amount", [("cut", 10), ("blur", 2.5), ("noise", 0.05)])
@pytest.mark.parametrize("D", [1.5, 1.8])
def test_D_of_a_profile_with_an_instrument_artefact(kind, amount, D):
    assert abs(tp.characterise(make_profile(D, kind, amount, 0)).D - D) < 0.05


def test_a_2048_map_is_characterised_like_a_1024_one():
    assert abs(tp.characterise(make_map(1.5, "blur", 4.0, 0, grid=2048)).D - 1.5) < 0.03


@pytest.fixture(scope="module")
def periodic_map():
    """A periodic 256² map of D = 1.5."""
    return tp.areal_map(1.5, G_TRUE, SIZE, 256, seed=3)


@pytest.fixture(scope="module")
def oblong_map(periodic_map):
    """`periodic_map` with every other column dropped: the same surface, pixels twice as long along y."""
    return Topography(periodic_map.heights()[:, ::2], (SIZE, SIZE), periodic=True)


def test_the_areal_spectrum_is_surfacetopographys(periodic_map):
    """C2D in SurfaceTopography's convention: its radially averaged PSD of the same periodic map."""
    surface = periodic_map
    q_st, C_st = surface.power_spectrum_from_area(nb_points_per_decade=10)
    c = tp.characterise(surface, band=(8 * SIZE / 256, SIZE / 4))
    ours = np.interp(np.log(q_st[5:-5]), np.log(c.spectrum[0]), np.log(c.spectrum[1]))
    assert np.median(np.abs(ours - np.log(C_st[5:-5]))) < 0.1


def test_a_map_of_oblong_pixels_has_the_spectrum_of_its_square_pixelled_surface(periodic_map, oblong_map):
    """The same C2D below the coarser axis's Nyquist wavevector as SurfaceTopography's PSD of the whole map."""
    q_st, C_st = periodic_map.power_spectrum_from_area(nb_points_per_decade=10)
    c = tp.characterise(oblong_map, band=(8 * SIZE / 128, SIZE / 4))
    below = (q_st > 2 * np.pi / (SIZE / 4)) & (q_st < 2 * np.pi / (8 * SIZE / 128))
    ours = np.interp(np.log(q_st[below]), np.log(c.spectrum[0]), np.log(c.spectrum[1]))
    assert np.median(np.abs(ours - np.log(C_st[below]))) < 0.1


def test_a_band_shorter_than_two_of_a_maps_coarser_spacings_is_refused_with_the_range(oblong_map):
    shortest = 2 * SIZE / 128  # two spacings along y; along x two are half that
    with pytest.raises(ValueError, match=rf"wavelengths must lie in \[{shortest:.3g}, "):
        tp.characterise(oblong_map, band=(1.5 * SIZE / 128, SIZE / 4))


def test_white_noise_has_no_band_and_says_so():
    noise = Topography(np.random.default_rng(0).standard_normal((256, 256)) * 1e-7, (SIZE, SIZE), periodic=True)
    with pytest.raises(tp.NoBandError, match="no stretch of the spectrum has the slope of a self-affine surface"):
        tp.characterise(noise)


def test_a_refusal_writes_psd_png_and_exits_2(tmp_path, capsys):
    noise = np.random.default_rng(0).standard_normal((256, 256)) * 1e-7
    path = tmp_path / "noise.npy"
    np.save(path, noise)
    code = main(["surface", str(path), "--size", "1e-3", "1e-3", "--out", str(tmp_path / "o")])
    assert (code, (tmp_path / "o" / "psd.png").is_file()) == (2, True)


@pytest.mark.skipif(not TOPOGRAPHIES.is_dir(), reason="the real instrument files live in ../shared/data")
def test_a_refusal_suggests_a_band_on_the_command_line(tmp_path, capsys):
    main(["surface", str(TOPOGRAPHIES / "hfm-1.hfm"), "--out", str(tmp_path)])
    assert "--band " in capsys.readouterr().err


@pytest.mark.skipif(not TOPOGRAPHIES.is_dir(), reason="the real instrument files live in ../shared/data")
def test_the_suggested_band_typed_back_gives_a_result(tmp_path, capsys):
    main(["surface", str(TOPOGRAPHIES / "hfm-1.hfm"), "--out", str(tmp_path)])
    short, long = capsys.readouterr().err.split("--band ")[1].split()[:2]
    assert main(["surface", str(TOPOGRAPHIES / "hfm-1.hfm"), "--band", short, long, "--out", str(tmp_path)]) == 0


def test_disagreeing_methods_are_named_in_a_diagnostic():
    c = tp.characterise(make_map(1.5, "cut", 10, 0))
    other = dataclasses.replace(c, D=c.D + 0.3, stderr={"D": 0.01, "G": c.G})
    assert any("the two methods disagree" in d and f"{other.D:.3f}" in d for d in tp.compared(c, other).diagnostics)


def test_disagreeing_methods_widen_the_interval():
    c = tp.characterise(make_map(1.5, "cut", 10, 0))
    other = dataclasses.replace(c, D=c.D + 0.3, stderr={"D": 0.01, "G": c.G})
    assert tp.compared(c, other).stderr["D"] > 0.15


def test_agreeing_methods_leave_the_interval_alone():
    c = tp.characterise(make_map(1.5, "cut", 10, 0))
    assert tp.compared(c, c).stderr["D"] == c.stderr["D"]


def test_heights_in_micrometres_read_as_metres_are_flagged():
    heights = tp.areal_map(1.5, G_TRUE, SIZE, 256, seed=0).heights() * 1e6
    c = tp.characterise(Topography(heights, (SIZE, SIZE), periodic=True))
    assert any("--unit" in d for d in c.diagnostics)


@functools.lru_cache(maxsize=4)
def two_resolutions(D, seed):
    """One 4096² surface measured twice: all of it at an eighth of the resolution (8 × 8 pixels averaged,
    as a camera's pixel does), and an eighth of its side at full resolution (not periodic)."""
    heights = tp.areal_map(D, G_TRUE, SIZE, 4096, seed=seed).heights()
    coarse = Topography(heights.reshape(512, 8, 512, 8).mean(axis=(1, 3)), (SIZE, SIZE), periodic=True)
    fine = Topography(heights[:512, :512], (SIZE / 8, SIZE / 8), periodic=False)
    return coarse, fine


@pytest.mark.parametrize("D", [1.2, 1.5, 1.8])
def test_two_resolutions_stitched_give_D(D):
    assert abs(tp.characterise_stitched(two_resolutions(D, 0)).D - D) < 0.03


def test_the_stitched_band_is_wider_than_either_measurement():
    coarse, fine = two_resolutions(1.5, 0)
    bands = [tp.characterise(t).band for t in (coarse, fine)]
    stitched = tp.characterise_stitched([coarse, fine]).band
    # The stitched band is the bins the joint fit uses (each measurement's window); each one alone also
    # reaches its longest wavelength with bins of few modes: 867 against 110 and 242 here.
    assert stitched[1] / stitched[0] > max(long / short for short, long in bands)


def test_stitching_needs_two_measurements():
    with pytest.raises(ValueError, match="at least 2 measurements"):
        tp.characterise_stitched([tp.areal_map(1.5, G_TRUE, SIZE, 256)])


@pytest.mark.skipif(not TOPOGRAPHIES.is_dir(), reason="the real instrument files live in ../shared/data")
def test_measurements_of_two_surfaces_are_refused_as_not_joining():
    two = [tp.read(TOPOGRAPHIES / name) for name in ("dektak-1.csv", "opdx-3.opdx")]
    with pytest.raises(ValueError, match="do not join into one power law with 1 < D < 2"):
        tp.characterise_stitched(two)


def test_surface_stitches_several_files(tmp_path, capsys):
    paths = []
    for name, topography in zip(("coarse.nc", "fine.nc"), two_resolutions(1.5, 0)):
        Topography(topography.heights(), topography.physical_sizes, unit="m", periodic=False).to_netcdf(tmp_path / name)
        paths.append(str(tmp_path / name))
    main(["surface", *paths, "--out", str(tmp_path / "o"), "--format", "json"])
    assert abs(json.loads(capsys.readouterr().out)["psd"]["D"] - 1.5) < 0.03


def test_a_measurement_stitched_with_itself_is_refused():
    coarse, _ = two_resolutions(1.5, 0)
    with pytest.raises(ValueError, match="topographies 1 and 2 are the same measurement"):
        tp.characterise_stitched([coarse, coarse])


@functools.cache
def _mismatched():
    """The two resolutions, the fine one's heights twice too large (a calibration mistake)."""
    coarse, fine = two_resolutions(1.5, 0)
    return coarse, Topography(fine.heights() * 2.0, fine.physical_sizes, periodic=False)


def test_measurements_that_do_not_join_are_refused():
    with pytest.raises(ValueError, match=r"do not join into one power law \(χ²/ν = .*accept_mismatch=True"):
        tp.characterise_stitched(_mismatched())


def test_measurements_that_do_not_join_are_fitted_where_the_user_insists():
    c = tp.characterise_stitched(_mismatched(), accept_mismatch=True)
    assert any("do not join into one power law" in d for d in c.diagnostics)
