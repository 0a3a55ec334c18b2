"""Input the library cannot use is refused with a ValueError that names the argument and its
range, before any work: never an OverflowError, a hang, a silently wrong number or a
"standard error" that one walk cannot have."""

import numpy as np
import pytest

import stfit

from conftest import EXAMPLE

UP, DOWN = [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]


def _walk():
    return stfit.Microsurface(stfit.Ggx(0.3), 1.5)


def _ground_ggx():
    return [f for f in stfit.read_fits(EXAMPLE.parent / "example-fits.json")
            if f.sample == "ground" and f.model == "ggx"][0]


SEEDED = {
    "sample_visible": lambda seed, out: stfit.Ggx(0.3).sample_visible(UP, seed=seed),
    "sample": lambda seed, out: stfit.RoughDielectric(stfit.Ggx(0.3), 1.5).sample(UP, seed=seed),
    "albedo": lambda seed, out: _walk().albedo(UP, walks=10, seed=seed),
    "eval": lambda seed, out: _walk().eval(UP, DOWN, walks=10, seed=seed),
    "fit": lambda seed, out: stfit.fit(str(EXAMPLE), orders="all", seed=seed),
    "synth": lambda seed, out: stfit.synth("ggx", 0.3, seed=seed),
    "report": lambda seed, out: stfit.report(str(EXAMPLE), out=out, orders="all", seed=seed),
    "export": lambda seed, out: stfit.export(_ground_ggx(), to="radiance", seed=seed),
    "tables": lambda seed, out: stfit.tables("ggx", orders="all", seed=seed),
}

WALKED = {
    "albedo": lambda walks, out: _walk().albedo(UP, walks=walks),
    "eval": lambda walks, out: _walk().eval(UP, DOWN, walks=walks),
    "fit": lambda walks, out: stfit.fit(str(EXAMPLE), orders="all", walks=walks),
    "synth": lambda walks, out: stfit.synth("ggx", 0.3, orders="all", walks=walks),
    "report": lambda walks, out: stfit.report(str(EXAMPLE), out=out, orders="all",
                                             walks=walks),
    "export": lambda walks, out: stfit.export(_ground_ggx(), to="radiance", walks=walks),
    "tables": lambda walks, out: stfit.tables("ggx", orders="all", walks=walks),
}


@pytest.mark.parametrize("value", [-1, 2**64, 10**30, True])
@pytest.mark.parametrize("call", SEEDED.values(), ids=SEEDED.keys())
def test_seeds_outside_u64_raise_value_error_naming_seed(call, value, tmp_path):
    """A seed that is negative, 2^64 or more, or a bool is a ValueError naming `seed` and
    the range [0, 2^64), not an OverflowError (nor a bool taken for 1)."""
    with pytest.raises(ValueError, match=r"seed: .*\[0, 2\^64\)"):
        call(value, tmp_path / "report")


@pytest.mark.parametrize("value", [-1, 2**64, True])
@pytest.mark.parametrize("call", WALKED.values(), ids=WALKED.keys())
def test_walks_outside_u64_raise_value_error_naming_walks(call, value, tmp_path):
    """A number of walks that is negative, 2^64 or more, or a bool is a ValueError naming
    `walks` and the range of walks [1, 1e9], not an OverflowError."""
    with pytest.raises(ValueError, match=r"walks: .*\[1, 1000000000\]"):
        call(value, tmp_path / "report")


@pytest.mark.parametrize("index, count, name", [(-1, 2, "index"), (1, 2**64, "count"),
                                                (True, 1, "index")])
def test_shard_numbers_outside_u64_raise_value_error(index, count, name):
    """A shard's index or count that is negative, too large or a bool is a ValueError naming
    the argument, not an OverflowError."""
    with pytest.raises(ValueError, match=f"{name}: "):
        stfit.table_shard("{}", index, count)


def test_numpy_integers_are_accepted_as_walks_and_seed():
    """NumPy integers count like Python ints for walks and seed (the same estimate)."""
    np = pytest.importorskip("numpy")
    a = _walk().albedo(UP, walks=np.int64(64), seed=np.uint64(3))
    b = _walk().albedo(UP, walks=64, seed=3)
    assert (a.reflectance, a.transmittance, a.walks) == (b.reflectance, b.transmittance, 64)


