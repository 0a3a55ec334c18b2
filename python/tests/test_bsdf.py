"""NDFs, the rough dielectric and the random walk on arrays: vectorised calls equal the scalar
calls and the command line's `stfit eval`, and samplers return unit vectors on the right side."""

import io

import numpy as np
import pytest

import stfit

NDFS = [stfit.StudentT(0.35, 2.7), stfit.Ggx(0.3), stfit.Beckmann(0.25)]


def sphere(n, seed, lower=None):
    """`n` unit vectors, uniform on the sphere (or a hemisphere: lower True / False)."""
    v = np.random.default_rng(seed).normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    if lower is not None:
        v[:, 2] = -np.abs(v[:, 2]) if lower else np.abs(v[:, 2])
    return v


@pytest.mark.parametrize("ndf", NDFS, ids=repr)
def test_ndf_batches_equal_scalar_calls(ndf):
    w = sphere(500, 1)
    wm = sphere(500, 2, lower=False)
    for name, x in [("d", wm), ("lambda_", w), ("sigma", w), ("g1", w)]:
        f = getattr(ndf, name)
        batch = f(x)
        assert batch.shape == (500,)
        assert np.array_equal(batch, np.array([f(v) for v in x])), name
    # Any leading shape: (10, 50, 3) gives (10, 50).
    assert np.array_equal(ndf.sigma(w.reshape(10, 50, 3)), ndf.sigma(w).reshape(10, 50))
    # The projected area obeys sigma(w) - sigma(-w) = w.z.
    np.testing.assert_allclose(ndf.sigma(w) - ndf.sigma(-w), w[:, 2], atol=1e-9)


@pytest.mark.parametrize("ndf", NDFS, ids=repr)
def test_visible_normals_are_unit_and_visible(ndf):
    """From directions all over the sphere: |wm| = 1, wm.z > 0, w.wm > 0; seeded."""
    w = sphere(20_000, 3)
    wm = ndf.sample_visible(w, seed=5)
    assert wm.shape == w.shape
    np.testing.assert_allclose(np.linalg.norm(wm, axis=1), 1.0, atol=1e-12)
    assert (wm[:, 2] > 0).all()
    assert (np.einsum("ij,ij->i", w, wm) > 0).all()
    assert np.array_equal(wm, ndf.sample_visible(w, seed=5))
    assert not np.array_equal(wm, ndf.sample_visible(w, seed=6))


def test_visible_normals_have_the_visible_density():
    """The mean of wm.z from normal incidence equals its integral against D_w (here
    E[wm.z] = integral wm.z^2 D / sigma, by quadrature in theta), within 5 standard errors."""
    ndf = stfit.Ggx(0.5)
    up = np.tile([0.0, 0.0, 1.0], (200_000, 1))
    z = ndf.sample_visible(up, seed=1)[:, 2]
    t = np.linspace(0, np.pi / 2, 20001)
    wm = np.stack([np.sin(t), 0 * t, np.cos(t)], axis=1)
    d = ndf.d(wm)
    integrand = np.cos(t) ** 2 * d * np.sin(t) * 2 * np.pi
    expected = np.trapezoid(integrand, t) / ndf.sigma([0.0, 0.0, 1.0])
    assert abs(z.mean() - expected) < 5 * z.std() / np.sqrt(z.size)


@pytest.mark.parametrize("masking", ["separable", "correlated"])
@pytest.mark.parametrize("ndf", NDFS, ids=repr)
def test_dielectric_batches_equal_scalar_calls(ndf, masking):
    glass = stfit.RoughDielectric(ndf, 1.51, masking=masking)
    wi, wo = sphere(400, 7), sphere(400, 8)
    for f in (glass.eval, glass.pdf):
        batch = f(wi, wo)
        assert np.array_equal(batch, np.array([f(a, b) for a, b in zip(wi, wo)]))
    # One wi against many wo broadcasts.
    assert np.array_equal(glass.eval(wi[0], wo), glass.eval(np.tile(wi[0], (400, 1)), wo))


