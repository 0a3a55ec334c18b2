//! Estimate the multiple-scattering albedo of a rough dielectric by the height-field random walk
//! (Heitz et al. 2016): how much light scatters once, how much more than once, and that a
//! lossless dielectric loses none (a white furnace).
//!
//! Run with `cargo run --release --example multiple_scattering_albedo`.

use stfit_core::ScatteringOrders;
use stfit_core::math::{radians, spherical_direction};
use stfit_core::ndf::StudentT;
use stfit_core::walk::{DielectricFacet, Estimator, Microsurface};

fn main() -> Result<(), stfit_core::ParamError> {
    // A rough Student-T glass, light from the air at 60 degrees.
    let surface = Microsurface::new(StudentT::new(0.8, 2.5)?, DielectricFacet::new(1.5)?);
    let wi = spherical_direction(radians(60.0), 0.0);
    let walks = 400_000;
    for orders in [
        ScatteringOrders::Single,
        ScatteringOrders::Multiple,
        ScatteringOrders::All,
    ] {
        let a = surface.with_orders(orders).albedo(wi, walks, 1);
        println!(
            "{:8} reflected {:.4} ± {:.4}, transmitted {:.4} ± {:.4}, mean scattering events {}",
            orders.name(),
            a.reflectance,
            a.reflectance_stderr,
            a.transmittance,
            a.transmittance_stderr,
            // None only if no walk left within the orders.
            a.mean_bounces.map_or("-".into(), |b| format!("{b:.2}"))
        );
    }
    let all = surface.albedo(wi, walks, 1);
    println!(
        "all orders conserve energy: R + T - 1 = {:.1e}",
        all.reflectance + all.transmittance - 1.0
    );
    Ok(())
}
