"""Topography → D, G, l_min (docs/model.md §8) on synthetic surfaces of known truth, and real files."""

import json
import math

import equinox as eqx
import numpy as np
import pytest
from helpers import ROOT, make_scene

import jaxcontact as jc
from jaxcontact import topography as tp
from jaxcontact.cli import main
from jaxcontact.topography._spectra import periodograms

G_TRUE = 1e-10
SIZE = 1e-3
TOPOGRAPHIES = ROOT.parent / "shared" / "data" / "topographies"
needs_topographies = pytest.mark.skipif(
    not TOPOGRAPHIES.is_dir(),
    reason=f"{TOPOGRAPHIES} is absent: the real instrument files live beside the project in ../shared/data "
    "(present in CI), never in it",
)


@pytest.fixture(scope="module")
def maps():
    return {(D, seed): tp.areal_map(D, G_TRUE, SIZE, 1024, seed=seed) for D in (1.2, 1.5, 1.8) for seed in (0, 1)}


@pytest.mark.parametrize("D", [1.2, 1.5, 1.8])
@pytest.mark.parametrize("seed", [0, 1])
def test_D_of_an_areal_map(maps, D, seed):
    assert abs(tp.characterise(maps[D, seed]).D - D) < 0.03


@pytest.mark.parametrize("D", [1.2, 1.5, 1.8])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_D_of_a_profile(D, seed):
    profile = tp.random_profile(D, G_TRUE, SIZE, 100_000, seed=seed)
    assert abs(tp.characterise(profile).D - D) < 0.03


@pytest.mark.parametrize("D", [1.2, 1.5, 1.8])
def test_amplitude_with_D_held_at_the_truth(maps, D):
    for seed in (0, 1):
        ratio = tp.characterise(maps[D, seed], D=D).G / G_TRUE
        assert 1 / 1.3 < ratio < 1.3
    profile = tp.random_profile(D, G_TRUE, SIZE, 100_000, seed=0)
    assert 1 / 1.3 < tp.characterise(profile, D=D).G / G_TRUE < 1.3


def test_the_joint_95_percent_region_covers_the_truth():
    """20 seeds of a 1024² map at D = 1.5: the (D, ln G) region from the scatter between tiles."""
    covered = sum(
        tp.characterise(tp.areal_map(1.5, G_TRUE, SIZE, 1024, seed=100 + s)).covers(1.5, G_TRUE) for s in range(20)
    )
    assert covered >= 17


def test_D_and_ln_G_are_strongly_correlated_and_it_is_reported(maps):
    # G is extrapolated from the band (q ~ 1e5-1e6 rad/m) to q = 1 rad/m: a steeper fit lowers it.
    assert tp.characterise(maps[1.5, 0]).correlation > 0.8


def test_line_scans_of_an_areal_map_have_the_profile_psd_of_model_md():
    """The mean line-scan PSD of synthesised maps matches C1D = K1 q^-(5-2D) within 5 %."""
    D = 1.5
    ratios = []
    for seed in range(4):
        q, C = tp.areal_map(D, G_TRUE, SIZE, 512, seed=seed).power_spectrum_from_profile(resampling_method=None)
        band = (q > 0.01 * np.pi * 512 / SIZE) & (q < 0.1 * np.pi * 512 / SIZE)
        ratios.append(np.mean(C[band] / (tp.profile_prefactor(D, G_TRUE) * q[band] ** -(5 - 2 * D))))
    assert abs(np.mean(ratios) - 1) < 0.05


@pytest.mark.parametrize("D", [1.2, 1.5, 1.8])
def test_the_G_converter_round_trips(D):
    there = tp.convert_G(3e-10, D, "wm", "structure-function")
    assert math.isclose(tp.convert_G(there, D, "structure-function", "wm"), 3e-10, rel_tol=1e-14)


def test_the_G_converter_is_model_md_factor():
    assert math.isclose(tp.convert_G(1.0, 1.5), 2 * math.pi, rel_tol=1e-14)  # ×6.28 at D = 1.5 (§8)


@pytest.mark.parametrize("D", [1.5, 1.7])
def test_the_structure_function_of_a_wm_profile_gives_the_converted_G(D):
    """The structure-function method (quoted constant) on a W-M profile returns G_sf = convert_G(G)."""
    profile = tp.wm_profile(D, G_TRUE, SIZE, 100_000, seed=1)
    found = tp.characterise(profile, method="structure-function", D=D).G_structure_function
    assert abs(found / tp.convert_G(G_TRUE, D) - 1) < 0.1


@pytest.mark.parametrize("kind", ["profile", "map"])
def test_the_two_methods_agree_on_D(maps, kind):
    surface = tp.random_profile(1.5, G_TRUE, SIZE, 100_000, seed=0) if kind == "profile" else maps[1.5, 0]
    psd = tp.characterise(surface)
    sf = tp.characterise(surface, method="structure-function")
    assert abs(psd.D - sf.D) < 0.03