@pytest.mark.parametrize("ndf, args", [
    (stfit.StudentT(0.4, 3.0), ["--ndf", "student-t", "--alpha", "0.4", "--gamma", "3"]),
    (stfit.StudentT(0.05, 1.6), ["--ndf", "student-t", "--alpha", "0.05", "--gamma", "1.6"]),
    (stfit.StudentT(0.7, 2.8), ["--ndf", "student-t", "--alpha", "0.7", "--gamma", "2.8"]),
    (stfit.StudentT(1.3, 1e7), ["--ndf", "student-t", "--alpha", "1.3", "--gamma", "1e7"]),
    (stfit.Ggx(0.2), ["--ndf", "ggx", "--alpha", "0.2"]),
    (stfit.Beckmann(0.7), ["--ndf", "beckmann", "--alpha", "0.7"]),
], ids=lambda v: repr(v) if not isinstance(v, list) else "")
@pytest.mark.parametrize("masking", ["separable", "correlated"])
def test_dielectric_eval_equals_the_cli(cli, ndf, args, masking):
    """`stfit eval` on the same pairs prints the same values, digit for digit (it writes the
    shortest text that reads back to the same double): a Student-T is evaluated through the
    same interpolated Lambda fractions (TabulatedStudentT) by both, where the command line had
    the exact fractions and differed from Python in the last digits of 1 value in 40."""
    for eta in (1.5, 0.7):
        glass = stfit.RoughDielectric(ndf, eta, masking)
        wi, wo = sphere(2000, 9), sphere(2000, 10)
        rows = "\n".join(",".join(repr(float(x)) for x in np.r_[a, b]) for a, b in zip(wi, wo))
        text = cli("eval", *args, "--eta", str(eta), "--masking", masking,
                   stdin="wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n" + rows + "\n")
        theirs = np.genfromtxt(io.StringIO(text), delimiter=",", names=True)["f_cos"]
        ours = glass.eval(wi, wo)
        assert np.count_nonzero(ours) > 500
        assert np.array_equal(ours, theirs), np.flatnonzero(ours != theirs)[:5]


@pytest.mark.parametrize("ndf", NDFS, ids=repr)
def test_dielectric_samples_are_unit_on_their_side_with_their_density(ndf):
    glass = stfit.RoughDielectric(ndf, 1.51)
    wi = sphere(20_000, 11)
    s = glass.sample(wi, seed=2)
    ok = s.valid
    assert ok.mean() > 0.8
    wo = s.wo[ok]
    np.testing.assert_allclose(np.linalg.norm(wo, axis=1), 1.0, atol=1e-12)
    reflected = wo[:, 2] * wi[ok, 2] > 0
    assert 0 < reflected.mean() < 0.5
    # Reflection mirrors about a facet normal with h.z > 0: wi + wo points up on wi's side.
    h = wi[ok][reflected] + wo[reflected]
    assert (h[:, 2] * wi[ok][reflected][:, 2] > 0).all()
    np.testing.assert_allclose(s.pdf[ok], glass.pdf(wi[ok], wo), rtol=1e-9)
    np.testing.assert_allclose(s.weight[ok] * s.pdf[ok], glass.eval(wi[ok], wo), rtol=1e-9)
    assert (s.weight[~ok] == 0).all() and (s.pdf[~ok] == 0).all()


def test_microsurface_conserves_energy_and_its_first_order_is_the_closed_form():
    ndf = stfit.Ggx(0.5)
    walk = stfit.Microsurface(ndf, 1.5)
    wi = np.array([-0.5, 0.0, np.sqrt(0.75)])
    a = walk.albedo(wi, walks=20_000, seed=3)
    assert a.reflectance + a.transmittance == pytest.approx(1.0, abs=1e-12)
    assert a.walks == 20_000 and a.reflectance_stderr > 0
    single = stfit.Microsurface(ndf, 1.5, orders="single")
    wo = sphere(64, 12)
    mean, stderr = single.eval(wi, wo, walks=40_000, seed=4)
    exact = stfit.RoughDielectric(ndf, 1.5, masking="correlated").eval(wi, wo)
    assert mean.shape == stderr.shape == (64,)
    z = (mean - exact) / np.maximum(stderr, 1e-300)
    assert (np.abs(z[stderr > 0]) < 5).all()
    # The same seed gives the same estimates; pairs sharing wi share their walks.
    again, _ = single.eval(wi, wo[::-1], walks=40_000, seed=4)
    assert np.array_equal(again[::-1], mean)


def test_large_batches_match_small_ones():
    """Batches large enough to run in parallel give what row-by-row calls give."""
    glass = stfit.RoughDielectric(stfit.StudentT(0.3, 3.0), 1.51)
    wi, wo = sphere(50_000, 13), sphere(50_000, 14)
    big = glass.eval(wi, wo)
    parts = np.concatenate([glass.eval(wi[k:k + 1000], wo[k:k + 1000]) for k in range(0, 50_000, 1000)])
    assert np.array_equal(big, parts)
