"""Input the library cannot use is refused with a ValueError that names the argument and its
range, before any work: never an OverflowError, a hang, a silently wrong number or a
"standard error" that one walk cannot have."""

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
    "sample_visible": lambda seed: stfit.Ggx(0.3).sample_visible(UP, seed=seed),
    "sample": lambda seed: stfit.RoughDielectric(stfit.Ggx(0.3), 1.5).sample(UP, seed=seed),
    "albedo": lambda seed: _walk().albedo(UP, walks=10, seed=seed),
    "eval": lambda seed: _walk().eval(UP, DOWN, walks=10, seed=seed),
    "fit": lambda seed: stfit.fit(str(EXAMPLE), orders="all", seed=seed),
    "synth": lambda seed: stfit.synth("ggx", 0.3, seed=seed),
    "report": lambda seed: stfit.report(str(EXAMPLE), out="/nonexistent/x", seed=seed),
    "export": lambda seed: stfit.export(_ground_ggx(), to="radiance", seed=seed),
    "tables": lambda seed: stfit.tables("ggx", orders="all", seed=seed),
}

WALKED = {
    "albedo": lambda walks: _walk().albedo(UP, walks=walks),
    "eval": lambda walks: _walk().eval(UP, DOWN, walks=walks),
    "fit": lambda walks: stfit.fit(str(EXAMPLE), orders="all", walks=walks),
    "synth": lambda walks: stfit.synth("ggx", 0.3, orders="all", walks=walks),
    "report": lambda walks: stfit.report(str(EXAMPLE), out="/nonexistent/x", walks=walks),
    "export": lambda walks: stfit.export(_ground_ggx(), to="radiance", walks=walks),
    "tables": lambda walks: stfit.tables("ggx", orders="all", walks=walks),
}


@pytest.mark.parametrize("value", [-1, 2**64, 10**30, True])
@pytest.mark.parametrize("call", SEEDED.values(), ids=SEEDED.keys())
def test_seeds_outside_u64_raise_value_error_naming_seed(call, value):
    """A seed that is negative, 2^64 or more, or a bool is a ValueError naming `seed` and
    the range [0, 2^64), not an OverflowError (nor a bool taken for 1)."""
    with pytest.raises(ValueError, match=r"seed: .*\[0, 2\^64\)"):
        call(value)


@pytest.mark.parametrize("value", [-1, 2**64, True])
@pytest.mark.parametrize("call", WALKED.values(), ids=WALKED.keys())
def test_walks_outside_u64_raise_value_error_naming_walks(call, value):
    """A number of walks that is negative, 2^64 or more, or a bool is a ValueError naming
    `walks` and the range of walks [1, 1e9], not an OverflowError."""
    with pytest.raises(ValueError, match=r"walks: .*\[1, 1000000000\]"):
        call(value)


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
