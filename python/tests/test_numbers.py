"""Numbers read one way everywhere: a bool is never taken for a number (ints and NumPy numbers
are), and a masked array's mask is never dropped."""

import numpy as np
import pytest

import stfit

from conftest import EXAMPLE

UP = [0.0, 0.0, 1.0]


def _ground_ggx():
    return [f for f in stfit.read_fits(EXAMPLE.parent / "example-fits.json")
            if f.sample == "ground" and f.model == "ggx"][0]


def _same(a, b):
    """Whether two datasets have the same source, samples and points."""
    ca, cb = a.columns(), b.columns()
    return (a.source, a.samples) == (b.source, b.samples) and ca.keys() == cb.keys() and all(
        list(ca[k]) == list(cb[k]) for k in ca)


def _walk():
    return stfit.Microsurface(stfit.Ggx(0.3), 1.5)


# Every numeric argument of the package, given a bool `b`: (name in the message, the call).
BOOLS = {
    "StudentT.alpha": ("alpha", lambda b, out: stfit.StudentT(b, 3.0)),
    "StudentT.gamma": ("gamma", lambda b, out: stfit.StudentT(0.3, b)),
    "Ggx.alpha": ("alpha", lambda b, out: stfit.Ggx(b)),
    "Beckmann.alpha": ("alpha", lambda b, out: stfit.Beckmann(b)),
    "RoughDielectric.eta": ("eta", lambda b, out: stfit.RoughDielectric(stfit.Ggx(0.3), b)),
    "Microsurface.eta": ("eta", lambda b, out: stfit.Microsurface(stfit.Ggx(0.3), b)),
    "fit.gamma": ("gamma", lambda b, out: stfit.fit(str(EXAMPLE), gamma=b)),
    "fit.log_floor": ("log_floor",
                      lambda b, out: stfit.fit(str(EXAMPLE), loss="log", log_floor=b)),
    "report.log_floor": ("log_floor", lambda b, out: stfit.report(
        str(EXAMPLE), out=out, loss="log", log_floor=b)),
    "synth.alpha": ("alpha", lambda b, out: stfit.synth("ggx", b)),
    "synth.gamma": ("gamma", lambda b, out: stfit.synth("student-t", 0.3, b)),
    "synth.scale": ("scale", lambda b, out: stfit.synth("ggx", 0.3, scale=b)),
    "synth.noise": ("noise", lambda b, out: stfit.synth("ggx", 0.3, noise=b)),
    "synth.eta": ("eta", lambda b, out: stfit.synth("ggx", 0.3, eta=b)),
    "synth.theta_i": (r"theta_i\[1\]", lambda b, out: stfit.synth("ggx", 0.3, theta_i=[0, b])),
    "synth.phi_o": (r"phi_o\[0\]", lambda b, out: stfit.synth(
        "ggx", 0.3, grid="general", phi_o=(b, 20.0))),
    "tables.n": ("n", lambda b, out: stfit.tables("ggx", surface="conductor", n=b, k=1.0)),
    "tables.k": ("k", lambda b, out: stfit.tables("ggx", surface="conductor", n=1.5, k=b)),
    "tables.alpha_grid": (r"alpha_grid\[1\]", lambda b, out: stfit.table_spec(
        "ggx", alpha_grid=[0.3, b], mu_grid="1", eta_grid="1.5")),
    "table_spec.n": ("n", lambda b, out: stfit.table_spec("ggx", surface="conductor", n=b)),
    "export.absorption": ("absorption", lambda b, out: stfit.export(
        _ground_ggx(), to="radiance", absorption=b)),
    "predict.theta_i_deg": (r"theta_i_deg\[0\]",
                            lambda b, out: _ground_ggx().predict([b], [180.0])),
    "predict.theta_o_deg": (r"theta_o_deg\[1\]",
                            lambda b, out: _ground_ggx().predict([0.0, 0.0], [180.0, b])),
    "albedo.walks": ("walks", lambda b, out: _walk().albedo(UP, walks=b)),
    "albedo.seed": ("seed", lambda b, out: _walk().albedo(UP, walks=10, seed=b)),
    "table_shard.index": ("index", lambda b, out: stfit.table_shard("{}", b, 1)),
}


@pytest.mark.parametrize("value", [True, False, np.bool_(True), np.array(False)],
                         ids=["True", "False", "np.True_", "0-d bool array"])
@pytest.mark.parametrize("case", BOOLS.values(), ids=BOOLS.keys())
def test_every_number_argument_refuses_a_bool(case, value, tmp_path):
    """A bool (Python's or NumPy's) given for a number is a ValueError naming the argument,
    where it was taken as 1.0 or 0.0 (stfit.Ggx(True) had alpha 1)."""
    name, call = case
    with pytest.raises(ValueError, match=rf"^{name}: .*bool"):
        call(value, tmp_path / "report")