def test_the_periodogram_is_surfacetopographys():
    profile = tp.random_profile(1.5, G_TRUE, SIZE, 4096, seed=0)  # periodic: no window on either side
    q_ref, C_ref = profile.power_spectrum_from_profile(resampling_method=None)
    q, C = periodograms(profile.heights()[None, :], SIZE / 4096, periodic=True)
    np.testing.assert_allclose(C[0], C_ref[1 : 1 + q.size], rtol=1e-10)


def test_stiffness_at_the_truth_lies_in_the_reported_band():
    """K(F) from the characterised map, with the band from (D, G)'s covariance, covers K at the truth."""
    D, G = 1.5, 1e-9
    c = tp.characterise(tp.areal_map(D, G, 1e-5, 1024, seed=7))
    scene = make_scene(D=1.4, G=1e-10, E=220e9, nu=0.25, H=100e9, area=1e-4, l_min=1e-9, interaction="none")
    loads = np.geomspace(1e-1, 1e2, 4)
    band = tp.stiffness_band(c, scene, loads)
    truth = jc.solve(eqx.tree_at(lambda s: s.surface, scene, jc.Surface(D=D, G=G, l_min=c.l_min)), loads).stiffness
    assert np.all(band.status == 0)
    assert np.all(np.asarray(truth) > 0)
    assert np.all((band.lower <= truth) & (truth <= band.upper))


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: tp.read("nowhere.dat"), "does not exist"),
        (lambda: tp.read(__file__, tip_radius=-1e-6), "tip_radius = -1e-06 m must be finite and > 0"),
        (lambda: tp.characterise(tp.random_profile(1.5, G_TRUE, SIZE, 64)), "too small for any power-law band"),
        (lambda: tp.characterise(tp.random_profile(1.5, G_TRUE, SIZE, 4096), band=(1e-9, 1e-3)), "outside the data"),
        (lambda: tp.convert_G(1e-10, 2.5), "D = 2.5 is outside"),
        (lambda: tp.convert_G(1e-10, 1.5, "wm", "sf"), "target = 'sf' is not a G convention"),
    ],
)
def test_bad_input_names_the_problem(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def _cli_one_line(capsys, argv):
    code = main(argv)
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return code, err


def test_an_unreadable_file_is_one_line_with_exit_2(tmp_path, capsys):
    bad = tmp_path / "noise.xyz"
    bad.write_bytes(b"\x00\x01 not a topography")
    code, err = _cli_one_line(capsys, ["surface", str(bad), "--out", str(tmp_path)])
    assert code == 2
    assert err.startswith(f"jaxcontact surface: error: topography file {str(bad)!r} cannot be read")


def test_a_file_with_missing_points_is_refused_unless_asked_to_fill(tmp_path, capsys):
    data = tmp_path / "map.txt"  # a plain matrix of heights: the size comes from the command line
    z = tp.areal_map(1.5, G_TRUE, SIZE, 512, seed=0).heights()
    z[3, 5] = np.nan
    np.savetxt(data, z)
    argv = ["surface", str(data), "--out", str(tmp_path), "--size", "1e-3", "1e-3"]
    code, err = _cli_one_line(capsys, argv)
    assert code == 2
    assert "undefined (NaN or missing) points" in err
    assert main([*argv, "--fill-undefined"]) == 0


@needs_topographies
@pytest.mark.parametrize("name", sorted(p.name for p in TOPOGRAPHIES.glob("*")) if TOPOGRAPHIES.is_dir() else [])
def test_every_real_file_gives_a_result_or_a_refusal_with_psd_png(tmp_path, capsys, name):
    """With consent to fill missing points: D in (1, 2) and a scene, or exit 2, psd.png and a suggestion."""
    argv = ["surface", str(TOPOGRAPHIES / name), "--out", str(tmp_path), "--format", "json", "--fill-undefined"]
    code = main(argv)
    captured = capsys.readouterr()
    if code == 0:
        payload = json.loads(captured.out)
        assert (1 < payload["psd"]["D"] < 2, (tmp_path / "surface.toml").is_file()) == (True, True)
    else:
        suggests = "--band " in captured.err or "no stretch of the spectrum" in captured.err
        assert (code, (tmp_path / "psd.png").is_file(), suggests) == (2, True, True)


@needs_topographies
@pytest.mark.parametrize("name", sorted(p.name for p in TOPOGRAPHIES.glob("*")) if TOPOGRAPHIES.is_dir() else [])
def test_every_real_file_ends_without_a_traceback(tmp_path, capsys, name):
    main(["surface", str(TOPOGRAPHIES / name), "--out", str(tmp_path), "--format", "json"])
    assert "Traceback" not in capsys.readouterr().err


@needs_topographies
def test_a_stylus_profile_becomes_a_scene_that_run_takes(tmp_path, capsys):
    assert main(["surface", str(TOPOGRAPHIES / "dektak-1.csv"), "--out", str(tmp_path / "s")]) == 0
    capsys.readouterr()
    assert main(["run", str(tmp_path / "s" / "surface.toml"), "--out", str(tmp_path / "r"), "--no-progress"]) == 0
    assert (tmp_path / "r" / "results.csv").is_file()


@pytest.fixture(scope="module")
def scan_run(tmp_path_factory):
    """`run --topography` on a synthetic 512² scan: the output folder and the JSON rows."""
    import contextlib
    import io

    folder = tmp_path_factory.mktemp("scan")
    data = folder / "map.txt"
    np.savetxt(data, tp.areal_map(1.5, 1e-9, 1e-5, 512, seed=2).heights())
    argv = ["run", "--topography", str(data), "--size", "1e-5", "1e-5", "--out", str(folder / "o")]
    with contextlib.redirect_stdout(io.StringIO()) as out:
        assert main([*argv, "--format", "json", "--no-progress"]) == 0
    payload = json.loads(out.getvalue())
    return folder / "o", payload["rows"], payload["notes"]


def test_run_goes_from_a_scan_to_a_stiffness_table_with_its_band(scan_run):
    folder, rows, _ = scan_run
    positive = [row for row in rows if row["status"] == "ok" and row["K_N_per_m"] > 0]
    assert len(positive) > 10
    assert all(row["K_lower_95_N_per_m"] < row["K_N_per_m"] < row["K_upper_95_N_per_m"] for row in positive)
    assert (folder / "stiffness_band.png").is_file()


@pytest.mark.parametrize("model", ["xia2024", "jzz2010", "gw"])
def test_each_other_models_value_has_its_own_status_beside_it(scan_run, model):
    """A value where the status says ok, and a status that says why where there is none."""
    _, rows, _ = scan_run
    assert all((row[f"status_{model}"] == "ok") == (row[f"K_{model}_N_per_m"] is not None) for row in rows)


def test_run_checks_that_a_rough_maps_own_bem_grows_as_a_rough_surfaces(scan_run):
    # A self-affine map (D = 1.5) with no form: its BEM grows as F^0.86-0.89 (docs/validation.md),
    # above the 0.75 under which the output warns that the form carries the load.
    _, _, notes = scan_run
    (line,) = [note for note in notes if note.startswith("form check: the BEM on the map itself")]
    assert float(line.split("F^")[1].split()[0]) > 0.75


def test_run_solves_on_the_measured_spectrum_by_default_and_says_so(scan_run):
    _, _, notes = scan_run
    assert any(note.startswith("route: the measured spectrum") for note in notes)


@needs_topographies
@pytest.mark.parametrize("name", ["dektak-1.csv", "opd-1.opd"])
def test_a_straight_band_that_agrees_with_the_corrected_one_stands(name):
    """Both files have a wider roll-off-corrected window whose slope agrees with the straight one's
    within their combined standard error (0.19 and 0.08 of it): the better determined straight band
    is kept."""
    assert tp.characterise(tp.read(TOPOGRAPHIES / name, fill_undefined=True)).rolloff is None


@pytest.fixture(scope="module")
def run_without_band(tmp_path_factory):
    """`run --topography x3p-2.x3p` (a map without a power-law band) on its default route: JSON rows
    and notes."""
    import contextlib
    import io

    folder = tmp_path_factory.mktemp("x3p")
    argv = ["run", "--topography", str(TOPOGRAPHIES / "x3p-2.x3p"), "--out", str(folder), "--format", "json"]
    with contextlib.redirect_stdout(io.StringIO()) as out:
        assert main([*argv, "--no-progress"]) == 0
    payload = json.loads(out.getvalue())
    return payload["rows"], payload["notes"]


@needs_topographies
def test_a_map_without_a_power_law_band_runs_on_its_whole_measured_spectrum(run_without_band):
    _, notes = run_without_band
    assert any("of the whole map" in note and "no power-law band" in note for note in notes), notes


@needs_topographies
def test_a_map_without_a_power_law_band_has_its_stiffness_band_at_every_load(run_without_band):
    rows, _ = run_without_band
    assert all(row["K_lower_95_N_per_m"] < row["K_N_per_m"] < row["K_upper_95_N_per_m"] for row in rows)


@needs_topographies
def test_a_map_without_a_power_law_band_leaves_out_the_models_that_need_one(run_without_band):
    # A model registered by another test (tests/toy_model.py) takes D, G, l_min too, and is left out as well.
    _, notes = run_without_band
    assert {note.split(":")[0] for note in notes if "takes D, G, l_min only" in note} >= {"xia2024", "jzz2010"}


@needs_topographies
def test_the_power_law_route_on_a_map_without_a_band_suggests_one(tmp_path, capsys):
    argv = ["run", "--topography", str(TOPOGRAPHIES / "x3p-2.x3p"), "--route", "power-law", "--out", str(tmp_path)]
    code, err = _cli_one_line(capsys, argv)
    assert (code, "--band 4.56e-06 4.01e-05" in err) == (2, True), err
