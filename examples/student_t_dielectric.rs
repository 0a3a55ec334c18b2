//! Evaluate and sample a Student-T rough dielectric: the single-scattering BSDF of Walter et
//! al. 2007 with the Student-T NDF, as a renderer would use it.
//!
//! Run with `cargo run --release --example student_t_dielectric`.

use stfit_core::Vec3;
use stfit_core::bsdf::{AnalyticBsdf, Bsdf, Masking, RoughDielectric};
use stfit_core::math::{radians, spherical_direction};
use stfit_core::ndf::{Ndf, StudentT};
use stfit_core::rand::SeedableRng;

fn main() -> Result<(), stfit_core::ParamError> {
    // Frosted glass as fitted to Walter et al.'s measurements: alpha 0.42, gamma 2.7, eta 1.51.
    let ndf = StudentT::new(0.42, 2.7)?;
    let glass = RoughDielectric::new(ndf, 1.51, Masking::Correlated)?;

    // Light from the air at 30 degrees (wi points toward the light).
    let wi = spherical_direction(radians(30.0), std::f64::consts::PI);
    println!("Smith G1 of the light direction: {:.6}", ndf.g1(wi));

    // The BSDF times |wo.z| toward a few directions: reflected, transmitted straight down, and
    // along the refracted direction.
    for (what, wo) in [
        ("mirror reflection", Vec3::new(-wi.x, -wi.y, wi.z)),
        ("straight through", Vec3::new(0.0, 0.0, -1.0)),
        ("refracted", spherical_direction(radians(180.0 - 19.3), 0.0)),
    ] {
        println!(
            "{what:18} f cos = {:.6}, sampling density {:.6}",
            glass.f_cos(wi, wo),
            glass.density(wi, wo)
        );
    }

    // Importance sampling: each sample's weight is f |wo.z| / pdf, so their mean estimates the
    // directional albedo, which a single-scattering dielectric keeps below 1.
    let mut rng = rand_pcg::Pcg64::seed_from_u64(1);
    let n = 200_000;
    let (mut reflected, mut transmitted) = (0.0, 0.0);
    for _ in 0..n {
        if let Some(s) = glass.sample(wi, &mut rng) {
            if s.wo.z > 0.0 {
                reflected += s.weight;
            } else {
                transmitted += s.weight;
            }
        }
    }
    println!(
        "single-scattering albedo from {n} samples: reflected {:.4}, transmitted {:.4}",
        reflected / n as f64,
        transmitted / n as f64
    );
    Ok(())
}
