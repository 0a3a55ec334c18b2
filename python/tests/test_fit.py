"""Fits from Python are the command line's fits: the same records, number for number."""

import json
import math
import pickle

import numpy as np
import pandas as pd
import pytest

import stfit

from conftest import EXAMPLE

FLOAT_KEYS_TOL = 1e-12


def assert_same_record(mine: dict, theirs: dict):
    assert mine.keys() == theirs.keys()
    for key, want in theirs.items():
        got = mine[key]
        if isinstance(want, float) and isinstance(got, float):
            assert math.isclose(got, want, rel_tol=FLOAT_KEYS_TOL, abs_tol=0.0), (key, got, want)
        else:
            assert got == want, (key, got, want)


def test_fits_of_the_example_equal_the_cli_json(at_repo, cli):
    """Every record of `stfit fits/example.csv --model all --json`, every key, to 1e-12."""
    theirs = json.loads(cli("fits/example.csv", "--model", "all", "--json"))["fits"]
    fits = stfit.fit("fits/example.csv", model="all")
    assert len(fits) == len(theirs) == 12
    for fit, want in zip(fits, theirs):
        assert_same_record(fit.to_dict(), want)
        # Every key of the JSON is an attribute of the same value.
        for key, value in want.items():
            got = getattr(fit, key)
            if isinstance(value, float):
                assert math.isclose(got, value, rel_tol=FLOAT_KEYS_TOL), key
            else:
                assert got == value, key
    assert json.loads(stfit.fits_json(fits))["fits"] == [f.to_dict() for f in fits]


def test_options_reach_the_library_as_on_the_command_line(at_repo, cli):
    """Free eta, a held scale, the log loss and L-BFGS give the CLI's records."""
    args = ["--model", "ggx", "--sample", "etched", "--eta", "free", "--scale", "1",
            "--loss", "log", "--optimizer", "lbfgs", "--masking", "correlated"]
    theirs = json.loads(cli("fits/example.csv", *args, "--json"))["fits"]
    fits = stfit.fit("fits/example.csv", model="ggx", sample="etched", eta="free", scale=1.0,
                     loss="log", optimizer="lbfgs", masking="correlated")
    assert len(fits) == len(theirs) == 1
    assert_same_record(fits[0].to_dict(), theirs[0])


@pytest.mark.parametrize("call, name", [
    (lambda out: stfit.fit(str(EXAMPLE), model="ggx", walks=2000), "walks"),
    (lambda out: stfit.fit(str(EXAMPLE), model="ggx", seed=3), "seed"),
    (lambda out: stfit.fit(str(EXAMPLE), model="ggx", multiple_term="exact"), "multiple_term"),
    (lambda out: stfit.fit(str(EXAMPLE), model="ggx", log_floor=0.01), "log_floor"),
    (lambda out: stfit.fit(str(EXAMPLE), model="ggx", loss="linear", log_floor=0.01),
     "log_floor"),
    (lambda out: stfit.report(str(EXAMPLE), out=out, walks=2000), "walks"),
    (lambda out: stfit.fit(str(EXAMPLE), loss="Log", log_floor=0.01), "loss"),
    (lambda out: stfit.synth("ggx", 0.3, walks=2000), "walks"),
])
def test_options_that_do_not_apply_are_refused(call, name, tmp_path):
    """As on the command line, walk options with single scattering and a log floor with
    another loss raise ValueError naming the option rather than being ignored; a loss that is
    not one is named as such before its floor is looked at."""
    with pytest.raises(ValueError, match=f"^{name}: (applies to |unknown loss)"):
        call(tmp_path / "report")
    assert not (tmp_path / "report").exists()


def test_options_that_apply_are_taken():
    """The same options where they apply: walks and seed with orders 'all', the floor with the
    log loss (the floor changes the fit; omitted, it is the command line's 1e-3)."""
    stfit.synth("ggx", 0.3, orders="all", walks=64, theta_i=[30], theta_o=[200])
    default = stfit.fit(str(EXAMPLE), model="ggx", sample="etched", loss="log")[0]
    same = stfit.fit(str(EXAMPLE), model="ggx", sample="etched", loss="log", log_floor=1e-3)[0]
    other = stfit.fit(str(EXAMPLE), model="ggx", sample="etched", loss="log", log_floor=0.1)[0]
    assert default.to_dict() == same.to_dict()
    assert other.log_floor == 0.1 and other.alpha != default.alpha


