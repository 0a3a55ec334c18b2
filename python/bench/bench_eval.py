"""Student-T rough dielectric at 10^6 direction pairs: stfit (Rust, GIL released, all cores)
against the same formula written in vectorised NumPy.

    python python/bench/bench_eval.py [--pairs N] [--repeats R] [--gamma G]

Prints the median wall and CPU time (the process's, over all its threads: the work, which a
busy machine does not inflate) of each over R runs, the speed-ups, and the largest relative
difference between the two (they compute the same function: Walter et al. 2007's
single-scattering BSDF times |wo.z| with the Student-T NDF of d'Eon 2023, its closed-form
Smith Lambda, exact Fresnel and separable masking).
"""

import argparse
import os
import statistics
import time

import numpy as np

import stfit

ALPHA, GAMMA, ETA = 0.45, 3.0, 1.51


def excess(k, nu):
    """The Student-T tail integral of stfit-core's `StudentT::excess`, vectorised:
    (nu + k^2) / (nu - 1) f(k) - k P(T > k), P by the incomplete-beta continued fraction."""
    from math import lgamma, pi

    t_norm = np.exp(lgamma(0.5 * (nu + 1)) - lgamma(0.5 * nu)) / np.sqrt(nu * pi)
    q = k * k / nu
    f = t_norm * np.exp(-0.5 * (nu + 1) * np.log1p(q))
    a = 0.5 * nu
    x = 1 / (1 + q)
    terminating = (a == int(a)) and a <= 2
    first = (x < (a + 1) / (a + 2.5)) & ~(terminating & (x >= 0.5))
    upper = np.empty_like(k)
    upper[first] = f[first] * k[first] * beta_cf(a, 0.5, x[first]) / nu
    rest = ~first
    upper[rest] = 0.5 - f[rest] * k[rest] * beta_cf(0.5, a, (q / (1 + q))[rest])
    out = (nu + k * k) / (nu - 1) * f - k * upper
    return np.where(k > 1e100, 0.0, out)


def beta_cf(a, b, x):
    """Lentz-free continued fraction of the incomplete beta function, vectorised (iterated
    until every element has converged, as the scalar code iterates per element)."""
    qab, qap, qam = a + b, a + 1, a - 1
    a0 = np.ones_like(x)
    b0 = np.ones_like(x)
    a1 = np.ones_like(x)
    b1 = 1 - qab * x / qap
    h = a1 / b1
    done = np.zeros(x.shape, bool)
    for m in range(1, 10_000):
        m2 = 2 * m
        even = m * (b - m) * x / ((qam + m2) * (a + m2))
        a2, b2 = a1 + even * a0, b1 + even * b0
        odd = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2))
        a3, b3 = a2 + odd * a1, b2 + odd * b1
        r = 1 / b3
        hn = a3 * r
        a0, b0, a1, b1 = a2 * r, b2 * r, hn, np.ones_like(x)
        newly = np.abs(hn - h) <= 1e-16 * np.abs(hn)
        h = np.where(done, h, hn)
        done |= newly
        if done.all():
            break
    return h


def sigma_up(w, nu):
    """Projected area of the upper-hemisphere direction w (|w.z| taken)."""
    c = np.abs(w[:, 2])
    sin = np.hypot(w[:, 0], w[:, 1])
    s = ALPHA / np.sqrt(2)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(sin > 0, c / (sin * s), np.inf)
        tail = np.where(sin > 0, sin * s * excess(np.where(sin > 0, k, 1.0), nu), 0.0)
    return c + tail


def d_student_t(h):
    u2 = h[:, 2] ** 2
    sin2 = np.minimum(h[:, 0] ** 2 + h[:, 1] ** 2, 1.0)
    g1 = GAMMA - 1
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.exp(-2 * np.log(u2) - GAMMA * np.log1p(sin2 / u2 / (g1 * ALPHA**2))) / (np.pi * ALPHA**2)
    return np.where((h[:, 2] > 0) & (u2 > 0), d, 0.0)