@pytest.mark.parametrize("walks", [0, 10**9 + 1, 2**63])
@pytest.mark.parametrize("call", ["albedo", "eval", "export", "synth"])
def test_walks_outside_core_range_raise_value_error(call, walks, tmp_path):
    """Walks of one estimate outside core's [1, 1e9] (check_walks) raise a ValueError naming
    walks and the range before any walk runs (huge counts hung the interpreter); a Radiance
    export, whose file states standard errors, needs at least 2 per patch."""
    low = 2 if call == "export" else 1
    with pytest.raises(ValueError, match=rf"walks.*\[{low}, (1e9|1000000000)\]"):
        WALKED[call](walks, tmp_path / "report")


def test_radiance_export_refuses_one_walk_per_patch(tmp_path):
    """One walk per Klems patch cannot estimate the standard errors the file states."""
    with pytest.raises(ValueError, match=r"walks per patch must be in \[2, "):
        WALKED["export"](1, tmp_path / "report")


@pytest.mark.parametrize("walks, text", [(1, "at least 2 walks"), (10**9 + 1, r"\[2, 1e9\]")])
@pytest.mark.parametrize("call", ["fit", "report"])
def test_fit_walks_outside_the_fit_range_raise_value_error(call, walks, text, tmp_path):
    """An all-orders fit (stfit.fit, stfit.report fitting first) refuses walks outside the
    fit's [2, 1e9] (check_fit_walks) as `--walks` does, naming walks."""
    with pytest.raises(ValueError, match=f"^walks: .*{text}"):
        WALKED[call](walks, tmp_path / "report")


def test_one_walk_has_no_standard_error():
    """With 1 walk the standard errors are undefined, as on the command line: eval gives NaN
    (stfit eval an empty field), albedo None (stfit albedo --json null); 2 walks give numbers
    (for a side neither walk reached, its upper bound)."""
    import math

    m = _walk()
    mean, se = m.eval(UP, DOWN, walks=1)
    assert math.isfinite(mean) and math.isnan(se)
    means, ses = m.eval([UP, UP], [DOWN, DOWN], walks=1)
    assert all(math.isnan(s) for s in ses)
    a = m.albedo(UP, walks=1)
    assert a.reflectance_stderr is None and a.transmittance_stderr is None
    assert "+-" not in repr(a)
    a = m.albedo(UP, walks=2)
    # Each side has a standard error, or the upper bound if neither walk reached it.
    for se, bound in [(a.reflectance_stderr, a.reflectance_upper_bound),
                      (a.transmittance_stderr, a.transmittance_upper_bound)]:
        assert (se is None) != (bound is None)
    assert math.isfinite(m.eval(UP, DOWN, walks=2)[1])


def test_one_walk_agrees_with_the_cli(cli):
    """Python's eval and albedo with 1 walk give the command line's values and its missing
    standard errors (NaN for its empty field, None for its null)."""
    import json
    import math

    out = cli("eval", "--ndf", "ggx", "--alpha", "0.3", "--eta", "1.5", "--orders", "all",
              "--walks", "1", stdin="wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,-1\n")
    row = out.splitlines()[1].split(",")
    mean, se = _walk().eval(UP, DOWN, walks=1)
    assert row[-1] == "" and math.isnan(se) and float(row[-2]) == mean
    out = json.loads(cli("albedo", "--ndf", "ggx", "--alpha", "0.3", "--eta", "1.5",
                         "--theta-i", "0", "--walks", "1", "--json"))
    a = _walk().albedo(UP, walks=1)
    assert out["reflectance_stderr"] is None and a.reflectance_stderr is None
    assert (out["reflectance"], out["transmittance"]) == (a.reflectance, a.transmittance)


