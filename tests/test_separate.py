"""Form, waviness and roughness apart (docs/topography.md): synthetic maps with a known roughness, a
known form and a known wave, against their spectra and SurfaceTopography's own detrending."""

import math

import numpy as np
import pytest
from helpers import refused_type

pytest.importorskip("SurfaceTopography")
import SurfaceTopography as st  # noqa: E402

import jaxcontact.topography as tp  # noqa: E402
from jaxcontact.cli import main  # noqa: E402

SIZE, GRID = 1e-3, 256


@pytest.fixture(scope="module")
def roughness():
    return tp.areal_map(1.4, 1e-11, SIZE, GRID, seed=1).heights()


def _coordinates():
    x = ((np.arange(GRID) + 0.5) / GRID - 0.5) * 2.0  # [-1, 1] over the map
    return np.meshgrid(x, x, indexing="ij")


def _measured(heights):
    return st.Topography(heights, (SIZE, SIZE), periodic=False, unit="m")


def _spectrum(heights, lowest=4):
    """Hann-windowed periodogram, radially averaged in 20 log bins from `lowest` q0 to the Nyquist q:
    an estimate that detrends nothing (the library's own removes a quadric first)."""
    window = np.outer(np.hanning(GRID), np.hanning(GRID))
    power = np.abs(np.fft.rfft2(heights * window)) ** 2 / np.mean(window**2)
    axes = np.meshgrid(np.fft.fftfreq(GRID, SIZE / GRID), np.fft.rfftfreq(GRID, SIZE / GRID), indexing="ij")
    q = 2 * math.pi * np.hypot(*axes)
    edges = np.geomspace(lowest * 2 * math.pi / SIZE, math.pi * GRID / SIZE, 21)
    index = np.digitize(q.ravel(), edges)
    return np.array([power.ravel()[index == k].mean() for k in range(1, 21)])


@pytest.fixture(scope="module")
def on_a_paraboloid(roughness):
    x, y = _coordinates()
    rms = np.std(roughness)
    return _measured(roughness + 50 * rms * (x**2 + 0.7 * y**2 + 0.4 * x))


def test_removing_the_curvature_recovers_the_roughness_spectrum_within_5_percent(roughness, on_a_paraboloid):
    ratio = _spectrum(tp.separate(on_a_paraboloid, tp.Curvature()).roughness.heights()) / _spectrum(roughness)
    assert np.all(np.abs(ratio - 1) < 0.05), ratio


def test_without_form_removal_the_paraboloid_swamps_the_spectrum(roughness, on_a_paraboloid):
    ratio = _spectrum(tp.separate(on_a_paraboloid, tp.Mean()).roughness.heights()) / _spectrum(roughness)
    assert ratio.max() > 2.0, ratio


def test_a_polynomial_of_degree_two_is_surfacetopographys_curvature(on_a_paraboloid, roughness):
    ours = tp.separate(on_a_paraboloid, tp.Polynomial(2)).roughness.heights()
    theirs = tp.separate(on_a_paraboloid, tp.Curvature()).roughness.heights()
    assert np.max(np.abs(ours - theirs)) < 1e-9 * np.std(roughness)


def test_a_polynomial_form_is_removed_exactly(roughness):
    x, y = _coordinates()
    cubic = 30 * np.std(roughness) * (x**3 - 2 * x * y**2 + 0.5 * y)
    plain = tp.separate(_measured(roughness), tp.Polynomial(3)).roughness.heights()
    shaped = tp.separate(_measured(roughness + cubic), tp.Polynomial(3)).roughness.heights()
    assert np.max(np.abs(shaped - plain)) < 1e-9 * np.std(roughness)


@pytest.fixture(scope="module")
def waved(roughness):
    """A wave of 10 times the roughness's rms at the map's longest wavelength, split at L/8; and the
    roughness alone split alike (the filter is linear: the difference is the wave's share)."""
    x, _ = _coordinates()
    wave = 10 * np.std(roughness) * math.sqrt(2) * np.sin(math.pi * x)
    parts, alone = (
        tp.separate(_measured(h), tp.Mean(), waviness_cutoff=SIZE / 8) for h in (roughness + wave, roughness)
    )
    return wave, parts, alone


