"""`jaxcontact compare`: the table, files and errors of the command (small grids)."""

import io
import json
from contextlib import redirect_stdout

import numpy as np
import pytest

from jaxcontact.cli import main
from jaxcontact.topography import _synthesis as synthesis

pytest.importorskip("ContactMechanics")


@pytest.fixture(scope="module")
def default_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("compare")
    argv = ["compare", "--grid", "256", "--realisations", "1", "--out", str(out), "--cache-dir", str(out / "cache")]
    return out, [*argv, "--reference", "contactmechanics"]


def test_compare_writes_rows_for_every_model(default_run, capsys):
    out, argv = default_run
    assert main([*argv, "--format", "json", "--no-progress"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    assert len(rows) == 4
    row = rows[1]
    np.testing.assert_allclose(row["ratio_persson"], row["K_persson_N_per_m"] / row["K_bem_mean_N_per_m"], rtol=1e-12)
    assert (out / "comparison.png").stat().st_size > 10_000


def test_compare_prints_the_grid_convergence(default_run, capsys):
    _, argv = default_run
    assert main([*argv, "--no-progress"]) == 0  # read back from the cache
    assert "grid convergence: K at 128² differs from 256² by at most" in capsys.readouterr().out


def test_the_jax_reference_gives_contactmechanicss_table(default_run, capsys):
    """`--reference jax` (the default) against ContactMechanics on the same surfaces and loads."""
    _, argv = default_run
    assert main([*argv, "--format", "json", "--no-progress"]) == 0
    reference = json.loads(capsys.readouterr().out)["rows"]
    assert main([*argv[:-2], "--format", "json", "--no-progress"]) == 0
    mine = json.loads(capsys.readouterr().out)["rows"]
    np.testing.assert_allclose(
        [r["K_bem_mean_N_per_m"] for r in mine], [r["K_bem_mean_N_per_m"] for r in reference], rtol=1e-5
    )


def test_an_edited_cache_entry_is_recomputed_and_reported_once(default_run, capsys):
    """Issue 35.1: a number edited in a cache entry never reaches the table."""
    out, argv = default_run
    assert main([*argv, "--format", "json", "--no-progress"]) == 0
    before = json.loads(capsys.readouterr().out)["rows"]
    entry = sorted((out / "cache").glob("*.json"))[0]
    edited = json.loads(entry.read_text())
    edited["row"]["stiffness"] *= 3.0
    entry.write_text(json.dumps(edited))
    assert main([*argv, "--format", "json", "--no-progress"]) == 0
    captured = capsys.readouterr()
    assert captured.err.splitlines() == [
        f"jaxcontact compare: warning: cache entry {entry} was invalid (its checksum does not match its content); "
        "recomputed"
    ]
    after = json.loads(captured.out)["rows"]
    assert [r["K_bem_mean_N_per_m"] for r in after] == [r["K_bem_mean_N_per_m"] for r in before]


def test_a_grid_too_coarse_is_one_line(capsys, tmp_path):
    assert main(["compare", "--grid", "128", "--out", str(tmp_path), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [err[0]] and "--grid 128 is too coarse for l_min" in err[0]
    assert "(--grid 256 or more, or l_min >=" in err[0]


def test_a_hardness_that_is_not_positive_is_one_line(capsys, tmp_path):
    assert main(["compare", "--plasticity", "1e9", "0", "--out", str(tmp_path), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["jaxcontact compare: error: --plasticity H = 0.0 must be a hardness in Pa, > 0"]


@pytest.fixture(scope="module")
def measured_map(tmp_path_factory):
    path = tmp_path_factory.mktemp("map") / "map.txt"
    np.savetxt(path, synthesis.areal_map(1.5, 1e-12, 1e-4, 512, seed=3).heights())
    return path


JOINT_ARGV = ["--size", "1e-4", "1e-4", "--grid", "64", "--realisations", "2", "--no-fit", "--no-progress"]


def _compared(measured_map, options, out) -> dict:
    """`compare --topography` on the map with `options`, its JSON output."""
    argv = ["compare", "--topography", str(measured_map), *options, "--out", str(out), "--format", "json"]
    with redirect_stdout(io.StringIO()) as printed:
        assert main(argv) == 0
    return json.loads(printed.getvalue())


@pytest.fixture(scope="module")
def joint(measured_map, tmp_path_factory):
    """The map (not periodic) without --substrate: the BEM on realisations of its measured spectrum."""
    return _compared(measured_map, JOINT_ARGV, tmp_path_factory.mktemp("joint"))


def test_without_a_substrate_the_bems_contact_is_at_the_fractions_asked_for(joint):
    # The loads are interpolated on the first realisation; the column is the mean of both.
    fractions = np.array([row["contact_fraction_bem"] for row in joint["rows"]])
    np.testing.assert_allclose(fractions, [0.005, 0.015, 0.05, 0.15], rtol=0.25)


def test_without_a_substrate_persson_on_the_measured_spectrum_is_within_30_percent_of_the_bem_from_5_percent(joint):
    # A self-affine map: the BEM on realisations of its spectrum is the BEM of the surface it samples.
    ratios = np.array([row["ratio_persson_spectrum"] for row in joint["rows"]])[2:]
    assert np.all((ratios > 0.7) & (ratios < 1.3)), ratios


def test_without_a_substrate_persson_is_below_the_bem_at_half_a_percent_contact(joint):
    # Persson's theory is softer than the BEM at low contact: 0.48 at 0.5 % on 64², 0.63 on 128²
    # (docs/validation.md).
    assert joint["rows"][0]["ratio_persson_spectrum"] < 0.7


def test_without_a_substrate_the_mirrored_map_stands_beside_the_realisations(joint):
    # The map is one sample of the surface the realisations are drawn from: the same K within 30 %.
    ratios = np.array([row["ratio_mirrored_map"] for row in joint["rows"]])
    assert np.all((ratios > 0.7) & (ratios < 1.3)), ratios


def test_without_a_substrate_a_rough_map_gets_no_note_on_its_form(joint):
    # Its mirrored map grows as F^0.73 on 64², the realisations of its spectrum as F^0.79.
    assert joint["notes"] == []


@pytest.fixture(scope="module")
def domed_map(measured_map, tmp_path_factory):
    """The same roughness on a paraboloid 20 times its rms high."""
    z = np.loadtxt(measured_map)
    x = np.linspace(-1.0, 1.0, z.shape[0])
    path = tmp_path_factory.mktemp("domed") / "domed.txt"
    np.savetxt(path, z + 20 * np.std(z) * (x[:, None] ** 2 + x[None, :] ** 2))
    return path


def test_without_a_substrate_a_map_whose_form_carries_the_load_gets_a_note(domed_map, tmp_path):
    # The form left in: its mirrored map grows as F^0.61, the realisations of its spectrum (the
    # paraboloid outside its band) as F^0.79.
    notes = _compared(domed_map, [*JOINT_ARGV, "--form", "mean"], tmp_path)["notes"]
    assert notes[0].startswith("note: K_BEM ∝ F^0.6")


def test_without_a_substrate_every_power_law_model_has_its_column(joint):
    assert {"ratio_persson", "ratio_xia2024_paper", "ratio_gw_spectrum"} <= set(joint["rows"][0])


MAP_ARGV = ["--size", "1e-4", "1e-4", "--substrate", "periodic", "--no-fit", "--grid", "128", "--no-progress"]


def test_compare_on_a_measured_map(measured_map, capsys, tmp_path):
    argv = ["compare", "--topography", str(measured_map), *MAP_ARGV, "--out", str(tmp_path)]
    assert main(argv) == 0
    assert "BEM on the measured heights, 128 x 128, coarsened 4x to --grid 128" in capsys.readouterr().out


def test_a_free_substrate_says_its_k_measures_the_maps_size(measured_map, capsys, tmp_path):
    argv = ["compare", "--topography", str(measured_map), *MAP_ARGV, "--grid", "32", "--substrate", "free"]
    assert main([*argv, "--out", str(tmp_path)]) == 0
    assert "its K measures the map's own size" in capsys.readouterr().out


@pytest.fixture(scope="module")
def measured_rows(measured_map, tmp_path_factory):
    return _compared(measured_map, MAP_ARGV, tmp_path_factory.mktemp("measured"))


def test_the_loads_span_the_bems_contact_fractions(measured_rows):
    fractions = [row["contact_fraction_bem"] for row in measured_rows["rows"]]
    assert 0.003 < fractions[0] < fractions[-1] < 0.3


def test_a_rough_map_gets_no_note_on_its_form(measured_rows):
    assert measured_rows["notes"] == []


def test_a_map_whose_form_carries_the_load_gets_a_note(domed_map, tmp_path):
    # The form left in: K_BEM ∝ F^0.67.
    notes = _compared(domed_map, [*MAP_ARGV, "--form", "mean"], tmp_path)["notes"]
    assert notes[0].startswith("note: K_BEM ∝ F^0.6")


def test_an_unknown_fit_model_is_one_line_naming_the_option(tmp_path, capsys):
    assert main(["compare", "--fits", "--fit-models", "bem,nope", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "jaxcontact compare: error: --fit-models 'bem,nope': each must be one of bem, persson, gw, "
        "xia2024 sneddon, xia2024 none"
    ]


def test_the_fits_table_of_maps_without_a_power_law_band_says_so():
    """A seed whose map has no power-law band has no prior: its table has the curve-alone row only."""
    import math

    from jaxcontact.studies._bem_fits import bem_fit_table

    nan = dict.fromkeys(("D_surface", "D_surface_low", "D_surface_high", "G_surface_ratio"), math.nan)
    row = dict(D_true=1.5, seed=15, model="bem", prior=False, D=1.49, D_low=1.4, D_high=1.6, covered=True)
    row |= dict(G_ratio=1.0, G_covered=True, success=True, on_bound=False, describes_data=True, seconds=1.0)
    lines = bem_fit_table([row | nan | {"G_surface_covered": False}]).splitlines()
    assert [line.split()[1:4] for line in lines[1:]] == [["surface", "alone", "–"], ["bem", "no", "1.490"]]


def test_the_table_prints_each_status_whole():
    """A point without a valid value shows its status in full, the column as wide as it needs."""
    from jaxcontact.cli._compare_table import comparison_table

    row = dict(F_star=1e-5, contact_fraction_bem=0.015, K_star_bem=0.3)
    rows = [
        row | dict(ratio_xia2024_paper=float("nan"), status_xia2024_paper="interaction_breakdown"),
        row | dict(ratio_xia2024_paper=1.25, status_xia2024_paper="ok"),
    ]
    lines = comparison_table(rows, ["xia2024 paper"]).splitlines()
    assert [line.split()[-1] for line in lines] == ["paper", "interaction_breakdown", "1.25"]