def test_unreached_side_has_an_upper_bound_not_a_zero_stderr(cli):
    """A side that no walk reached (orders >= 2 of a near-specular surface: every walk leaves
    after one event) has no standard error but the one-sided 95% bound 1 - 0.05^(1/walks),
    as `stfit albedo --json` gives it; a reached side has a standard error and no bound."""
    import json

    m = stfit.Microsurface(stfit.Ggx(1e-8), 1.5, orders="multiple")
    wi = [-0.5, 0.0, 3**0.5 / 2]
    a = m.albedo(wi, walks=1000)
    bound = 1 - 0.05 ** (1 / 1000)
    assert a.reflectance == 0.0 and a.transmittance == 0.0
    assert a.reflectance_stderr is None and a.transmittance_stderr is None
    assert a.reflectance_upper_bound == pytest.approx(bound, rel=1e-12)
    assert a.transmittance_upper_bound == pytest.approx(bound, rel=1e-12)
    assert "no walk; below" in repr(a) and "+-" not in repr(a)
    out = json.loads(cli("albedo", "--ndf", "ggx", "--alpha", "1e-8", "--eta", "1.5",
                         "--theta-i", "30", "--orders", "multiple", "--walks", "1000",
                         "--json"))
    assert out["reflectance_upper_bound"] == a.reflectance_upper_bound
    assert out["transmittance_stderr"] is None
    b = _walk().albedo(UP, walks=1000)
    assert b.reflectance_upper_bound is None and b.reflectance_stderr > 0


@pytest.mark.parametrize("theta_i, theta_o, text", [
    (95.0, 180.0, r"theta_i_deg\[1\] = 95 is out of range; must be in \[0, 90\)"),
    (90.0, 180.0, r"theta_i_deg\[1\] = 90 is out of range"),
    (-1.0, 180.0, r"theta_i_deg\[1\] = -1 "),
    (float("nan"), 180.0, r"theta_i_deg\[1\] = NaN "),
    (30.0, 50.0, r"theta_o_deg\[1\] = 50 is out of range; must be in \(90, 270\)"),
    (30.0, 270.0, r"theta_o_deg\[1\] = 270 "),
    (30.0, float("inf"), r"theta_o_deg\[1\] = inf "),
])
def test_predict_refuses_angles_outside_the_data_format(theta_i, theta_o, text):
    """FitResult.predict refuses in-plane angles outside data-format.md's ranges (theta_i in
    [0, 90), theta_o in (90, 270), NaN included) with a ValueError naming the argument, its
    index and the range, where it returned 0."""
    fit = _ground_ggx()
    with pytest.raises(ValueError, match=text):
        fit.predict([30.0, theta_i], [180.0, theta_o])


def test_predict_in_range_is_unchanged():
    """Angles inside the ranges, at their edges too, predict positive finite values."""
    import math

    values = _ground_ggx().predict([0.0, 30.0, 89.9], [180.0, 90.1, 269.9])
    assert all(math.isfinite(v) and v >= 0 for v in values) and values[0] > 0


@pytest.mark.parametrize("key, value, text", [
    ("n_points", 0, "n_points must be at least 1"),
    ("rmse_sqrt_l", -1.0, "rmse_sqrt_l must be finite and >= 0"),
    ("eta", 1.01, r"eta is out of range: 1.01 \(the glass of a fit has eta in \[1.05, 3\]\)"),
    ("log_floor", 5.0, r"log_floor must be in \[1e-12, 1\]"),
    ("alpha_stderr", -1.0, "alpha_stderr must be finite and > 0"),
    ("multiple_term", "exact", "multiple_term must be null for orders single"),
    ("warning", [], 'unknown key "warning"'),
])
def test_from_json_checks_the_record_as_a_fits_file_does(key, value, text, tmp_path):
    """FitResult.from_json refuses a record with a number outside its documented range or a
    key the format does not define, as read_fits refuses it in a file, where it accepted it
    (only the model was checked) and fits_json then wrote a file that read_fits refuses."""
    import json

    record = {**json.loads(_ground_ggx().to_json()), key: value}
    with pytest.raises(ValueError, match=text):
        stfit.FitResult.from_json(json.dumps(record))
    path = tmp_path / "fits.json"
    path.write_text(json.dumps({"version": 1, "fits": [record]}))
    with pytest.raises(ValueError, match=text):
        stfit.read_fits(path)
    assert stfit.FitResult.from_json(_ground_ggx().to_json()) == _ground_ggx()


