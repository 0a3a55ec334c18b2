"""stfit.export writes what `stfit export` writes, byte for byte, from a fits file or from
FitResult objects, to stdout text, one file or a folder; bad options raise ValueError."""

import pathlib

import pytest

import stfit

FITS = "fits/example-fits.json"
RENDERERS = ["mitsuba3", "pbrt-v4", "cycles", "appleseed", "openpbr", "vray"]


@pytest.mark.parametrize("target", RENDERERS)
def test_text_equals_the_cli_stdout(cli, at_repo, target):
    expected = cli("export", FITS, "--to", target, "--sample", "frosted")
    if target == "vray":
        # Frosted Beckmann's gtr_gamma ends on its bound, said as the CLI says it on stderr.
        with pytest.warns(UserWarning, match="frosted_beckmann: gtr_gamma .* ended on a bound"):
            text = stfit.export(FITS, to=target, sample="frosted")
    else:
        text = stfit.export(FITS, to=target, sample="frosted")
    assert text == expected


def test_fit_results_export_like_their_file(cli, at_repo):
    fits = stfit.read_fits(FITS)
    expected = cli("export", FITS, "--to", "pbrt-v4", "--sample", "ground", "--model", "ggx")
    ground_ggx = [f for f in fits if f.sample == "ground" and f.model == "ggx"]
    assert len(ground_ggx) == 1
    assert stfit.export(ground_ggx[0], to="pbrt-v4") == expected
    assert stfit.export(fits, to="pbrt-v4", sample="ground", model="ggx") == expected


def test_model_selection_separates_gamma_fixed(cli, at_repo):
    for model in ["student-t", "student-t-fixed"]:
        expected = cli("export", FITS, "--to", "appleseed", "--sample", "etched", "--model", model)
        assert stfit.export(FITS, to="appleseed", sample="etched", model=model) == expected
    assert stfit.export(FITS, to="appleseed", sample="etched", model="student-t") != \
        stfit.export(FITS, to="appleseed", sample="etched", model="student-t-fixed")


def test_one_file_of_each_type_like_the_cli(cli, at_repo, tmp_path):
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    cli("export", FITS, "--to", "mitsuba3", "--sample", "etched",
        "--out", str(tmp_path / "cli" / "scene.xml"))
    written = stfit.export(FITS, to="mitsuba3", sample="etched", out=tmp_path / "py" / "scene.xml")
    assert [pathlib.Path(p).name for p in written] == ["scene.xml", "scene.py"]
    for name in ["scene.xml", "scene.py"]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()


def test_folder_holds_one_file_per_fit_like_the_cli(cli, at_repo, tmp_path):
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    listed = cli("export", FITS, "--to", "vray", "--model", "ggx", "--out", str(tmp_path / "cli"))
    written = stfit.export(FITS, to="vray", model="ggx", out=str(tmp_path / "py"))
    names = sorted(pathlib.Path(p).name for p in written)
    assert names == sorted(pathlib.Path(p).name for p in listed.split())
    assert names == ["etched_ggx-vray.vrscene", "frosted_ggx-vray.vrscene",
                     "ground_ggx-vray.vrscene"]
    for name in names:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()


@pytest.mark.parametrize("options", [
    ["--layer", "interface"],
    ["--walks", "16", "--seed", "5", "--absorption", "0.1"],
])
def test_radiance_file_equals_the_cli(cli, at_repo, tmp_path, options):
    cli("export", FITS, "--to", "radiance", "--sample", "ground", "--model", "ggx",
        "--out", str(tmp_path / "cli.xml"), *options)
    keywords = {}
    for flag, value in zip(options[::2], options[1::2]):
        name = flag[2:]
        keywords[name] = value if name == "layer" else float(value) if name == "absorption" \
            else int(value)
    written = stfit.export(FITS, to="radiance", sample="ground", model="ggx",
                           out=tmp_path / "py.xml", **keywords)
    assert [pathlib.Path(p).name for p in written] == ["py.xml"]
    text = (tmp_path / "py.xml").read_bytes()
    assert text == (tmp_path / "cli.xml").read_bytes()
    assert b"<WindowElement" in text


