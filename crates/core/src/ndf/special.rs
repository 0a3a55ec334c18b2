//! Special functions for the Beckmann family: the scaled complementary error function and
//! the "visibility gap" `1 - sqrt(pi) x erfcx(x)` that governs Beckmann projected areas below
//! the horizon, both without cancellation or underflow.

#![allow(clippy::excessive_precision)]

/// `1 / sqrt(pi)`.
pub const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;
/// `sqrt(pi)`.
pub const SQRT_PI: f64 = 1.772_453_850_905_516;

/// Boundary between Cody's first interval (a series for erf) and his second (a rational
/// function for erfcx).
const CODY_1: f64 = 0.468_75;
/// Boundary between Cody's second interval and his third (a rational function in `1/x^2`).
const CODY_2: f64 = 4.0;

/// `x^2` and its rounding error `lo` (`x^2 = hi + lo` exactly), by Veltkamp's split and
/// Dekker's product: plain arithmetic, since without a target FMA `mul_add` is a library call.
#[inline]
pub(crate) fn square_with_error(x: f64) -> (f64, f64) {
    let c = 134_217_729.0 * x;
    let xh = c - (c - x);
    let xl = x - xh;
    let hi = x * x;
    (hi, ((xh * xh - hi) + 2.0 * xh * xl) + xl * xl)
}

/// `exp(x^2)` with the rounding error of `x^2` compensated, so the relative error stays near
/// one ulp for large `|x|`.
#[inline]
pub fn exp_x2(x: f64) -> f64 {
    let (x2, lo) = square_with_error(x);
    x2.exp() * (1.0 + lo)
}

/// `exp(-x^2)`, compensated like [`exp_x2`].
#[inline]
pub fn exp_neg_x2(x: f64) -> f64 {
    let (x2, lo) = square_with_error(x);
    (-x2).exp() * (1.0 - lo)
}

/// `erf(x) / x` for `|x| <= 0.46875`, given `t = x^2`: Cody's (1969) rational approximation
/// in `x^2` (coefficients of Netlib SPECFUN `calerf`).
#[inline]
fn cody_erf_over_x(t: f64) -> f64 {
    // Estrin's scheme (independent sub-products) rather than Horner's: shorter dependency
    // chain; all terms are positive, so no cancellation.
    let t2 = t * t;
    let num = (3.209_377_589_138_469_47e3 + 3.774_852_376_853_020_21e2 * t)
        + (1.138_641_541_510_501_56e2 + 3.161_123_743_870_565_60e0 * t) * t2
        + 1.857_777_061_846_031_53e-1 * (t2 * t2);
    let den = (2.844_236_833_439_170_62e3 + 1.282_616_526_077_372_28e3 * t)
        + (2.440_246_379_344_441_73e2 + 2.360_129_095_234_412_09e1 * t) * t2
        + t2 * t2;
    num / den
}

/// `erfcx(x)` for `0.46875 <= x <= 4`: Cody's (1969) rational approximation of degree 8/8,
/// by Estrin's scheme (all coefficients positive, so no cancellation), as numerator and
/// denominator so that callers can fold the division into their own.
#[inline]
fn cody_erfcx_mid_parts(x: f64) -> (f64, f64) {
    let x2 = x * x;
    let x4 = x2 * x2;
    let num = ((1.230_339_354_797_997_25e3 + 2.051_078_377_826_071_47e3 * x)
        + (1.712_047_612_634_070_58e3 + 8.819_522_212_417_690_90e2 * x) * x2)
        + ((2.986_351_381_974_001_31e2 + 6.611_919_063_714_162_95e1 * x)
            + (8.883_149_794_388_375_94e0 + 5.641_884_969_886_700_89e-1 * x) * x2)
            * x4
        + 2.153_115_354_744_038_46e-8 * (x4 * x4);
    let den = ((1.230_339_354_803_749_42e3 + 3.439_367_674_143_721_64e3 * x)
        + (4.362_619_090_143_247_16e3 + 3.290_799_235_733_459_63e3 * x) * x2)
        + ((1.621_389_574_566_690_19e3 + 5.371_811_018_620_098_58e2 * x)
            + (1.176_939_508_913_124_99e2 + 1.574_492_611_070_983_47e1 * x) * x2)
            * x4
        + x4 * x4;
    (num, den)
}

/// `erfcx(x)` for `0.46875 <= x <= 4` ([`cody_erfcx_mid_parts`]).
#[inline]
fn cody_erfcx_mid(x: f64) -> f64 {
    let (num, den) = cody_erfcx_mid_parts(x);
    num / den
}