ROWS = {"sample": ["a", "a", "a"], "theta_i_deg": [0.0, 0.0, 30.0],
        "theta_o_deg": [180.0, 170.0, 190.0], "L": [1.0, 0.5, 0.7]}


def _frame(**columns):
    pd = pytest.importorskip("pandas")
    return pd.DataFrame({**ROWS, **columns})


@pytest.mark.parametrize("missing", [None, float("nan"), "pd.NA", "pd.NaT"])
@pytest.mark.parametrize("container", ["list", "object array", "DataFrame"])
def test_missing_sample_names_are_refused_at_their_row(missing, container):
    """A missing sample name (None, NaN, pandas' NA or NaT) is a LoadError at its row (line 3
    for row 1) in the sample column, not a sample called 'None', 'nan' or '<NA>'."""
    import numpy as np
    pd = pytest.importorskip("pandas")
    value = {"pd.NA": pd.NA, "pd.NaT": pd.NaT}.get(missing, missing)
    names = ["a", value, "a"]
    if container == "list":
        source, label = {**ROWS, "sample": names}, "<arrays>"
    elif container == "object array":
        source, label = {**ROWS, "sample": np.array(names, dtype=object)}, "<arrays>"
    else:
        source, label = _frame(sample=pd.Series(names, dtype=object)), "<DataFrame>"
    with pytest.raises(stfit.LoadError, match="sample name") as e:
        stfit.load(source)
    assert (e.value.file, e.value.line, e.value.column) == (label, 3, "sample")


def test_pandas_string_column_with_na_is_refused():
    """pandas' string dtype with a missing name is refused at its row, not read as '<NA>'."""
    pd = pytest.importorskip("pandas")
    frame = _frame(sample=pd.array(["a", None, "a"], dtype="string"))
    with pytest.raises(stfit.LoadError) as e:
        stfit.load(frame)
    assert (e.value.line, e.value.column) == (3, "sample")


@pytest.mark.parametrize("column, values, shape", [
    ("L", [[1.0], [0.5], [0.7]], r"\[3, 1\]"),
    ("theta_i_deg", [[0.0, 0.0, 30.0]], r"\[1, 3\]"),
    ("weight", 1.0, r"\[\]"),
    ("sample", [["a"], ["a"], ["a"]], r"\[3, 1\]"),
    ("note", [["x"], ["y"], ["z"]], r"\[3, 1\]"),
])
def test_columns_that_are_not_1d_are_refused(column, values, shape):
    """A column of another shape than one value per row (2-D, a scalar) is a LoadError naming
    the column and its shape, where it was flattened (or broadcast by the loader)."""
    with pytest.raises(stfit.LoadError, match=f"1-D column.*{shape}") as e:
        stfit.load({**ROWS, column: values})
    assert (e.value.file, e.value.line, e.value.column) == ("<arrays>", None, column)


@pytest.mark.parametrize("values, dtype", [
    ("bool", "bool"),
    ("complex", "complex128"),
    ("text", "<U3"),
    ("bytes", r"\|S3"),
    ("datetime", "datetime64"),
])
def test_numeric_columns_of_other_dtypes_are_refused(values, dtype):
    """A number column (angles, L, weight) must have an integer or float dtype: booleans,
    complex numbers (truncated with a ComplexWarning), text ('1.0' parsed as a number) and
    dates are a LoadError naming the column and its dtype."""
    import numpy as np
    arrays = {
        "bool": np.array([True, True, False]),
        "complex": np.array([1 + 1j, 0.5, 0.7]),
        "text": np.array(["1.0", "0.5", "0.7"]),
        "bytes": np.array([b"1.0", b"0.5", b"0.7"]),
        "datetime": np.array(["2020-01-01"] * 3, dtype="datetime64[D]"),
    }
    column = "weight" if values == "bool" else "L"
    with pytest.raises(stfit.LoadError, match=fr"integer or float dtype\), got dtype {dtype}") as e:
        stfit.load({**ROWS, column: arrays[values]})
    assert (e.value.line, e.value.column) == (None, column)