def fresnel(cos_i, eta):
    eta = np.where(cos_i < 0, 1 / eta, eta)
    cos_i = np.minimum(np.abs(cos_i), 1.0)
    sin2_t = (1 - cos_i**2) / eta**2
    cos_t = np.sqrt(np.maximum(1 - sin2_t, 0))
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return np.where(sin2_t >= 1, 1.0, 0.5 * (rs**2 + rp**2))


def f_cos_numpy(wi, wo):
    """Walter et al. 2007 f(wi, wo) |wo.z| with separable Smith masking, vectorised."""
    nu = 2 * GAMMA - 2
    ci, co = wi[:, 2], wo[:, 2]
    refl = ci * co > 0
    n_i = np.where(ci > 0, 1.0, ETA)[:, None]
    n_o = np.where(co > 0, 1.0, ETA)[:, None]
    v = np.where(refl[:, None], wi + wo, -(wi * n_i + wo * n_o))
    length = np.linalg.norm(v, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        h = v / length[:, None]
        h = np.where(h[:, 2:3] < 0, -h, h)
        cih = np.einsum("ij,ij->i", wi, h)
        coh = np.einsum("ij,ij->i", wo, h)
        ok = (ci != 0) & (co != 0) & (length > 0) & (cih * ci > 0) & (coh * co > 0)
        denom = n_i[:, 0] * cih + n_o[:, 0] * coh
        jac = np.where(refl, 0.25 / np.abs(coh), n_o[:, 0] ** 2 * np.abs(coh) / denom**2)
        f = fresnel(cih, ETA)
        lobe = np.where(refl, f, 1 - f)
        a_i = sigma_up(wi, nu) / np.abs(ci)
        a_o = sigma_up(wo, nu) / np.abs(co)
        value = np.abs(cih) * jac * lobe / np.abs(ci) / (a_i * a_o) * d_student_t(h)
    return np.where(ok, value, 0.0)


def pairs(n, seed=1):
    rng = np.random.default_rng(seed)
    wi = rng.normal(size=(n, 3))
    wi[:, 2] = np.abs(wi[:, 2])  # light from the air
    wo = rng.normal(size=(n, 3))  # reflected and transmitted
    return [v / np.linalg.norm(v, axis=1, keepdims=True) for v in (wi, wo)]


def median_time(f, repeats):
    """Medians of the wall time and of the process's CPU time (all threads) of one call."""
    wall, cpu = [], []
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        f()
        wall.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    return statistics.median(wall), statistics.median(cpu)


def main():
    global GAMMA
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=11)
    parser.add_argument("--gamma", type=float, default=GAMMA,
                        help="Student-T shape (default 3; integer shapes up to 16 take integer "
                        "powers in stfit, others a logarithm and an exponential)")
    args = parser.parse_args()
    GAMMA = args.gamma
    wi, wo = pairs(args.pairs)
    glass = stfit.RoughDielectric(stfit.StudentT(ALPHA, GAMMA), ETA, masking="separable")
    ours, theirs = glass.eval(wi, wo), f_cos_numpy(wi, wo)
    scale = np.maximum(np.abs(ours), 1e-300)
    diff = np.max(np.abs(ours - theirs) / scale)
    t_rust = median_time(lambda: glass.eval(wi, wo), args.repeats)
    t_numpy = median_time(lambda: f_cos_numpy(wi, wo), max(3, args.repeats // 3))
    print(f"pairs                 {args.pairs} (alpha {ALPHA}, gamma {GAMMA}, eta {ETA})")
    print(f"cores                 {os.cpu_count()}")
    print(f"stfit eval (median)   {t_rust[0] * 1e3:.1f} ms wall, {t_rust[1] * 1e3:.1f} ms CPU")
    print(f"numpy eval (median)   {t_numpy[0] * 1e3:.1f} ms wall, {t_numpy[1] * 1e3:.1f} ms CPU")
    print(f"speed-up              {t_numpy[0] / t_rust[0]:.1f}x wall, "
          f"{t_numpy[1] / t_rust[1]:.1f}x CPU")
    print(f"max relative diff     {diff:.2e}")


if __name__ == "__main__":
    main()
