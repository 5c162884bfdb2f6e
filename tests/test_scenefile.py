"""Scene files: the embedded default, and one clear message for each kind of bad file."""

import pathlib

import numpy as np
import pytest
from helpers import ROOT, TABLE1

import jaxcontact as jc
from jaxcontact.cli._scenefile import SceneFileError, load_scene, parse_scene

GOOD = {
    "surface": {"D": 1.4058, "G": 2.2826e-10},
    "material": {"E": 220e9, "nu": 0.25, "H": 100e9},
    "joint": {"area": 1e-4},
    "loads": {"values": [2.2, 22.0]},
}


def test_embedded_default_is_the_data_file():
    data_file = ROOT / "data" / "scenes" / "table1_grinding.toml"
    spec, from_data = load_scene(), load_scene(data_file)
    assert spec.title == from_data.title
    assert np.array_equal(spec.loads, from_data.loads)
    s = spec.scene
    assert (s.surface.D, s.surface.G, s.surface.l_min, s.material.E, s.material.nu, s.material.H, s.area) == tuple(
        TABLE1[k] for k in ("D", "G", "l_min", "E", "nu", "H", "area")
    )
    assert s.model == jc.Xia2024(jc.PaperInteraction(), jc.MajumdarBhushan())
    np.testing.assert_allclose(spec.load_star[[0, -1]], [1e-7, 1e-3], rtol=1e-12)
    assert spec.loads.size == 41


def test_loads_in_F_star_and_newtons():
    spec = parse_scene({**GOOD, "loads": {"unit": "F_star", "values": [1e-6]}})
    np.testing.assert_allclose(spec.loads, [22.0], rtol=1e-14)
    spec = parse_scene({**GOOD, "loads": {"range": [1.0, 100.0], "count": 3}})
    np.testing.assert_allclose(spec.loads, [1.0, 10.0, 100.0], rtol=1e-14)


def with_(table, key, value):
    data = {k: dict(v) for k, v in GOOD.items()}
    data.setdefault(table, {})[key] = value
    return data


@pytest.mark.parametrize(
    "data, message",
    [
        (with_("surface", "Dd", 1.4), r"unknown key surface.Dd \(allowed in \[surface\]: D, G, l_min\)"),
        (with_("surface", "D", "rough"), r"surface.D = 'rough' must be a number"),
        (with_("surface", "D", 2.3), r"D \(fractal dimension\) = 2.3 is outside its valid range \(1, 2\)"),
        (with_("material", "nu", 0.7), r"nu .*= 0.7 .*\[0, 0.5\)"),
        (with_("model", "name", "gw2"), r"model = 'gw2' is not one of 'xia2024', 'jzz2010', 'gw', 'persson'"),
        (with_("effects", "interaction", "strong"), r"interaction = 'strong' is not one of"),
        (with_("effects", "regime_shares", "yes"), r"effects.regime_shares = 'yes' must be true or false"),
        (with_("loads", "unit", "kN"), r"loads.unit = 'kN' is not one of 'N', 'F_star'"),
        (with_("loads", "range", [1.0, 2.0]), r"exactly one of values"),
        ({**GOOD, "loads": {"range": [5.0, 1.0]}}, r"loads.range = \[5.0, 1.0\] must satisfy 0 < low <= high"),
        ({**GOOD, "loads": {"values": [1.0, -2.0]}}, r"loads.values\[1\] = -2.0 must be > 0"),
        ({**GOOD, "loads": {"range": [1.0, 2.0], "count": 0}}, r"loads.count = 0 must be in"),
        ({k: v for k, v in GOOD.items() if k != "material"}, r"missing table \[material\]"),
        ({**GOOD, "surface": {"D": 1.4}}, r"missing key surface.G"),
        ({**GOOD, "extras": {}}, r"unknown table \[extras\]"),
    ],
)
def test_bad_files_name_the_key(data, message):
    with pytest.raises(SceneFileError, match=message):
        parse_scene(data)


def test_unreadable_files(tmp_path: pathlib.Path):
    with pytest.raises(SceneFileError, match="does not exist"):
        load_scene(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[surface\nD = 1.4")
    with pytest.raises(SceneFileError, match="is not valid TOML"):
        load_scene(bad)


def test_scene_object_is_the_library_scene():
    assert isinstance(parse_scene(GOOD).scene, jc.Scene)


def test_a_byte_order_mark_is_accepted(tmp_path):
    path = tmp_path / "bom.toml"
    path.write_text("\ufeff" + (ROOT / "data" / "scenes" / "table1_grinding.toml").read_text(), encoding="utf-8")
    assert load_scene(path).title == load_scene().title


def test_a_directory_is_not_called_missing(tmp_path):
    with pytest.raises(SceneFileError, match="is a directory"):
        load_scene(tmp_path)


@pytest.mark.parametrize(
    "model, expected",
    [
        ({"spot_stiffness": "sneddon"}, jc.Xia2024(spot_stiffness=jc.Sneddon())),
        ({"interaction": "series"}, jc.Xia2024(interaction=jc.SeriesInteraction())),
        ({"distribution": "wk"}, jc.Xia2024(distribution=jc.WangKomvopoulos())),
        (
            {"quadrature": "gauss-legendre", "quadrature_nodes": 24},
            jc.Xia2024(interaction=jc.PaperInteraction(quadrature=jc.GaussLegendre(nodes=24))),
        ),
    ],
)
def test_every_model_option_is_accepted_in_the_model_table(model, expected):
    """Issue 35.9: what `Scene` takes by name, a scene file takes in [model]."""
    assert parse_scene({**GOOD, "model": {"name": "xia2024", **model}}).scene.model == expected


def test_an_option_given_in_model_and_effects_is_refused():
    data = {**GOOD, "model": {"spot_stiffness": "sneddon"}, "effects": {"spot_stiffness": "paper"}}
    with pytest.raises(SceneFileError, match=r"spot_stiffness is given in both \[model\] and \[effects\]"):
        parse_scene(data)