@pytest.mark.parametrize("bad, kind", [
    (True, "bool"), ("0.5", "str"), (0.5 + 0j, "complex"), (b"0.5", "bytes"),
])
def test_non_numbers_in_object_arrays_are_refused_at_their_row(bad, kind):
    """A bool, text or complex element among numbers in an object array is a LoadError at
    its row, where NumPy converted it to a float ('0.5' parsed, True taken for 1)."""
    import numpy as np
    with pytest.raises(stfit.LoadError, match=f"is a {kind}, not a number") as e:
        stfit.load({**ROWS, "L": np.array([1.0, bad, 0.7], dtype=object)})
    assert (e.value.line, e.value.column) == (3, "L")


def test_bools_among_numbers_in_a_list_are_refused_at_their_row():
    """A list mixing a bool with floats, which NumPy makes a float array, is a LoadError at
    the bool's row; text or complex numbers in a list give a text or complex dtype, refused."""
    with pytest.raises(stfit.LoadError, match="True is a bool, not a number") as e:
        stfit.load({**ROWS, "L": [1.0, True, 0.7]})
    assert (e.value.line, e.value.column) == (3, "L")
    for values, dtype in [([1.0, "0.5", 0.7], "<U32"), ([1.0, 0.5j, 0.7], "complex128")]:
        with pytest.raises(stfit.LoadError, match=f"got dtype {dtype}"):
            stfit.load({**ROWS, "L": values})


@pytest.mark.parametrize("key", [5, 1.5, ("L", "x"), b"L"])
@pytest.mark.parametrize("container", ["dict", "DataFrame"])
def test_column_names_that_are_not_strings_are_refused(key, container):
    """A column name that is not a string is a LoadError saying so (a DataFrame's gave a
    KeyError, a dict's a TypeError): a file's header is text."""
    source = {**ROWS, key: [1, 2, 3]}
    if container == "DataFrame":
        source = _frame()
        source[key] = [1, 2, 3]
    with pytest.raises(stfit.LoadError, match="column names must be strings") as e:
        stfit.load(source)
    assert e.value.column is None


def test_repeated_dataframe_column_is_refused_as_in_a_file():
    """A DataFrame with a column name twice reaches the loader, which refuses the repeated
    header name, where the two columns were flattened into one of twice the rows."""
    pd = pytest.importorskip("pandas")
    frame = pd.concat([_frame(), pd.DataFrame({"L": [1.0, 1.0, 1.0]})], axis=1)
    with pytest.raises(stfit.LoadError, match="appears twice") as e:
        stfit.load(frame)
    assert (e.value.line, e.value.column) == (1, "L")


def test_accepted_columns_still_load():
    """Lists, tuples, integer and float32 arrays, object arrays of numbers, pandas' nullable
    Int64 and Float64, integer sample names and extra text columns load as before."""
    import numpy as np
    pd = pytest.importorskip("pandas")
    sources = [
        ROWS,
        {**ROWS, "L": (1.0, 0.5, 0.7)},
        {**ROWS, "theta_i_deg": np.array([0, 0, 30]), "L": np.array([1, 0.5, 0.7], np.float32)},
        {**ROWS, "L": np.array([1.0, 0.5, 0.7], dtype=object)},
        {**ROWS, "note": ["x", "y", "z"]},
        _frame(theta_i_deg=pd.array([0, 0, 30], dtype="Int64"),
               L=pd.array([1.0, 0.5, 0.7], dtype="Float64")),
        _frame(sample=pd.array(["a", "a", "a"], dtype="string")),
    ]
    for source in sources:
        d = stfit.load(source)
        assert d.samples == ["a"] and d.n_points == 3
        assert np.allclose(d.columns()["L"], [1.0, 0.5, 0.7])
    assert stfit.load({**ROWS, "sample": [1, 2, 1]}).samples == ["1", "2"]


