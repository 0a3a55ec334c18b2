"""Objects as values: reprs write numbers as repr(float) does, and the parameter objects
compare, hash and pickle by value."""

import json
import pickle

import pytest

import stfit

from conftest import EXAMPLE

UP = [0.0, 0.0, 1.0]


def _ground_ggx():
    return [f for f in stfit.read_fits(EXAMPLE.parent / "example-fits.json")
            if f.sample == "ground" and f.model == "ggx"][0]


@pytest.mark.parametrize("obj, text", [
    (stfit.Ggx(1e-8), "stfit.Ggx(alpha=1e-08)"),
    (stfit.Beckmann(1), "stfit.Beckmann(alpha=1.0)"),
    (stfit.StudentT(0.3, 1e15), "stfit.StudentT(alpha=0.3, gamma=1000000000000000.0)"),
    (stfit.StudentT(0.1 + 0.2, 3), "stfit.StudentT(alpha=0.30000000000000004, gamma=3.0)"),
    (stfit.RoughDielectric(stfit.Ggx(0.3), 1 / 3),
     "stfit.RoughDielectric(stfit.Ggx(alpha=0.3), eta=0.3333333333333333, masking='separable')"),
    (stfit.Microsurface(stfit.Ggx(0.3), 2),
     "stfit.Microsurface(stfit.Ggx(alpha=0.3), eta=2.0, orders='all')"),
])
def test_reprs_write_numbers_as_repr_float(obj, text):
    """Numbers in reprs are Python's shortest round-trip text (1e-08, not 0.00000001), and an
    NDF's repr evaluates back to an equal NDF."""
    assert repr(obj) == text
    if isinstance(obj, (stfit.Ggx, stfit.Beckmann, stfit.StudentT)):
        assert eval(text, {"stfit": stfit}) == obj


def test_fit_result_repr_writes_huge_numbers_shortly():
    """A FitResult with a huge rmse (scale 1e300) shows it as 1e+300-like text, not in 149
    digits."""
    record = _ground_ggx().to_dict()
    record.update(rmse_sqrt_l=1.2345e300, alpha=1e-8)
    fit = stfit.FitResult.from_json(json.dumps(record))
    assert repr(fit) == ("stfit.FitResult(sample 'ground', ggx, alpha=1e-08, "
                         "rmse_sqrt_l=1.2345e+300)")
    a = stfit.Microsurface(stfit.Ggx(0.3), 1.5).albedo(UP, walks=10)
    assert f"transmittance={a.transmittance!r} +- {a.transmittance_stderr!r}" in repr(a)
    # None of the 10 walks is reflected: the bound, as a float repr, instead of a +- 0.
    assert a.reflectance == 0.0
    assert f"reflectance=0.0 (no walk; below {a.reflectance_upper_bound!r} at 95%)" in repr(a)


def test_ndfs_and_dielectrics_compare_and_hash_by_value():
    """Immutable parameter objects are equal when their class and parameters are, with
    hashes to match (usable as dict keys); another class or parameter is unequal."""
    assert stfit.Ggx(0.3) == stfit.Ggx(0.3) and hash(stfit.Ggx(0.3)) == hash(stfit.Ggx(0.3))
    assert stfit.StudentT(0.3, 3) == stfit.StudentT(0.3, 3.0)
    assert stfit.Ggx(0.3) != stfit.Ggx(0.31)
    assert stfit.Ggx(0.3) != stfit.Beckmann(0.3)
    assert stfit.StudentT(0.3, 3) != stfit.StudentT(0.3, 4)
    assert stfit.Ggx(0.3) != 0.3 and stfit.Ggx(0.3) != "Ggx"
    glass = stfit.RoughDielectric(stfit.Ggx(0.3), 1.5)
    assert glass == stfit.RoughDielectric(stfit.Ggx(0.3), 1.5, masking="separable")
    assert hash(glass) == hash(stfit.RoughDielectric(stfit.Ggx(0.3), 1.5))
    assert glass != stfit.RoughDielectric(stfit.Ggx(0.3), 1.5, masking="correlated")
    assert glass != stfit.RoughDielectric(stfit.Beckmann(0.3), 1.5)
    assert glass != stfit.RoughDielectric(stfit.Ggx(0.3), 1.33)
    assert len({stfit.Ggx(0.3), stfit.Ggx(0.3), glass, stfit.RoughDielectric(stfit.Ggx(0.3),
                                                                            1.5)}) == 2
    walk = stfit.Microsurface(stfit.StudentT(0.3, 3), 1.5)
    assert walk == stfit.Microsurface(stfit.StudentT(0.3, 3), 1.5, orders="all")
    assert hash(walk) == hash(stfit.Microsurface(stfit.StudentT(0.3, 3), 1.5))
    assert walk != stfit.Microsurface(stfit.StudentT(0.3, 3), 1.5, orders="single")


def test_values_pickle():
    """Microsurface, Dataset and Albedo are plain values: they pickle and read back equal
    (every number exactly), as NDFs, RoughDielectric and FitResult do."""
    for obj in [stfit.Ggx(0.3), stfit.StudentT(0.3, 2.5),
                stfit.RoughDielectric(stfit.Beckmann(0.2), 1.33, masking="correlated"),
                stfit.Microsurface(stfit.StudentT(0.3, 3), 1.5, orders="multiple")]:
        back = pickle.loads(pickle.dumps(obj))
        assert back == obj and type(back) is type(obj) and repr(back) == repr(obj)
    data = stfit.load(EXAMPLE)
    general = stfit.synth("ggx", 0.3, grid="general", noise=0.1, sample="g")
    for d in [data, general, stfit.load(general.columns())]:
        back = pickle.loads(pickle.dumps(d))
        assert back == d and back.source == d.source
        assert stfit.fit(back, model="ggx") == stfit.fit(d, model="ggx")
    with pytest.raises(TypeError):
        hash(data)
    a = stfit.Microsurface(stfit.Ggx(0.3), 1.5).albedo([0.6, 0.0, 0.8], walks=100, seed=7)
    back = pickle.loads(pickle.dumps(a))
    fields = ["reflectance", "transmittance", "reflectance_stderr", "transmittance_stderr",
              "mean_bounces", "truncated", "walks"]
    assert [getattr(back, f) for f in fields] == [getattr(a, f) for f in fields]
    assert repr(back) == repr(a)
    one = stfit.Microsurface(stfit.Ggx(0.3), 1.5).albedo(UP, walks=1)
    assert pickle.loads(pickle.dumps(one)).reflectance_stderr is None


def test_albedo_compares_and_hashes_by_value():
    """Albedo estimates are equal when every field is the same number (an undefined standard
    error too: a 1-walk estimate equals its pickled copy), and hash consistently; another seed
    or count of walks gives a different estimate. Albedo had identity equality only."""
    surface = stfit.Microsurface(stfit.Ggx(0.3), 1.5)
    a = surface.albedo([0.6, 0.0, 0.8], walks=100, seed=7)
    again = surface.albedo([0.6, 0.0, 0.8], walks=100, seed=7)
    assert a == again and hash(a) == hash(again) and len({a, again}) == 1
    assert a != surface.albedo([0.6, 0.0, 0.8], walks=100, seed=8)
    assert a != surface.albedo([0.6, 0.0, 0.8], walks=101, seed=7)
    one = surface.albedo(UP, walks=1)
    assert pickle.loads(pickle.dumps(one)) == one
    assert a != one and a != "albedo"