def test_table_is_the_cli_table(at_repo, cli):
    fits = stfit.fit("fits/example.csv", model="all")
    assert stfit.table(fits) == cli("fits/example.csv", "--model", "all")


def test_dataframe_and_arrays_fit_as_the_file():
    """A DataFrame or a dict of arrays with the file's column names is the file's data."""
    from_file = stfit.load(str(EXAMPLE))
    frame = pd.read_csv(EXAMPLE, comment="#")
    from_frame = stfit.load(frame)
    from_dict = stfit.load({c: frame[c].to_numpy() for c in frame.columns})
    assert from_frame.source == "<DataFrame>" and from_dict.source == "<arrays>"
    assert from_frame.samples == from_file.samples == ["frosted", "etched", "ground"]
    for d in (from_frame, from_dict):
        assert d.n_points == from_file.n_points
        cols, want = d.columns(), from_file.columns()
        assert cols.keys() == want.keys()
        for k in want:
            assert np.array_equal(np.asarray(cols[k]), np.asarray(want[k])), k
    a = stfit.fit(from_file, model="student-t")
    b = stfit.fit(frame, model="student-t")
    for x, y in zip(a, b):
        dx, dy = x.to_dict(), y.to_dict()
        assert dy.pop("data") == "<DataFrame>"
        dx.pop("data")
        assert dx == dy


def test_columns_round_trip_through_pandas():
    d = stfit.load(str(EXAMPLE), sample="ground")
    again = stfit.load(pd.DataFrame(d.columns()))
    assert again.samples == ["ground"] and again.n_points == d.n_points == 300


def test_results_pickle_and_read_back_from_a_fits_file(tmp_path):
    fits = stfit.fit(str(EXAMPLE), model="all")
    assert pickle.loads(pickle.dumps(fits)) == fits
    path = tmp_path / "fits.json"
    path.write_text(stfit.fits_json(fits))
    assert stfit.read_fits(path) == fits


def test_synth_then_fit_recovers_the_truth(tmp_path):
    out = tmp_path / "synth.csv"
    data = stfit.synth("student-t", 0.3, 2.5, noise=0.0, sample="s", out=out)
    assert data.samples == ["s"] and data.n_points == 300
    reread = stfit.load(out)
    for k, v in data.columns().items():
        assert np.array_equal(np.asarray(reread.columns()[k]), np.asarray(v)), k
    (fit,) = stfit.fit(data, model="student-t")
    assert fit.alpha == pytest.approx(0.3, rel=1e-4)
    assert fit.gamma == pytest.approx(2.5, rel=1e-3)
    # The fitted model predicts the data it was fitted to.
    cols = data.columns()
    predicted = fit.predict(cols["theta_i_deg"], cols["theta_o_deg"])
    np.testing.assert_allclose(predicted, cols["L"], rtol=1e-3, atol=1e-6)


def test_synth_general_grid_matches_cli(cli, tmp_path):
    ours = stfit.synth("ggx", 0.25, grid="general", eta=1.45, theta_i="0,60,150",
                       phi_o="0:340:40", noise=0.01, seed=3).columns()
    text = cli("synth", "--model", "ggx", "--alpha", "0.25", "--grid", "general", "--eta",
               "1.45", "--theta-i", "0,60,150", "--phi-o", "0:340:40", "--noise", "0.01",
               "--seed", "3")
    path = tmp_path / "cli.csv"
    path.write_text(text)
    theirs = stfit.load(path).columns()
    for k in ("theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg", "bsdf"):
        assert np.array_equal(ours[k], theirs[k]), k


def test_report_writes_the_figures_and_table(tmp_path):
    data = stfit.load(str(EXAMPLE), sample="frosted")
    paths = stfit.report(data, out=tmp_path / "r")
    names = {p.name for p in map(__import__("pathlib").Path, paths)}
    assert {"frosted-fits.png", "frosted-fits.svg", "fits.md", "overview.png"} <= names
    assert (tmp_path / "r" / "frosted-fits.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fits = stfit.fit(data, model="all")
    again = stfit.report(data, fits, out=tmp_path / "s")
    assert (tmp_path / "s" / "fits.md").read_text() == (tmp_path / "r" / "fits.md").read_text()
    assert len(again) == len(paths)