@pytest.mark.parametrize("ndf", [stfit.Ggx(0.3), stfit.Beckmann(1e-3), stfit.StudentT(0.3, 3.0)])
def test_sample_visible_refuses_directions_that_see_no_normal(ndf):
    """sample_visible raises ValueError naming the row where sigma(w) = 0 (straight below;
    Beckmann far below the horizon), instead of returning a normal that is not visible."""
    w = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
    with pytest.raises(ValueError, match=r"w\[1\].*sigma"):
        ndf.sample_visible(w, seed=1)


def test_normals_seen_from_below_at_tiny_alpha_are_visible():
    """GGX at alpha 1e-8 seen from 120 to 179 degrees: every normal drawn is visible."""
    th = np.radians(np.repeat([120.0, 150.0, 179.0], 1000))
    w = np.stack([np.sin(th), np.zeros_like(th), np.cos(th)], axis=-1)
    wm = stfit.Ggx(1e-8).sample_visible(w, seed=3)
    assert np.all(np.einsum("ij,ij->i", w, wm) > 0) and np.all(wm[:, 2] > 0)


@pytest.mark.parametrize(
    "option", [{"walks": 0}, {"walks": 100}, {"seed": 2}, {"orders": "all"}, {"eta": 1.5}]
)
def test_report_refuses_fit_options_with_stored_fits(option, tmp_path):
    """report(data, fits, ...) refuses fit options (even valid ones) instead of ignoring them,
    as `stfit report --fits` does: the stored fits carry their own."""
    data = stfit.load(EXAMPLE)
    fits = stfit.fit(data, model="ggx")
    name = next(iter(option))
    with pytest.raises(ValueError, match=f"^{name}: does not apply with fits"):
        stfit.report(data, fits, out=tmp_path / "r", **option)
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize("w, dtype", [
    (np.array([0.0, 0.0, 1.0 + 0.5j]), "complex128"),
    ([False, False, True], "bool"),
    (["0", "0", "1"], "<U1"),
    (np.array([0.0, 0.0, 1.0], dtype=object), "object"),
])
@pytest.mark.parametrize("call", [
    lambda w: stfit.Ggx(0.3).d(w),
    lambda w: stfit.Ggx(0.3).sample_visible(w),
    lambda w: stfit.RoughDielectric(stfit.Ggx(0.3), 1.5).eval(UP, w),
    lambda w: stfit.RoughDielectric(stfit.Ggx(0.3), 1.5).sample(w),
    lambda w: _walk().albedo(w, walks=10),
], ids=["d", "sample_visible", "eval", "sample", "albedo"])
def test_directions_of_other_dtypes_are_refused(call, w, dtype):
    """Directions must have an integer or float dtype, as load's number columns: complex
    numbers (whose imaginary part was dropped with only a ComplexWarning), booleans and text
    (parsed as numbers) raise a ValueError naming the dtype, where they were converted."""
    with pytest.raises(ValueError, match=rf": not an array of numbers \(an integer or float "
                                         rf"dtype\), got dtype {dtype}"):
        call(w)


def test_integer_and_float32_directions_are_accepted():
    """Integer and float32 arrays, lists and non-contiguous views are directions as before."""
    ndf = stfit.Ggx(0.3)
    up = ndf.d([0.0, 0.0, 1.0])
    for w in ([0, 0, 1], np.array([0, 0, 1], dtype=np.uint8), np.array(UP, dtype=np.float32),
              np.eye(3)[:, ::-1][0]):
        assert ndf.d(w) == up


def test_report_refuses_an_empty_list_of_fits(tmp_path):
    """report(data, []) raises a ValueError naming fits and writes nothing, as
    `stfit report --fits` refuses a fits file with no fit, where it drew a report without
    models."""
    with pytest.raises(ValueError, match="^fits: holds no fit"):
        stfit.report(str(EXAMPLE), [], out=tmp_path / "r")
    assert not (tmp_path / "r").exists()