/// `R(z)` with `sqrt(pi) x erfcx(x) = 1 - sqrt(pi) z R(z)`, `z = 1/x^2`, for `x > 4`: Cody's
/// (1969) rational approximation of the asymptotic series (`R(0) = 1 / (2 sqrt(pi))`), as
/// numerator and denominator.
#[inline]
fn cody_tail_parts(z: f64) -> (f64, f64) {
    let num = ((((1.631_538_713_730_209_78e-2 * z + 3.053_266_349_612_323_44e-1) * z
        + 3.603_448_999_498_044_39e-1)
        * z
        + 1.257_817_261_112_292_46e-1)
        * z
        + 1.608_378_514_874_227_66e-2)
        * z
        + 6.587_491_615_298_378_03e-4;
    let den = ((((z + 2.568_520_192_289_822_42e0) * z + 1.872_952_849_923_460_47e0) * z
        + 5.279_051_029_514_284_12e-1)
        * z
        + 6.051_834_131_244_131_91e-2)
        * z
        + 2.335_204_976_268_691_85e-3;
    (num, den)
}

/// `R(z)` of [`cody_tail_parts`].
#[inline]
fn cody_tail(z: f64) -> f64 {
    let (num, den) = cody_tail_parts(z);
    num / den
}

/// Scaled complementary error function `erfcx(x) = exp(x^2) erfc(x)`, accurate to a few ulps
/// on the whole real line; `+inf` for `x < -26.6` (overflow), `~1/(x sqrt(pi))` for large `x`.
/// Cody's rational approximations: no exponential at all for `x >= 0.46875`.
#[inline]
pub fn erfcx(x: f64) -> f64 {
    if x > CODY_2 {
        let z = 1.0 / (x * x);
        (FRAC_1_SQRT_PI - z * cody_tail(z)) / x
    } else if x >= CODY_1 {
        cody_erfcx_mid(x)
    } else if x > -CODY_1 {
        exp_x2(x) * (1.0 - x * cody_erf_over_x(x * x))
    } else if x.is_nan() {
        f64::NAN
    } else {
        2.0 * exp_x2(x) - erfcx(-x)
    }
}

/// `(erfc(x), exp(-x^2))` from a single exponential: `erfc(x) = exp(-x^2) erfcx(x)` with the
/// rational [`erfcx`] for `|x| >= 0.46875` (and `2 - ...` for negative `x`), Cody's series
/// for erf below. A few ulps of relative error in both (absolute for `erfc` near 2).
#[inline]
pub fn erfc_and_gauss(x: f64) -> (f64, f64) {
    let e = exp_neg_x2(x);
    let ax = x.abs();
    if ax < CODY_1 {
        return (1.0 - x * cody_erf_over_x(x * x), e);
    }
    let t = e * if ax > CODY_2 {
        let z = 1.0 / (x * x);
        (FRAC_1_SQRT_PI - z * cody_tail(z)) / ax
    } else {
        cody_erfcx_mid(ax)
    };
    (if x > 0.0 { t } else { 2.0 - t }, e)
}

/// The visibility gap `1 - sqrt(pi) x erfcx(x)` for `x >= 0`, without cancellation: it decays
/// like `1 / (2 x^2)` for large `x` and is 1 at `x = 0`. It is the acceptance probability of
/// the Student-T visible-normal sampler below the horizon, and gives the Beckmann projected
/// area below the horizon, `sigma = s alpha exp(-a^2) gap(a) / (2 sqrt(pi))`, and Lambda above
/// it, `Lambda = exp(-a^2) gap(a) / (2 a sqrt(pi))`. Beyond `x = 4` it is Cody's asymptotic
/// rational function itself, `sqrt(pi) R(1/x^2) / x^2`, so the cancellation never happens.
#[inline]
pub fn erfcx_gap(x: f64) -> f64 {
    if x > CODY_2 {
        let z = 1.0 / (x * x);
        SQRT_PI * z * cody_tail(z)
    } else {
        1.0 - SQRT_PI * x * erfcx(x)
    }
}

