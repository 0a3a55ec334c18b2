//! Full-sphere NDFs: projected area by quadrature, normalisation and majorants.

use stfit_core::Vec3;
use stfit_core::math::spherical_direction;
use stfit_core::ndf::{Beckmann, Ggx, Ndf, StudentT};
use stfit_core::sphere::{
    HeightField, Porous, SphereNdf, VonMisesFisher, ring_cross_section, sigma_by_quadrature,
};

const THETAS_DEG: [f64; 12] = [
    0.0, 10.0, 30.0, 60.0, 85.0, 89.9, 90.0, 90.1, 95.0, 120.0, 150.0, 180.0,
];

/// Checks quadrature sigma against the closed form to 1e-6 relative (1e-12 absolute where
/// sigma is negligible, far below the horizon at low roughness).
fn check_sigma_matches_closed_form<N: Ndf>(ndf: &N, label: &str)
where
    HeightField<N>: SphereNdf,
{
    let hf = HeightField(ndf.clone());
    for &deg in &THETAS_DEG {
        let w = spherical_direction(deg.to_radians(), 0.3);
        let exact = ndf.sigma(w);
        let quad = sigma_by_quadrature(|u| hf.d_cos(u), w.z, hf.angular_width());
        let err = (quad - exact).abs();
        assert!(
            err <= 1e-6 * exact.abs() || err <= 1e-12,
            "{label} theta {deg}: quadrature {quad:.12e} vs closed form {exact:.12e}"
        );
    }
}

#[test]
fn sigma_by_quadrature_matches_closed_forms_of_height_fields() {
    for alpha in [0.05, 0.3, 1.0, 2.0] {
        check_sigma_matches_closed_form(
            &Beckmann::new(alpha).unwrap(),
            &format!("beckmann {alpha}"),
        );
        check_sigma_matches_closed_form(&Ggx::new(alpha).unwrap(), &format!("ggx {alpha}"));
        for gamma in [2.0, 3.0, 10.0, 40.0] {
            let ndf = StudentT::new(alpha, gamma).unwrap();
            check_sigma_matches_closed_form(&ndf, &format!("student-t {alpha} {gamma}"));
        }
    }
}

#[test]
fn ring_cross_section_equals_azimuthal_quadrature() {
    for (c, u) in [
        (0.3, 0.9),
        (0.9, 0.2),
        (-0.4, 0.7),
        (0.0, 0.5),
        (0.5, -0.5),
        (-1.0, 0.3),
    ] {
        let s = (1.0f64 - c * c).sqrt();
        let sm = (1.0f64 - u * u).sqrt();
        let n = 200_000;
        let brute: f64 = (0..n)
            .map(|k| {
                let phi = (k as f64 + 0.5) / n as f64 * std::f64::consts::TAU;
                (c * u + s * sm * phi.cos()).max(0.0)
            })
            .sum::<f64>()
            * std::f64::consts::TAU
            / n as f64;
        let k = ring_cross_section(c, u);
        assert!((k - brute).abs() < 1e-8, "c {c} u {u}: {k} vs {brute}");
    }
}

/// `sigma(w) - sigma(-w) = w.z integral D wm.z dwm`, which is `w.z` for the
/// projected-area-normalised NDFs and `(1 - P) w.z` for a porous blend.
fn check_projected_difference(ndf: &impl SphereNdf, expected_norm: f64, label: &str) {
    for &deg in &[0.0, 20.0, 45.0, 70.0, 88.0] {
        let w = spherical_direction(f64::to_radians(deg), 1.0);
        let diff = ndf.sigma(w) - ndf.sigma(-w);
        assert!(
            (diff - expected_norm * w.z).abs() < 1e-7 * ndf.sigma(w).max(1.0),
            "{label} theta {deg}: sigma(w) - sigma(-w) = {diff}, want {}",
            expected_norm * w.z
        );
    }
}

#[test]
fn von_mises_fisher_is_normalised_by_projected_area() {
    for kappa in [0.1, 1.0, 10.0, 100.0, 1e4] {
        let ndf = VonMisesFisher::new(kappa).unwrap();
        check_projected_difference(&ndf, 1.0, &format!("vmf {kappa}"));
    }
}

#[test]
fn porous_blend_keeps_the_height_field_projection_and_adds_a_sphere() {
    let base = HeightField(Ggx::new(0.5).unwrap());
    for porosity in [0.0, 0.3, 1.0] {
        let ndf = Porous::new(base, porosity).unwrap();
        check_projected_difference(&ndf, 1.0 - porosity, &format!("porous {porosity}"));
    }
    // A uniform sphere has the same projected area from every direction.
    let sphere = Porous::new(base, 1.0).unwrap();
    let s0 = sphere.sigma(Vec3::z());
    for deg in [30.0, 90.0, 160.0] {
        let w = spherical_direction(f64::to_radians(deg), 0.0);
        assert!((sphere.sigma(w) / s0 - 1.0).abs() < 1e-9);
    }
}

/// Scans D densely: the bound must hold everywhere and be tight (the scan's maximum within
/// 1e-3 of it) unless it is the supremum approached at grazing.
fn check_bound(ndf: &impl SphereNdf, tight: bool, label: &str) {
    let bound = ndf.majorant();
    let n = 200_000;
    let mut max = 0.0f64;
    for k in 0..=n {
        let u = -1.0 + 2.0 * k as f64 / n as f64;
        let d = ndf.d_cos(u);
        assert!(d <= bound, "{label}: D({u}) = {d} exceeds bound {bound}");
        max = max.max(d);
    }
    if tight {
        assert!(
            max >= bound * (1.0 - 1e-3),
            "{label}: bound {bound} loose, max {max}"
        );
    }
}

#[test]
fn bounds_are_valid_and_tight() {
    for alpha in [0.05, 0.3, 0.7, 1.0, 1.5] {
        check_bound(
            &HeightField(Beckmann::new(alpha).unwrap()),
            true,
            &format!("beckmann {alpha}"),
        );
        check_bound(
            &HeightField(Ggx::new(alpha).unwrap()),
            alpha <= 1.0,
            &format!("ggx {alpha}"),
        );
        for gamma in [2.0, 2.5, 3.0, 10.0] {
            let ndf = HeightField(StudentT::new(alpha, gamma).unwrap());
            check_bound(
                &ndf,
                gamma > 2.0 || alpha <= 1.0,
                &format!("st {alpha} {gamma}"),
            );
        }
    }
    for kappa in [0.5, 20.0, 500.0] {
        check_bound(
            &VonMisesFisher::new(kappa).unwrap(),
            true,
            &format!("vmf {kappa}"),
        );
    }
    let porous = Porous::new(HeightField(Beckmann::new(0.4).unwrap()), 0.2).unwrap();
    check_bound(&porous, true, "porous");
}

#[test]
fn student_t_below_gamma_two_has_no_majorant() {
    assert!(
        HeightField(StudentT::new(0.5, 1.8).unwrap())
            .majorant()
            .is_infinite()
    );
}

#[test]
fn constructors_reject_invalid_parameters() {
    for kappa in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(VonMisesFisher::new(kappa).is_err(), "kappa {kappa}");
    }
    let base = HeightField(Ggx::new(0.5).unwrap());
    for p in [-0.1, 1.1, f64::NAN] {
        assert!(Porous::new(base, p).is_err(), "porosity {p}");
    }
}