def test_huge_and_tiny_numbers_in_messages_are_short():
    """A direction or an angle of 1e300 or 5e-324 is named in scientific notation in the
    message, where its hundreds of digits were written out."""
    with pytest.raises(ValueError) as e:
        stfit.Ggx(0.3).sigma([1e300, 5e-324, 0.0])
    assert "w[0] = [1e300, 5e-324, 0]: not a unit vector (norm 1e300)" in str(e.value)
    assert len(str(e.value)) < 200
    with pytest.raises(ValueError, match=r"^theta_i_deg\[0\] = 1e300 is out of range") as e:
        _ground_ggx().predict([1e300], [180.0])
    assert len(str(e.value)) < 200


@pytest.mark.parametrize("wi, wo, name", [
    ([1.0, 0.0, 1e-320], [0.0, 0.0, 1.0], "wi"),
    ([0.0, 0.0, 1.0], [1.0, 0.0, -5e-324], "wo"),
])
def test_a_subnormal_z_is_refused_not_evaluated_to_nan(wi, wo, name):
    """A unit direction whose z is subnormal (nonzero, below 2.2e-308) is refused, naming the
    argument, as `stfit eval` refuses it: the BSDF divides by |z|, and had returned NaN."""
    for call in (lambda: stfit.RoughDielectric(stfit.Ggx(0.3), 1.5).eval(wi, wo),
                 lambda: stfit.Microsurface(stfit.Ggx(0.3), 1.5).eval(wi, wo, walks=16)):
        with pytest.raises(ValueError, match=rf"^{name}\[0\] = .*: z = .* is below the normal"):
            call()
    with pytest.raises(ValueError, match="above 1.8e308"):
        stfit.Ggx(0.3).sigma([1.5e308, 1.5e308, 0.0])


def test_a_direction_just_off_unit_length_is_named_as_such():
    """The plain norm decides and the message states it: a direction whose norm is 1 - 1.0e-6
    less an ulp had been called subnormal in z."""
    w = [0.30374447326405685, 0.42483036101897353, 0.8527933274358023]
    with pytest.raises(ValueError, match=r"^wm\[0\] = .*: not a unit vector \(norm 0\.99999"):
        stfit.Ggx(0.3).d(w)


def test_a_microsurface_refuses_a_shape_its_walks_cannot_take():
    """A Student-T shape below 1.501 is refused when the Microsurface is made, naming gamma, as
    `stfit albedo` refuses it; it had been accepted and refused only at the first estimate."""
    with pytest.raises(ValueError, match=r"^gamma: .*random walks need gamma >= 1\.501"):
        stfit.Microsurface(stfit.StudentT(0.3, 1.5000001), 1.5)
    stfit.Microsurface(stfit.StudentT(0.3, 1.501), 1.5)


@pytest.mark.parametrize("wi", [[1.0, 0.0, 0.0], [0.6, -0.8, -0.0]])
def test_albedo_refuses_a_direction_on_the_horizon(wi):
    """No flux arrives from a direction on the horizon, so its albedo is undefined: a
    ValueError naming wi, as `stfit albedo` refuses --theta-i 90, where it returned
    reflectance 0 +- 0 and transmittance 0 +- 0 (all of the flux lost)."""
    with pytest.raises(ValueError, match=r"^wi = \[.*\]: on the horizon \(z = 0\)"):
        _walk().albedo(wi, walks=10)
    a = _walk().albedo([0.6, 0.0, 0.8], walks=100)
    assert a.reflectance + a.transmittance > 0.99


@pytest.mark.parametrize("name", ["eta", "scale"])
@pytest.mark.parametrize("value", [True, False, np.bool_(True)])
def test_fit_parameters_refuse_booleans(name, value):
    """eta and scale take a number or 'free': a bool is a ValueError naming the parameter,
    where scale=True (meant as 'fit the scale') held the scale at 1."""
    with pytest.raises(ValueError, match=rf"^{name}: expected a number or 'free', got a bool"):
        stfit.fit(str(EXAMPLE), model="ggx", sample="ground", **{name: value})


def test_a_0d_array_is_named_with_its_own_shape():
    """A 0-d array is refused with shape [] in the message, where the conversion to a
    contiguous array had made it 1-d and the message said [1]."""
    with pytest.raises(ValueError,
                       match=r"^w: expected directions of shape \(\.\.\., 3\), got shape \[\]$"):
        stfit.Ggx(0.3).sigma(np.array(1.0))