def test_the_waviness_takes_the_share_of_the_wave_iso_16610_gives_it(waved):
    wave, parts, alone = waved
    share = np.sum((parts.waviness - alone.waviness) * wave) / np.sum(wave * wave)
    # The Gaussian filter's transmission at λ = 8 λc: exp(-π (α/8)²) = 0.9894.
    assert abs(share - math.exp(-math.pi * (tp._separate.ALPHA / 8) ** 2)) < 0.002


def test_the_wave_leaves_the_roughness_nearly_alone(waved):
    wave, parts, alone = waved
    assert np.std(parts.roughness.heights() - alone.roughness.heights()) < 0.03 * np.std(wave)


def test_the_roughness_keeps_its_spectrum_below_the_waviness_cutoff(waved, roughness):
    lowest = SIZE / tp._separate.longest_roughness_wavelength(SIZE / 8)
    ratio = _spectrum(waved[1].roughness.heights(), lowest) / _spectrum(roughness, lowest)
    assert np.all(np.abs(ratio - 1) < 0.05), ratio


def test_the_three_parts_add_up_to_the_map(waved, roughness):
    wave, parts, _ = waved
    total = parts.form_heights + parts.waviness + parts.roughness.heights()
    np.testing.assert_allclose(total, roughness + wave - np.mean(roughness + wave), rtol=0, atol=1e-12 * SIZE)


def test_a_split_roughness_is_fitted_only_where_it_keeps_its_amplitude(waved):
    c = tp.characterise(waved[1].roughness)
    assert c.band[1] <= tp._separate.longest_roughness_wavelength(SIZE / 8)
    assert c.ends[0].startswith("the waviness cutoff")


@pytest.mark.parametrize(
    "call, message",
    [
        (
            lambda t: tp.separate(t, waviness_cutoff=SIZE * 2),
            r"waviness_cutoff = 0.002 m must lie in \[3.13e-05, 0.001\] m",
        ),
        (lambda t: tp.separate(t, waviness_cutoff=True), r"waviness_cutoff = True m must lie in"),
        (lambda t: tp.separate(t, tp.Polynomial(0)), r"degree = 0 must be an integer in \[1, 10\]"),
    ],
)
def test_bad_choices_name_the_parameter_and_its_range(on_a_paraboloid, call, message):
    with pytest.raises(ValueError, match=message):
        call(on_a_paraboloid)


def test_a_form_given_by_name_is_refused_with_its_object(on_a_paraboloid):
    with refused_type("form", r"form = 'tilt': give the object, jaxcontact.topography.Tilt\(\)"):
        tp.separate(on_a_paraboloid, "tilt")


def test_the_surface_command_says_what_it_removed(tmp_path, capsys, on_a_paraboloid):
    data = tmp_path / "map.npy"
    np.save(data, on_a_paraboloid.heights())
    argv = ["surface", str(data), "--size", str(SIZE), str(SIZE), "--out", str(tmp_path), "--waviness-cutoff", "2.5e-4"]
    assert main(argv) == 0
    assert "form removed: curvature (rms" in capsys.readouterr().out


def test_the_command_lines_forms_are_the_librarys():
    from jaxcontact.cli._surface_commands import FORMS

    assert set(FORMS) == set(tp._separate.FORMS)


def test_a_mirror_symmetric_maps_mirrored_bem_is_its_periodic_one(roughness):
    """A map that is its own mirror image: mirrored, it is the map tiled 2 × 2, so a periodic BEM at
    four times the load gives four times its stiffness (to the solver's tolerance)."""
    import jax.numpy as jnp

    from jaxcontact.bem import solve

    quarter = roughness[:32, :32]
    symmetric = np.block([[quarter, quarter[:, ::-1]], [quarter[::-1, :], quarter[::-1, ::-1]]])
    size = SIZE / 4  # 64 points at the map's spacing
    mirror = tp.mirrored(st.Topography(symmetric, (size, size), periodic=False, unit="m"))
    load = 1e-4 * 2e11 * size**2
    alone = solve(jnp.asarray(symmetric), size, 2e11, jnp.array([load]), secant=0.02).secant_stiffness
    tiled = solve(jnp.asarray(mirror.heights()), 2 * size, 2e11, jnp.array([4 * load]), secant=0.02)
    np.testing.assert_allclose(tiled.secant_stiffness / 4, alone, rtol=1e-7)
