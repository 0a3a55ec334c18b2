"""The 12 single-scattering fits of `stfit DATA --model all` (Beckmann, GGX, Student-T with gamma
3, Student-T with free gamma, on each sample), vectorised with NumPy and SciPy, for a
side-by-side timing of the whole process against the stfit binary.

It does what stfit does (theory.md sections 2, 3, 5 and 8): Walter et al.'s transmission BTDF
with separable Smith masking and exact Fresnel, L = scale f_t cos(theta_i) / eta^2 with eta 1.51,
least squares on sqrt(L) with the scale projected out in closed form, Nelder-Mead in
(ln alpha, ln(gamma - 3/2)) from the local minima of the same starting grid (at most 3), and
HC3 sandwich standard errors from a central-difference Jacobian.

Usage: python3 python/bench/scipy_fits.py ../shared/data/walter2007/measurements.csv
"""

import csv
import sys

import numpy as np
from scipy import optimize, special

ETA = 1.51
ALPHA_GRID = [0.02, 0.04, 0.07, 0.12, 0.2, 0.35, 0.6, 1.0]
GAMMA_GRID = [1.7, 2.2, 3.2, 6.0, 20.0]


def load(path):
    samples = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(line for line in f if not line.startswith("#")):
            s = samples.setdefault(row["sample"], ([], [], []))
            s[0].append(float(row["theta_i_deg"]))
            s[1].append(float(row["theta_o_deg"]))
            s[2].append(float(row["sqrt_L"]))
    return {k: tuple(np.array(v) for v in s) for k, s in samples.items()}


def geometry(ti_deg, to_deg):
    """Per point: cos of the half vector, |wi.z|, |wo.z| and the NDF-independent factor."""
    ti, lean = np.radians(ti_deg), np.radians(to_deg - 180.0)
    wi = np.stack([-np.sin(ti), 0 * ti, np.cos(ti)])
    wo = np.stack([np.sin(lean), 0 * ti, -np.cos(lean)])
    h = -(wi + ETA * wo)
    h /= np.linalg.norm(h, axis=0)
    h *= np.sign(h[2])
    ci, co = (wi * h).sum(0), (wo * h).sum(0)
    # Exact unpolarised dielectric Fresnel at cos ci (from air).
    c = np.abs(ci)
    g2 = ETA**2 - 1 + c * c
    g = np.sqrt(np.maximum(g2, 0))
    fr = 0.5 * ((g - c) / (g + c)) ** 2 * (1 + ((c * (g + c) - 1) / (c * (g - c) + 1)) ** 2)
    denom = (ci + ETA * co) ** 2
    k = np.abs(ci) * np.abs(co) / (np.abs(wi[2]) * np.abs(wo[2])) * ETA**2 * (1 - fr) / denom
    valid = (ci > 0) & (co < 0)
    k = np.where(valid, k * np.abs(wi[2]) / ETA**2, 0.0)
    return h[2], np.abs(wi[2]), np.abs(wo[2]), k


def ndf(kind, u, alpha, gamma):
    t2 = 1 / (u * u) - 1
    if kind == "beckmann":
        return np.exp(-t2 / alpha**2) / (np.pi * alpha**2 * u**4)
    if kind == "ggx":
        return alpha**2 / (np.pi * u**4 * (alpha**2 + t2) ** 2)
    g = gamma
    return (g - 1) ** g * alpha ** (2 * g - 2) / (np.pi * u**4 * (alpha**2 * (g - 1) + t2) ** g)


def lam(kind, c, alpha, gamma):
    """Smith Lambda at |cos| c (zero at normal incidence)."""
    normal = c >= 1.0
    c = np.where(normal, 0.5, c)
    return np.where(normal, 0.0, lam_oblique(kind, c, alpha, gamma))


def lam_oblique(kind, c, alpha, gamma):
    mu = c / np.sqrt(1 - c * c)
    if kind == "beckmann":
        a = mu / alpha
        return (special.erf(a) - 1) / 2 + np.exp(-a * a) / (2 * a * np.sqrt(np.pi))
    if kind == "ggx":
        return (-1 + np.sqrt(1 + alpha**2 / mu**2)) / 2
    s = alpha / np.sqrt(2)
    k = mu / s
    nu = 2 * gamma - 2
    pdf = np.exp(
        special.gammaln((nu + 1) / 2) - special.gammaln(nu / 2) - 0.5 * np.log(nu * np.pi)
        - (nu + 1) / 2 * np.log1p(k * k / nu)
    )
    return (s / mu) * ((nu + k * k) / (nu - 1) * pdf - k * special.stdtr(nu, -k))