/// The Beckmann Smith function `Lambda(a) = (erf(a) - 1)/2 + exp(-a^2) / (2 a sqrt(pi))`
/// for `a > 0`, given `a^2` (Heitz 2014; `a = cot theta / alpha`). The exponential is taken
/// of `a^2` directly, so it does not wait for the square root that gives `a`; rounding `a^2`
/// costs no accuracy that forming `a` from a direction had not already cost. On Cody's
/// middle interval `Lambda = exp(-a^2) (Q - sqrt(pi) a P) / (2 sqrt(pi) a Q)` with `erfcx =
/// P/Q`, one division; beyond `a = 4` it is `exp(-a^2) z R(z) / (2 a)`, `z = 1/a^2`, with no
/// cancellation; below `0.46875` `erfc = 1 - a erf(a)/a` by the series.
#[inline]
pub(crate) fn lambda_beckmann_sq(a2: f64) -> f64 {
    let e = (-a2).exp();
    let a = a2.sqrt();
    if a > CODY_2 {
        let (num, den) = cody_tail_parts(1.0 / a2);
        0.5 * e * num / (a2 * a * den)
    } else if a >= CODY_1 {
        let (num, den) = cody_erfcx_mid_parts(a);
        0.5 * e * (den - SQRT_PI * a * num) / (SQRT_PI * a * den)
    } else {
        0.5 * (FRAC_1_SQRT_PI * e / a - (1.0 - a * cody_erf_over_x(a2)))
    }
}

#[cfg(test)]
#[allow(clippy::excessive_precision)]
mod tests {
    use super::*;

    /// Reference values from mpmath at 40 digits (printed to 17 significant digits).
    #[test]
    fn erfcx_matches_high_precision_references() {
        let refs = [
            (-3.0, 16_205.988_853_999_587),
            (-0.5, 1.952_360_489_182_557_1),
            (0.0, 1.0),
            (1e-3, 0.998_872_620_081_151_4),
            (0.5, 0.615_690_344_192_925_9),
            (3.9, 0.140_314_181_600_689_73),
            (4.1, 0.133_834_116_418_651_98),
            (10.0, 0.056_140_992_743_822_586),
            (1e3, 5.641_893_014_533_876_5e-4),
            (1e8, 5.641_895_835_477_562_6e-9),
        ];
        for (x, r) in refs {
            let e: f64 = erfcx(x);
            assert!(((e - r) / r).abs() < 4e-15, "erfcx({x}) = {e}, want {r}");
        }
    }

    #[test]
    fn gap_matches_high_precision_references() {
        let refs = [
            (0.0, 1.0),
            (0.3, 0.609_386_974_171_879),
            (2.0, 0.094_645_900_037_650_84),
            (3.99, 0.028_831_904_690_070_965),
            (4.01, 0.028_567_259_346_247_646),
            (30.0, 5.546_321_916_935_123e-4),
            (1e5, 4.999_999_999_25e-11),
        ];
        for (x, r) in refs {
            let e = erfcx_gap(x);
            assert!(((e - r) / r).abs() < 1e-13, "gap({x}) = {e}, want {r}");
        }
    }

    /// The Beckmann Lambda from `a^2` against mpmath (80 digits, by erfc) across Cody's three
    /// intervals and their boundaries; the residual is the cancellation of `erf(a) - 1`
    /// against the exponential term near `a = 4` (a few digits, as in any evaluation by
    /// erfc) and the rounding of `a^2`.
    #[test]
    fn beckmann_lambda_matches_high_precision_references() {
        let refs = [
            (0.001, 281.595_073_868_622_9),
            (0.1, 2.349_110_474_981_484_8),
            (0.3, 0.523_697_471_078_699_59),
            (0.468_75, 0.229_396_409_555_697_44),
            (0.5, 0.199_641_228_374_245_67),
            (1.283, 0.007_586_406_676_740_336_5),
            (2.0, 0.000_244_505_678_737_873_81),
            (3.99, 2.484_757_010_550_259_2e-10),
            (4.01, 2.087_471_594_278_031_1e-10),
            (6.0, 1.455_534_739_558_135_6e-19),
            (10.0, 5.170_265_957_331_844e-48),
            (25.0, 3.314_778_041_635_355_1e-277),
        ];
        for (a, r) in refs {
            let l = lambda_beckmann_sq(a * a);
            let err = ((l - r) / r).abs();
            assert!(err < 1e-13, "Lambda({a}) = {l}, want {r}");
        }
    }

    /// The shared-exponential erfc agrees with libm's erfc (and exp) to a few ulps from
    /// `erfc ~ 2` to `erfc ~ 1e-300`, across all three of Cody's intervals.
    #[test]
    fn erfc_and_gauss_matches_libm() {
        let mut x = -6.0;
        while x < 26.0 {
            let (c, e) = erfc_and_gauss(x);
            let (rc, re) = (libm::erfc(x), (-x * x).exp());
            assert!(((c - rc) / rc).abs() < 4e-15, "erfc({x}) = {c}, libm {rc}");
            // libm's exp(-x^2) itself carries the rounding of x^2 (relative x^2 * 2^-53).
            let tol = 4e-16 * (1.0 + x * x);
            assert!(((e - re) / re).abs() < tol, "exp(-{x}^2) = {e}, libm {re}");
            x += 0.0137;
        }
    }
}
