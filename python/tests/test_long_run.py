"""Long random-walk runs are announced before they start, as the command line's notes on
stderr announce them: a ``stfit.LongRunWarning`` (a ``UserWarning``) with the note's words.
Turned into an error, the warning stops each call before its walks start, so these runs of a
billion walks end at once."""

import json
import warnings

import numpy as np
import pytest

import stfit

UP = np.array([0.0, 0.0, 1.0])
DOWN = np.array([0.0, 0.0, -1.0])
BILLION = 10**9
GRID = {"alpha_grid": [0.2, 0.6], "mu_grid": "0.5:1:2", "eta_grid": "1.3,2"}


def _data():
    return stfit.synth("ggx", 0.3, theta_i=[30], theta_o=[170, 180, 190, 200])


def _all_orders_fit(walks):
    """An all-orders GGX fit of small data, with its `walks` as given (a stored fit's own)."""
    fit = stfit.fit(_data(), model="ggx", orders="all", walks=64)[0]
    record = json.loads(fit.to_json())
    record["walks"] = walks
    return stfit.FitResult.from_json(json.dumps(record))


def _walk():
    return stfit.Microsurface(stfit.Ggx(0.3), 1.5)


LONG = {
    "fit": lambda out: stfit.fit(_data(), model="ggx", orders="all", walks=BILLION),
    "report (fits)": lambda out: stfit.report(_data(), out=out, orders="all", walks=BILLION),
    "report (drawing)": lambda out: stfit.report(_data(), [_all_orders_fit(BILLION)], out=out),
    "synth": lambda out: stfit.synth("ggx", 0.3, orders="all", walks=BILLION, theta_i=[30],
                                     theta_o=[200]),
    "tables": lambda out: stfit.tables("ggx", **GRID, orders="all", walks=BILLION),
    "table_shard": lambda out: stfit.table_shard(
        stfit.table_spec("ggx", **GRID, orders="all", walks=BILLION)),
    "export": lambda out: stfit.export([_all_orders_fit(64)], to="radiance", walks=BILLION),
    "albedo": lambda out: _walk().albedo(UP, walks=BILLION),
    "eval": lambda out: _walk().eval(UP, DOWN, walks=BILLION),
}


def test_long_run_warning_is_a_user_warning():
    assert issubclass(stfit.LongRunWarning, UserWarning)
    assert "LongRunWarning" in stfit.__all__


@pytest.mark.parametrize("call", LONG.values(), ids=LONG.keys())
def test_long_runs_warn_before_their_walks_start(call, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error", stfit.LongRunWarning)
        with pytest.raises(stfit.LongRunWarning, match=r"will take about .*shorter"):
            call(tmp_path / "report")
    assert not (tmp_path / "report").exists()


def test_short_runs_do_not_warn(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error", stfit.LongRunWarning)
        fits = stfit.fit(_data(), model="ggx", orders="all", walks=64)
        stfit.report(_data(), fits, out=tmp_path / "report")
        stfit.synth("ggx", 0.3, orders="all", walks=64, theta_i=[30], theta_o=[200])
        _walk().albedo(UP, walks=100)
        _walk().eval(UP, DOWN, walks=100)
        stfit.tables("ggx", **GRID, orders="all", walks=300)


def test_the_warning_says_what_runs_and_how_long():
    """The command line's words, with the keyword's name (`walks`) for the flag's."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", stfit.LongRunWarning)
        with pytest.raises(stfit.LongRunWarning) as raised:
            stfit.synth("ggx", 0.3, orders="all", walks=BILLION, theta_i=[30], theta_o=[200])
    note = str(raised.value)
    assert note.startswith(
        "the random walks of the orders >= 2 term (1000000000 walks per incident direction) "
        "will take about "), note
    assert note.endswith("(fewer walks make it shorter)"), note
