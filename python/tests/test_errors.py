"""Bad input raises Python exceptions with what is wrong and where; the interpreter survives."""

import math

import numpy as np
import pandas as pd
import pytest

import stfit

from conftest import EXAMPLE


@pytest.mark.parametrize(
    "make, text",
    [
        (lambda: stfit.StudentT(0.3, 1.5), "gamma"),
        (lambda: stfit.StudentT(0.3, math.nan), "gamma"),
        (lambda: stfit.Ggx(0.0), "alpha"),
        (lambda: stfit.Beckmann(-1.0), "alpha"),
        (lambda: stfit.Ggx(math.inf), "alpha"),
        (lambda: stfit.RoughDielectric(stfit.Ggx(0.3), 1.0), "eta"),
        (lambda: stfit.RoughDielectric(stfit.Ggx(0.3), 1.5, masking="smith"), "masking"),
        (lambda: stfit.Microsurface(stfit.Ggx(0.3), -2.0), "eta"),
        (lambda: stfit.Microsurface(stfit.Ggx(0.3), 1.5, orders="some"), "orders"),
        (lambda: stfit.Microsurface(stfit.Ggx(0.3), 1.5).albedo([0, 0, 1.0], walks=0), "walks"),
        (lambda: stfit.fit(str(EXAMPLE), model="phong"), "model"),
        (lambda: stfit.fit(str(EXAMPLE), model="ggx", gamma=3.0), "gamma"),
        (lambda: stfit.fit(str(EXAMPLE), eta=1.0), "eta"),
        (lambda: stfit.fit(str(EXAMPLE), eta="fixed"), "eta"),
        (lambda: stfit.fit(str(EXAMPLE), orders="multiple"), "multiple"),
        (lambda: stfit.fit(str(EXAMPLE), orders="all", masking="separable"), "masking"),
        (lambda: stfit.fit(str(EXAMPLE), loss="l1"), "loss"),
        (lambda: stfit.synth("ggx", 0.3, noise=-1.0), "noise"),
        (lambda: stfit.synth("ggx", 0.3, theta_i=[95.0]), "theta_i"),
        (lambda: stfit.synth("student-t", 0.3), "gamma"),
        (lambda: stfit.report(str(EXAMPLE), out="/tmp/x", y_axis="log"), "y_axis"),
    ],
)
def test_bad_parameters_raise_value_error(make, text):
    with pytest.raises(ValueError, match=text):
        make()


@pytest.mark.parametrize(
    "w, text",
    [
        ([0.0, 0.0, 2.0], "unit vector"),
        ([[0.0, 0.0, 1.0], [math.nan, 0.0, 1.0]],
         r"^w\[1\] = \[NaN, 0, 1\]: a coordinate is not a finite number$"),
        (np.zeros((4, 2)), "shape"),
        ("up", "array"),
    ],
)
def test_bad_directions_raise_value_error(w, text):
    with pytest.raises(ValueError, match=text):
        stfit.Ggx(0.3).sigma(w)


def test_mismatched_batches_raise_value_error():
    glass = stfit.RoughDielectric(stfit.Ggx(0.3), 1.5)
    with pytest.raises(ValueError, match="same shape"):
        glass.eval(np.tile([0, 0, 1.0], (3, 1)), np.tile([0, 0, -1.0], (4, 1)))


def test_wrong_types_raise_type_error():
    with pytest.raises(TypeError, match="ndf"):
        stfit.RoughDielectric("ggx", 1.5)
    with pytest.raises(TypeError):
        stfit.load(42)


def test_bad_file_raises_load_error_with_file_line_and_column(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("sample,theta_i_deg,theta_o_deg,L\na,0,180,1\na,30,85,1\n")
    with pytest.raises(stfit.LoadError) as e:
        stfit.load(path)
    assert (e.value.file, e.value.line, e.value.column) == (str(path), 3, "theta_o_deg")
    assert "out of range" in e.value.message
    assert isinstance(e.value, ValueError)
    with pytest.raises(stfit.LoadError) as e:
        stfit.load(tmp_path / "missing.csv")
    assert e.value.line is None and e.value.column is None
    with pytest.raises(stfit.LoadError) as e:
        stfit.load(str(EXAMPLE), sample="opal")
    assert e.value.column == "sample" and "opal" in str(e.value)


def test_bad_dataframe_raises_load_error_at_its_row():
    frame = pd.read_csv(EXAMPLE, comment="#")
    frame.loc[7, "L"] = np.nan
    with pytest.raises(stfit.LoadError) as e:
        stfit.load(frame)
    assert (e.value.file, e.value.line, e.value.column) == ("<DataFrame>", 9, "L")
    frame = pd.read_csv(EXAMPLE, comment="#").drop(columns="L")
    with pytest.raises(stfit.LoadError, match="L or sqrt_L"):
        stfit.load(frame)


def test_unfittable_sample_raises_fit_error():
    data = stfit.load({"theta_i_deg": [0.0, 30.0], "theta_o_deg": [180.0, 170.0], "L": [1.0, 0.5]})
    with pytest.raises(stfit.FitError) as e:
        stfit.fit(data, model="student-t")
    assert e.value.sample == "" and "points" in e.value.message
