"""Reading instrument files: missing points, sizes and units, damaged files, flat maps, option errors."""

import json

import numpy as np
import pytest
from helpers import ROOT

from jaxcontact import topography as tp
from jaxcontact.cli import main

pytest.importorskip("SurfaceTopography")

D_TRUE, G_TRUE, L = 1.5, 1e-9, 1e-5
OPD = ROOT.parent / "shared" / "data" / "topographies" / "opd-1.opd"


@pytest.fixture(scope="module")
def heights():
    """A map whose intact characterisation covers the truth (the baseline test below), so that
    the filled maps' tests see what filling does."""
    return tp.areal_map(D_TRUE, G_TRUE, L, 512, seed=6).heights()


def test_the_intact_map_covers_the_truth(heights, tmp_path):
    np.savetxt(tmp_path / "map.txt", heights)
    c = tp.characterise(tp.read(tmp_path / "map.txt", size=(L, L)))
    assert c.ci95["D"][0] <= D_TRUE <= c.ci95["D"][1] and c.ci95["G"][0] <= G_TRUE <= c.ci95["G"][1]


def with_missing(heights, fraction, kind, seed=1):
    """`heights` with `fraction` of the points NaN: random points, or random 32² blocks."""
    rng = np.random.default_rng(seed)
    n = heights.shape[0]
    if kind == "points":
        return np.where(rng.random(heights.shape) < fraction, np.nan, heights)
    mask = np.zeros(heights.shape, bool)
    while mask.mean() < fraction:
        i, j = rng.integers(0, n - 32, 2)
        mask[i : i + 32, j : j + 32] = True
    return np.where(mask, np.nan, heights)


def one_line_error(capsys, argv, code=2):
    assert main(argv) == code
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    return err.strip()


@pytest.mark.parametrize("kind", ["points", "blocks"])
@pytest.mark.parametrize("fraction", [0.01, 0.10])
def test_a_filled_map_has_intervals_that_cover_the_truth(heights, tmp_path, fraction, kind):
    """Issue 35.3: filling biases D low; up to 15 % filled, the intervals are widened to cover that."""
    np.savetxt(tmp_path / "map.txt", with_missing(heights, fraction, kind))
    c = tp.characterise(tp.read(tmp_path / "map.txt", size=(L, L), fill_undefined=True))
    assert c.ci95["D"][0] <= D_TRUE <= c.ci95["D"][1], (c.D, c.ci95["D"])
    assert c.ci95["G"][0] <= G_TRUE <= c.ci95["G"][1], (c.G, c.ci95["G"])
    assert any("filled by interpolation" in d for d in c.diagnostics)


@pytest.mark.parametrize("kind", ["points", "blocks"])
@pytest.mark.parametrize("fraction", [0.30, 0.50])
def test_a_map_missing_more_than_15_percent_is_refused(heights, tmp_path, fraction, kind):
    np.savetxt(tmp_path / "map.txt", with_missing(heights, fraction, kind))
    with pytest.raises(ValueError, match=r"% undefined .* more than 15 % cannot be filled"):
        tp.read(tmp_path / "map.txt", size=(L, L), fill_undefined=True)


def test_the_filled_fraction_is_recorded(heights, tmp_path):
    np.savetxt(tmp_path / "map.txt", with_missing(heights[:64, :64], 0.05, "points"))
    top = tp.read(tmp_path / "map.txt", size=(L, L), fill_undefined=True)
    assert top.info["filled_fraction"] == pytest.approx(np.mean(np.isnan(np.loadtxt(tmp_path / "map.txt"))))


def test_size_overrides_the_files_own(tmp_path):
    """Issue 35.5: `size` replaces the size a file states (an x–z profile states one)."""
    x = np.arange(4096) * 1e-6
    z = tp.random_profile(1.5, 1e-10, 4096e-6, 4096, seed=0).heights()
    np.savetxt(tmp_path / "profile.txt", np.column_stack([x, z]))
    as_given = tp.read(tmp_path / "profile.txt")
    overridden = tp.read(tmp_path / "profile.txt", size=2e-3)
    assert as_given.physical_sizes[0] == pytest.approx(4096e-6)
    assert overridden.physical_sizes[0] == pytest.approx(2e-3)
    np.testing.assert_allclose(overridden.heights(), as_given.heights())


def test_an_x_z_profile_in_micrometres_is_read_in_metres(tmp_path):
    x = np.arange(4096) * 0.5  # µm
    z = tp.random_profile(1.5, 1e-10, 2048e-6, 4096, seed=0).heights() * 1e6  # µm
    np.savetxt(tmp_path / "profile.txt", np.column_stack([x, z]))
    top = tp.read(tmp_path / "profile.txt", unit="µm")
    assert top.physical_sizes[0] == pytest.approx(2048e-6)
    assert np.std(top.heights()) == pytest.approx(np.std(z) * 1e-6, rel=1e-9)