def test_bad_options_raise_value_error(at_repo):
    with pytest.raises(ValueError, match="to: unknown target 'mitsuba'"):
        stfit.export(FITS, to="mitsuba")
    with pytest.raises(ValueError, match="model: unknown model 'gxx'"):
        stfit.export(FITS, to="pbrt-v4", model="gxx")
    with pytest.raises(ValueError, match="layer: unknown layer"):
        stfit.export(FITS, to="radiance", sample="ground", model="ggx", layer="slab")
    with pytest.raises(ValueError, match="apply to to='radiance' only"):
        stfit.export(FITS, to="pbrt-v4", walks=10)
    with pytest.raises(ValueError, match="absorption"):
        stfit.export(FITS, to="radiance", sample="ground", model="ggx", absorption=1.5)
    with pytest.raises(ValueError, match="absorption"):
        stfit.export(FITS, to="radiance", sample="ground", model="ggx", absorption=float("nan"))
    with pytest.raises(ValueError, match="one BSDF file per fit"):
        stfit.export(FITS, to="radiance")
    with pytest.raises(ValueError, match=r"walks: -1 is not an integer in \[1, 1000000000\]"):
        stfit.export(FITS, to="radiance", sample="ground", model="ggx", walks=-1)
    # A single-scattering interface is integrated by quadrature: its walks would be ignored.
    # Even at their default values, as on the command line.
    for option in [{"walks": 10}, {"seed": 3}, {"walks": 65_536}, {"seed": 1}]:
        with pytest.raises(ValueError, match="walks and seed apply to the pane"):
            stfit.export(FITS, to="radiance", sample="ground", model="ggx", layer="interface",
                         **option)
    for option in [{"layer": "pane"}, {"absorption": 0.0}, {"seed": 1}]:
        with pytest.raises(ValueError, match="apply to to='radiance' only"):
            stfit.export(FITS, to="mitsuba3", **option)


def test_bad_fits_raise(at_repo, tmp_path):
    with pytest.raises(ValueError, match="example-fits.json: no fit matches the selection"):
        stfit.export(FITS, to="pbrt-v4", sample="no such sample")
    with pytest.raises(OSError):
        stfit.export(tmp_path / "missing.json", to="pbrt-v4")
    broken = tmp_path / "broken.json"
    broken.write_text('{"version": 1, "fits": [{"sample": 3}]}')
    with pytest.raises(ValueError, match="broken.json"):
        stfit.export(broken, to="pbrt-v4")
    with pytest.raises(TypeError, match="fits: expected a FitResult"):
        stfit.export([1, 2], to="pbrt-v4")
    with pytest.raises(TypeError, match="fits: expected a FitResult"):
        stfit.export(3.5, to="pbrt-v4")
    with pytest.raises(OSError):
        stfit.export(FITS, to="pbrt-v4", model="ggx", sample="ground",
                     out=tmp_path / "no" / "such" / "folder.pbrt")


def test_a_refused_fit_does_not_stop_the_others(at_repo, tmp_path):
    """appleseed refuses eta 2.8: ExportError names that fit, the others are written."""
    import json

    doc = json.loads(pathlib.Path(FITS).read_text())
    doc["fits"] = [f for f in doc["fits"] if f["model"] == "ggx"]
    for f, (sample, eta) in zip(doc["fits"], [("a", 1.51), ("b", 2.8), ("c", 1.5)]):
        f["sample"], f["eta"] = sample, eta
    mixed = tmp_path / "mixed.json"
    mixed.write_text(json.dumps(doc))
    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(stfit.ExportError, match="1 of 3 exports refused") as e:
        stfit.export(mixed, to="appleseed", out=out)
    assert isinstance(e.value, ValueError)
    assert len(e.value.refused) == 1
    assert e.value.refused[0].startswith(f"{mixed}: sample 'b', ggx to appleseed: ")
    assert "eta 2.8" in e.value.refused[0]
    names = sorted(pathlib.Path(p).name for p in e.value.written)
    assert names == ["a_ggx-appleseed.xml", "c_ggx-appleseed.xml"]
    assert sorted(p.name for p in out.iterdir()) == names
    assert e.value.text is None
    with pytest.raises(stfit.ExportError) as e:
        stfit.export(mixed, to="appleseed")
    assert e.value.written == []
    assert 'name="a_ggx"' in e.value.text and 'name="c_ggx"' in e.value.text
    assert "b_ggx" not in e.value.text