@pytest.mark.parametrize("w, index", [
    ([0, 0, True], r"\[2\]"),
    ([[0.0, 0.0, 1.0], [0, 0, np.True_]], r"\[1, 2\]"),
    ((np.array([0.0, 0.0, 1.0]), np.array([False, False, True])), r"\[1\]"),
])
def test_directions_refuse_bools_among_numbers(w, index):
    """A list of directions holding a bool, which NumPy makes 1 or 0 among numbers, is a
    ValueError naming the argument and the bool's index; a bool array already was."""
    with pytest.raises(ValueError, match=rf"^w: the element at index {index} is a bool"):
        stfit.Ggx(0.3).sigma(w)
    with pytest.raises(ValueError, match="^w: not an array of numbers"):
        stfit.Ggx(0.3).sigma(np.array([False, False, True]))


def test_ints_and_numpy_numbers_are_still_numbers():
    """Python ints and NumPy floats and integers are numbers as before."""
    assert stfit.Ggx(1).alpha == 1.0
    assert stfit.Ggx(np.float32(0.5)).alpha == 0.5
    assert stfit.StudentT(np.float64(0.3), np.int64(3)).gamma == 3.0
    assert stfit.RoughDielectric(stfit.Ggx(0.3), np.float64(1.5)).eta == 1.5
    a = stfit.synth("student-t", np.float64(0.3), np.int32(3), scale=np.float32(2),
                    noise=0, eta=np.float64(1.5), theta_i=np.array([0, 30]),
                    theta_o=[np.float64(180.0), 200])
    b = stfit.synth("student-t", 0.3, 3.0, scale=2.0, noise=0.0, eta=1.5, theta_i=[0.0, 30.0],
                    theta_o=[180.0, 200.0])
    assert _same(a, b)
    fit = _ground_ggx()
    assert fit.predict(np.array([0, 30]), (180, 200.0)) == fit.predict([0.0, 30.0],
                                                                        [180.0, 200.0])
    spec = stfit.table_spec("ggx", alpha_grid=np.array([0.3, 0.6]), mu_grid="1",
                            eta_grid=[np.float64(1.5)])
    assert spec == stfit.table_spec("ggx", alpha_grid=[0.3, 0.6], mu_grid="1", eta_grid="1.5")


MASKED = np.ma.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]], mask=[[0, 0, 0], [0, 1, 0]])


def test_masked_directions_are_refused_naming_the_first_masked_index():
    """A masked array of directions with a masked element is a ValueError naming the argument
    and the first masked index, where the values under the mask were used."""
    glass = stfit.RoughDielectric(stfit.Ggx(0.3), 1.5)
    with pytest.raises(ValueError, match=r"^wm: a masked array .*index \[1, 1\]"):
        stfit.Ggx(0.3).d(MASKED)
    with pytest.raises(ValueError, match=r"^wo: a masked array .*index \[1, 1\]"):
        glass.eval(UP, -MASKED)
    with pytest.raises(ValueError, match=r"^wi: a masked array .*index \[0\]"):
        _walk().albedo(np.ma.masked_all(3))


def test_masked_arrays_without_masked_elements_are_their_values():
    """A masked array whose mask hides nothing is taken as its data."""
    w = np.ma.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]], mask=False)
    assert np.array_equal(stfit.Ggx(0.3).d(w), stfit.Ggx(0.3).d(w.data))
    columns = {"theta_i_deg": np.ma.array([0.0, 30.0]), "theta_o_deg": [180.0, 200.0],
               "L": np.ma.array([1.0, 0.5], mask=[False, False])}
    assert _same(stfit.load(columns), stfit.load({k: np.asarray(v) for k, v in columns.items()}))


def test_masked_data_columns_are_refused_at_their_row():
    """A masked value in a data column is a LoadError at its row and column (line k + 2),
    where the value under the mask was loaded."""
    columns = {"theta_i_deg": [0.0, 30.0, 60.0], "theta_o_deg": [180.0, 200.0, 220.0],
               "L": np.ma.array([1.0, 0.5, 0.2], mask=[False, True, False])}
    with pytest.raises(stfit.LoadError, match=r"^<arrays>:3: column 'L': masked") as e:
        stfit.load(columns)
    assert (e.value.line, e.value.column) == (3, "L")
    names = {"sample": np.ma.array(["a", "b"], mask=[True, False]),
             "theta_i_deg": [0.0, 30.0], "theta_o_deg": [180.0, 200.0], "L": [1.0, 0.5]}
    with pytest.raises(stfit.LoadError, match="column 'sample': masked"):
        stfit.fit(names)


def test_masked_number_sequences_are_refused():
    """Angle lists and predict's angles refuse a masked element, naming the argument."""
    with pytest.raises(ValueError, match=r"^theta_i: a masked array .*index \[1\]"):
        stfit.synth("ggx", 0.3, theta_i=np.ma.array([0.0, 30.0], mask=[0, 1]))
    with pytest.raises(ValueError, match=r"^theta_o_deg: a masked array"):
        _ground_ggx().predict([0.0], np.ma.masked_all(1))
    with pytest.raises(ValueError, match=r"^alpha: a masked array"):
        stfit.Ggx(np.ma.masked)