def test_heights_in_the_wrong_unit_are_warned_about(tmp_path):
    np.savetxt(tmp_path / "map.txt", tp.areal_map(1.5, 1e-10, 1e-3, 64, seed=0).heights() * 1e6)
    with pytest.warns(UserWarning, match=r"rms height .* m is outside what instruments measure"):
        tp.read(tmp_path / "map.txt", size=(1e-3, 1e-3))


def test_a_flat_map_says_so(tmp_path, capsys):
    """Issue 35.6: no RuntimeWarnings, no D = nan."""
    np.savetxt(tmp_path / "flat.txt", np.full((64, 64), 3e-6))
    err = one_line_error(
        capsys, ["surface", str(tmp_path / "flat.txt"), "--size", "1e-3", "1e-3", "--out", str(tmp_path)]
    )
    assert err.endswith("error: the map is flat: every height is the same, so it has no roughness to characterise")


def test_a_damaged_file_is_one_line_naming_its_format(tmp_path, capsys):
    """Issue 35.4: the format the extension names and what is wrong, no list of readers, no raw bytes."""
    if not OPD.is_file():
        pytest.skip(f"{OPD} is absent (../shared/data beside the project)")
    (tmp_path / "cut.opd").write_bytes(OPD.read_bytes()[:2000])
    err = one_line_error(capsys, ["surface", str(tmp_path / "cut.opd"), "--out", str(tmp_path)])
    assert err == (
        f"jaxcontact surface: error: topography file {str(tmp_path / 'cut.opd')!r} cannot be read as Wyko OPD "
        "(the format of .opd files): The file ended after 6 of 16 bytes of a data block; it is probably truncated."
    )


def test_a_file_that_is_not_its_extensions_format_is_refused(tmp_path, capsys):
    (tmp_path / "scan.x3p").write_text("1 2 3\n4 5 6\n")
    err = one_line_error(capsys, ["surface", str(tmp_path / "scan.x3p"), "--out", str(tmp_path)])
    assert "cannot be read as XML 3D surface profile (X3P) (the format of .x3p files)" in err


@pytest.mark.parametrize(
    "options, message",
    [
        (["--size", "-1e-3", "1e-3"], "error: --size -0.001 0.001 m must be finite and > 0 (valid range (0, inf) m)"),
        (["--band", "-1e-6", "1e-5"], "error: --band -1e-06 1e-05 m must be (shortest, longest) wavelengths"),
        (["--tip-radius", "-2e-6"], "error: --tip-radius -2e-06 m must be finite and > 0"),
        (["--groups", "2"], "error: --groups 2 must be an integer >= 3"),
    ],
)
def test_negative_and_bad_options_are_refused_by_name(tmp_path, capsys, options, message):
    """Issues 35.7 and 35.12: negative numbers parse, and are refused as the user typed them."""
    np.savetxt(tmp_path / "map.txt", tp.areal_map(1.5, 1e-10, 1e-3, 64, seed=0).heights())
    argv = ["surface", str(tmp_path / "map.txt"), "--out", str(tmp_path)]
    if "--size" not in options:
        argv += ["--size", "1e-3", "1e-3"]
    assert message in one_line_error(capsys, argv + options)


def test_a_file_without_a_size_asks_for_the_option(tmp_path, capsys):
    np.savetxt(tmp_path / "map.txt", np.zeros((8, 8)))
    err = one_line_error(capsys, ["surface", str(tmp_path / "map.txt"), "--out", str(tmp_path)])
    assert err.endswith("does not say its physical size: give --size L for a line scan or --size LX LY for a map, in m")


def test_the_same_error_from_python_is_in_python_spelling(tmp_path):
    np.savetxt(tmp_path / "map.txt", np.zeros((8, 8)))
    with pytest.raises(ValueError, match=r"does not say its physical size: give size \(m\)$"):
        tp.read(tmp_path / "map.txt")


def test_surface_reads_an_x_z_profile_with_its_unit(tmp_path, capsys):
    x = np.arange(8192) * 0.25  # µm
    z = tp.random_profile(1.5, 1e-10, 2048e-6, 8192, seed=3).heights() * 1e6
    np.savetxt(tmp_path / "profile.txt", np.column_stack([x, z]))
    argv = ["surface", str(tmp_path / "profile.txt"), "--unit", "µm", "--out", str(tmp_path), "--format", "json"]
    assert main(argv) == 0
    payload = json.loads(capsys.readouterr().out)
    assert abs(payload["psd"]["D"] - 1.5) < 0.05


