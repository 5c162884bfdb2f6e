"""What a user is told: missing extras, implausible units, every exit code of the command line, and a
mistake in a Python call."""

import sys

import numpy as np
import pytest
from helpers import ROOT, TABLE1, make_scene, refused_type

import jaxcontact as jc
from jaxcontact import bem, fitting
from jaxcontact import topography as tp
from jaxcontact.cli import main


@pytest.fixture
def a_map(tmp_path):
    path = tmp_path / "map.txt"
    np.savetxt(path, np.random.default_rng(0).normal(size=(16, 16)) * 1e-7)
    return path


@pytest.mark.parametrize(
    "package, argv, extra",
    [
        ("SurfaceTopography", ["surface", "{map}", "--size", "1e-3", "1e-3"], "surface"),
        ("SurfaceTopography", ["run", "--topography", "{map}", "--size", "1e-3", "1e-3"], "surface"),
        ("ContactMechanics", ["compare", "--realisations", "1", "--reference", "contactmechanics"], "bem"),
    ],
)
def test_a_missing_extra_is_one_line_naming_it(monkeypatch, capsys, tmp_path, a_map, package, argv, extra):
    """Issue 35.10: not "internal error": which extra to install, exit 2."""
    monkeypatch.setitem(sys.modules, package, None)
    code = main([a.format(map=a_map) for a in argv] + ["--out", str(tmp_path / "o"), "--no-progress"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and err[0].endswith(
        f"which jaxcontact's {extra!r} extra installs: pip install 'jaxcontact[{extra}]'"
    )


def test_a_missing_extra_in_python_is_an_import_error_naming_it(monkeypatch, a_map):
    monkeypatch.setitem(sys.modules, "SurfaceTopography", None)
    with pytest.raises(ImportError, match=r"pip install 'jaxcontact\[surface\]'"):
        tp.read(a_map, size=(1e-3, 1e-3))


def test_a_modulus_in_gpa_is_warned_about_in_python():
    """Issue 35.11: the library warns as the command line does; the point is flagged, not an error."""
    with pytest.warns(jc.PlausibilityWarning, match=r"E = 220 Pa is far outside .* given in GPa or MPa instead of Pa"):
        make_scene(**dict(TABLE1, E=220.0))


def test_a_plausible_scene_is_not_warned_about(recwarn):
    make_scene(**TABLE1)
    assert not [w for w in recwarn if issubclass(w.category, jc.PlausibilityWarning)]


def test_an_interrupted_command_exits_130(monkeypatch, capsys, tmp_path):
    """Exit codes (docs/cli.md): 130 after Ctrl-C, with one line."""
    from jaxcontact.cli import _commands as commands

    def interrupted(*_):
        raise KeyboardInterrupt

    monkeypatch.setattr(commands, "load_scene", interrupted, raising=False)
    monkeypatch.setattr("jaxcontact.cli._scenefile.load_scene", interrupted)
    assert main(["run", "--out", str(tmp_path), "--no-progress"]) == 130
    assert capsys.readouterr().err == "jaxcontact: interrupted\n"


def test_a_usage_mistake_is_one_line_with_exit_2(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["surface", "scan.x3p", "--unit", "inch"])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err.splitlines()
    assert err == [
        "jaxcontact surface: error: argument --unit: invalid choice: 'inch' (choose from 'm', 'mm', 'µm', 'um', 'nm')"
    ]


@pytest.mark.parametrize(
    "argv, message",
    [
        (["run", "--area", "-1"], r"--area -1 \(nominal contact area, m²\) is outside its valid range"),
        (["run", "--l-min", "-1e-9"], r"--l-min -1e-09 \(lower cutoff length, m\) is outside its valid range"),
        (["run", "--l-min", "nan"], r"--l-min nan \(lower cutoff length, m\) is outside its valid range"),
        (["run", "--model", "bem"], r"grid = 256 is too coarse for l_min = 1e-09 m"),
        (["compare", "--scale", "--validation"], r"--scale and --validation: give one study at a time"),
        (["compare", "--seed", "-1"], r"--seed -1 must be an integer >= 0"),
    ],
)
def test_an_option_out_of_its_range_or_ignored_is_one_line_with_exit_2(tmp_path, capsys, argv, message):
    assert main([*argv, "--out", str(tmp_path / "o"), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and __import__("re").search(message, err[0]), err


def test_an_area_option_is_warned_about_as_a_scene_files_value(tmp_path, capsys):
    assert main(["run", "--area", "264", "--out", str(tmp_path), "--no-progress", "--format", "json"]) == 0
    assert "area = 264 m² is far outside what engineering surfaces have" in capsys.readouterr().err


@pytest.mark.parametrize(
    "argv",
    [
        ["run"],
        ["surface", "{map}", "--size", "1e-3", "1e-3"],
        ["fit", str(ROOT / "data" / "table1_grinding_generated.csv")],
        ["figures"],
    ],
    ids=["run", "surface", "fit", "figures"],
)
def test_an_output_folder_that_is_a_file_is_refused_before_computing(tmp_path, capsys, a_map, argv):
    existing = tmp_path / "results.csv"
    existing.write_text("kept\n")
    argv = [a.replace("{map}", str(a_map)) for a in argv]
    assert main([*argv, "--out", str(existing), "--no-progress"]) == 2
    assert capsys.readouterr().err.strip().endswith("is a file, not a folder; name a folder to write into")


def test_a_cache_folder_that_is_a_file_is_refused(tmp_path, capsys):
    existing = tmp_path / "cache"
    existing.write_text("")
    assert main(["compare", "--cache-dir", str(existing), "--out", str(tmp_path / "o"), "--no-progress"]) == 2
    assert "--cache-dir" in capsys.readouterr().err


def _curve():
    loads = np.geomspace(1e-9, 1e-4, 12) * TABLE1["E"] * TABLE1["area"]
    return loads, 1e9 * (loads / loads[0]) ** 0.4


API_MISTAKES = {
    "BEM grid 2**20": (lambda: jc.BEM(grid=2**20), r"grid = 1048576 must be a power of two in \[8, 8192\]"),
    "ragged batch": (
        lambda: fitting.fit_batch([[1.0, 2.0, 3.0], [1.0, 2.0]], [[1.0, 2.0, 3.0], [1.0, 2.0]], make_scene(**TABLE1)),
        r"loads = .* must be real numbers \(an array of one shape\)",
    ),
    "empty batch": (
        lambda: fitting.fit_batch(np.zeros((0, 5)), np.zeros((0, 5)), make_scene(**TABLE1)),
        r"loads has shape \(0, 5\): give \(curves, points\), at least one curve",
    ),
    "no band samples": (
        lambda: fitting.sample(*_curve(), make_scene(**TABLE1), band_samples=0),
        "band_samples = 0 must be an integer >= 1",
    ),
    "a prior as a tuple": (
        lambda: fitting.fit(*_curve(), make_scene(**TABLE1), prior={"D": (1.45, 0.05)}),
        r"prior\['D'\] = \(1.45, 0.05\) must be fitting.Normal\(mean, sd\) or fitting.Bounds\(low, high\)",
    ),
    "an approach in text": (
        lambda: fitting.fit(*_curve(), make_scene(**TABLE1), approach="abc"),
        "approach = 'abc' must be real numbers",
    ),
    "starts of another width": (
        lambda: fitting.fit(*_curve(), make_scene(**TABLE1), starts=[[1.4, 1e-10, 3.0]]),
        r"starts has shape \(1, 3\): give \(n, 2\) values of D, G",
    ),
    "a start beyond its bound": (
        lambda: fitting.fit(*_curve(), make_scene(**TABLE1), starts=[[2.5, 1e-10]]),
        r"starts: D = 2.5 is outside its search range \(1, 2\)",
    ),
}


@pytest.mark.parametrize("call, message", API_MISTAKES.values(), ids=API_MISTAKES.keys())
def test_a_python_mistake_is_a_value_error_naming_it(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_complex_heights_are_refused():
    with refused_type("heights", "heights has dtype complex128: give real heights"):
        bem.solve(np.ones((16, 16)) * (1 + 1j), 1e-4, 1e11, np.array([1.0]))


def test_a_sweep_beyond_the_free_memory_is_refused_before_computing(tmp_path, capsys):
    argv = ["sweep", "--D", "1.3:1.7:100000", "--G", "1e-11:1e-9:100000", "--out", str(tmp_path), "--no-progress"]
    assert main(argv) == 2
    assert "points would need about" in capsys.readouterr().err


def test_a_method_by_name_is_refused_with_its_object():
    with refused_type("method", r"method = 'lm': give the object, fitting.LevenbergMarquardt\(\)"):
        fitting.fit([1.0, 2.0, 3.0], [1e8, 2e8, 3e8], make_scene(**TABLE1), method="lm")


def test_a_substrate_by_name_is_refused_with_its_object():
    with refused_type("substrate", r"substrate = 'free': give the object, bem.Free\(\)"):
        bem.solve(np.zeros((16, 16)), 1e-4, 1e11, np.array([1.0]), substrate="free")


def test_a_priors_mean_in_text_is_refused():
    with refused_type("mean", r"mean = 'a' must be real numbers"):
        fitting.Normal("a", 0.1)