def model(kind, geo, alpha, gamma):
    hz, ciz, coz, k = geo
    g1 = 1 / ((1 + lam(kind, ciz, alpha, gamma)) * (1 + lam(kind, coz, alpha, gamma)))
    return k * g1 * ndf(kind, hz, alpha, gamma)


def fit(kind, gamma_fixed, geo, y):
    norm = (y * y).sum()

    def params(x):
        alpha = np.exp(np.clip(x[0], np.log(1e-3), np.log(20.0)))
        if kind == "student-t" and gamma_fixed is None:
            return alpha, 1.5 + np.exp(np.clip(x[1], np.log(1e-3), np.log(500.0)))
        return alpha, gamma_fixed

    def cost(x):
        q = np.sqrt(model(kind, geo, *params(x)))
        c = max((y * q).sum(), 0) / (q * q).sum()
        return ((y - c * q) ** 2).sum() / norm

    free_gamma = kind == "student-t" and gamma_fixed is None
    grid = [[np.log(a), np.log(g - 1.5)] if free_gamma else [np.log(a)]
            for g in (GAMMA_GRID if free_gamma else [None]) for a in ALPHA_GRID]
    costs = np.array([cost(x) for x in grid])
    shape = (len(GAMMA_GRID), len(ALPHA_GRID)) if free_gamma else (1, len(ALPHA_GRID))
    cg = costs.reshape(shape)
    minima = []
    for i in range(shape[0]):
        for j in range(shape[1]):
            nb = [cg[a, b] for a, b in ((i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1))
                  if 0 <= a < shape[0] and 0 <= b < shape[1]]
            if all(cg[i, j] <= v for v in nb):
                minima.append((cg[i, j], i * shape[1] + j))
    best = None
    for _, k in sorted(minima)[:3]:
        r = optimize.minimize(cost, grid[k], method="Nelder-Mead",
                              options={"xatol": 1e-10, "fatol": 1e-15, "maxiter": 400})
        if best is None or r.fun < best.fun:
            best = r
    alpha, gamma = params(best.x)
    q = np.sqrt(model(kind, geo, alpha, gamma))
    c = (y * q).sum() / (q * q).sum()
    scale = c * c
    # HC3 sandwich standard errors of (alpha, [gamma], scale).
    theta = [alpha] + ([gamma] if free_gamma else [])
    cols = []
    for i, v in enumerate(theta):
        h = 1e-4 * (v - 1.5 if i == 1 else v)
        up, dn = list(theta), list(theta)
        up[i] += h
        dn[i] -= h
        mp = model(kind, geo, up[0], up[1] if free_gamma else gamma)
        mm = model(kind, geo, dn[0], dn[1] if free_gamma else gamma)
        cols.append((np.sqrt(scale * mp) - np.sqrt(scale * mm)) / (2 * h))
    m = q * q
    cols.append(np.sqrt(m) / (2 * np.sqrt(scale)))
    jac = np.stack(cols, axis=1)
    r = y - np.sqrt(scale * m)
    bread = np.linalg.inv(jac.T @ jac)
    leverage = np.einsum("ij,jk,ik->i", jac, bread, jac)
    rj = r / (1.0 - leverage)
    meat = (jac * (rj * rj)[:, None]).T @ jac
    se = np.sqrt(np.diag(bread @ meat @ bread))
    rmse = np.sqrt((r * r).mean())
    return alpha, gamma, scale, rmse, se


def main():
    for name, (ti, to, sqrt_l) in load(sys.argv[1]).items():
        geo = geometry(ti, to)
        for kind, g in (("beckmann", None), ("ggx", None), ("student-t", 3.0), ("student-t", None)):
            alpha, gamma, scale, rmse, se = fit(kind, g, geo, sqrt_l)
            print(f"{name:8} {kind:10} {'' if g is None else '(3)':4} alpha {alpha:.4f} "
                  f"gamma {gamma if gamma is not None else '':<8} scale {scale:.4f} "
                  f"rmse {rmse:.5f} se {np.array2string(se, precision=4)}")


if __name__ == "__main__":
    main()