@pytest.mark.parametrize("shape, size", [((64, 48), (1e-5, 2e-5)), ((500,), (1e-5,))])
def test_an_npy_file_reads_as_surfacetopographys_reader_reads_it(tmp_path, shape, size):
    """`.npy` heights come from numpy (SurfaceTopography's serial reader copies them one by one):
    the same heights, sizes and periodicity, a Fortran-ordered array too."""
    from SurfaceTopography import open_topography

    path = tmp_path / "h.npy"
    np.save(path, np.asfortranarray(np.random.default_rng(0).standard_normal(shape) * 1e-7))
    ours = tp.read(path, size=size)
    theirs = open_topography(str(path)).topography(physical_sizes=size, unit="m").detrend("center")
    np.testing.assert_array_equal(ours.heights(), theirs.heights())
    assert ours.physical_sizes == theirs.physical_sizes
    assert ours.is_periodic == theirs.is_periodic


TOPOGRAPHIES = ROOT.parent / "shared" / "data" / "topographies"
needs_real_files = pytest.mark.skipif(
    not TOPOGRAPHIES.is_dir(), reason="the real instrument files live in ../shared/data"
)


def _profile_rows(n=400):
    """A random-walk x–z profile (m), one "x,z" row a line."""
    z = np.cumsum(np.random.default_rng(0).normal(size=n)) * 1e-8
    return [f"{i * 1e-6:.9e},{v:.9e}\n" for i, v in enumerate(z)]


def _written(tmp_path, rows, header="x,z\n", name="profile.csv"):
    path = tmp_path / name
    path.write_text(header + "".join(rows))
    return path


def test_a_header_recognised_by_content_keeps_every_row(tmp_path):
    assert tp.read(_written(tmp_path, _profile_rows(), header="# profilometer\nx (m), z (m)\n")).nb_grid_pts == (400,)


@pytest.mark.parametrize("row", [50, 101, 398])
def test_a_text_value_among_the_rows_is_refused_naming_its_line(tmp_path, row):
    rows = _profile_rows()
    rows[row] = "1.0e-5,abc\n"
    with pytest.raises(ValueError, match=rf"line {row + 2} \('1.0e-5,abc'\) is not a row of numbers"):
        tp.read(_written(tmp_path, rows))


def test_a_profile_with_every_row_twice_is_refused(tmp_path):
    rows = [r for r in _profile_rows() for _ in (0, 1)]
    with pytest.raises(ValueError, match=r"line 3 repeats x = 0 of line 2 \(a duplicated row\?\)"):
        tp.read(_written(tmp_path, rows))


def test_rows_out_of_x_order_are_refused_naming_the_line(tmp_path):
    rows = _profile_rows()
    rows[10], rows[11] = rows[11], rows[10]
    with pytest.raises(ValueError, match=r"line 13 has x = 1e-05, below line 12's 1.1e-05: the rows are not in"):
        tp.read(_written(tmp_path, rows))


def test_a_row_with_another_number_of_values_is_refused(tmp_path):
    rows = _profile_rows()
    rows[7] = "7e-6,1e-8,3\n"
    with pytest.raises(ValueError, match="line 9 has 3 values where the rows above have 2"):
        tp.read(_written(tmp_path, rows))


def test_a_latin1_byte_that_the_reader_rejects_is_named_with_its_line(tmp_path):
    path = tmp_path / "latin1.csv"
    path.write_bytes("# Messung é\n".encode("latin-1") + "".join(_profile_rows()).encode())
    with pytest.raises(ValueError, match="line 1 has the byte 0xe9, which is not UTF-8"):
        tp.read(path)


@needs_real_files
def test_a_di_file_cut_short_is_one_line(tmp_path):
    path = tmp_path / "cut.di"
    path.write_bytes((TOPOGRAPHIES / "di-1.di").read_bytes()[:100])
    with pytest.raises(ValueError, match="without a readable data channel"):
        tp.read(path)


@needs_real_files
def test_a_di_header_damaged_where_only_the_heights_notice_is_one_line(tmp_path):
    """Three header bytes changed (found by fuzzing): the reader opens it and fails on the heights' unit."""
    data = bytearray((TOPOGRAPHIES / "di-1.di").read_bytes())
    for offset, value in ((144, 182), (376, 236), (383, 238)):
        data[offset] = value
    path = tmp_path / "damaged.di"
    path.write_bytes(bytes(data))
    with pytest.raises(ValueError, match="cannot be read: Unknown unit"):
        tp.read(path)
