//! Round trips through a renderer: a Student-T fit translated to GGX (over the sphere of
//! directions, not by a formula) explains the original measurements within 10% of the rmse of
//! a GGX fitted to them directly. Runs on the synthetic example data (fits/example.csv) and,
//! when the shared folder is present, on the Walter et al. 2007 measurements. The V-Ray (GTR)
//! translation of the same fit is measured beside it.

use stfit_core::Vec3;
use stfit_export::ExportModel;
use stfit_export::directions::l_of;
use stfit_export::target::{Scatter, Smith};
use stfit_export::targets::vray::VRayGlass;
use stfit_export::targets::vray::translation as vray_translation;
use stfit_export::targets::{AlphaMap, Family1, Microfacet};
use stfit_export::translate::{Family, Reference, fit};
use stfit_fit::conventions::pair_from_deg;
use stfit_fit::{
    Dataset, FitOptions, Gamma, Model, ModelKind, ModelSpec, Sample, fit_sample, load_path,
};
use stfit_test_support::{project_root, walter_measurements};

/// The usable points of an in-plane sample: `(theta_i, theta_o)` and the measured `L`.
fn points(sample: &Sample) -> (Vec<(f64, f64)>, Vec<f64>) {
    sample
        .points
        .iter()
        .filter(|p| p.weight > 0.0)
        .map(|p| (p.in_plane_angles().expect("an in-plane sample"), p.value))
        .unzip()
}

/// rmse of `sqrt(L)` of model values against measured ones.
fn rmse(model: &[f64], measured: &[f64]) -> f64 {
    let s: f64 = model
        .iter()
        .zip(measured)
        .map(|(m, l)| (l.max(0.0).sqrt() - m.max(0.0).sqrt()).powi(2))
        .sum();
    (s / measured.len() as f64).sqrt()
}

/// `L` of a renderer BSDF at the measured configurations, with the fit's scale and eta.
fn target_l(target: &impl Scatter, angles: &[(f64, f64)], eta: f64, scale: f64) -> Vec<f64> {
    angles
        .iter()
        .map(|&(ti, to)| {
            let (wi, wo): (Vec3, Vec3) = pair_from_deg(ti, to);
            l_of(target.f_cos(wi, wo), wi, wo, eta, scale)
        })
        .collect()
}

fn check(data: &Dataset) {
    let opts = FitOptions::default();
    for sample in &data.samples {
        let direct = fit_sample(sample, ModelSpec::ggx(), &opts).unwrap();
        let st = fit_sample(sample, ModelSpec::student_t(), &opts).unwrap();
        let model = ExportModel::from_fit(&st).unwrap();
        let reference = Reference::standard(&model).unwrap();
        let ggx = Microfacet {
            ndf: Family1::Ggx,
            eta: st.model.eta,
            smith: Smith::MitsubaSeparable,
            map: AlphaMap::Alpha,
            name: "alpha",
            max_param: 10.0,
            min_alpha: 0.0,
        };
        let mut warnings = Vec::new();
        let t = fit(&ggx, &model, &reference, &mut warnings).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        let alpha = t.params[0].value;
        // The renderer gets alpha only; the calibration scale is the Student-T fit's.
        let translated = Model {
            kind: ModelKind::Ggx,
            alpha,
            gamma: Gamma::NotApplicable,
            ..st.model
        };
        let (angles, measured) = points(sample);
        let r = rmse(&translated.predict(&angles).unwrap(), &measured);
        let v = vray_translation(&model, &reference, &mut warnings).unwrap();
        let p: Vec<f64> = v.params.iter().map(|p| p.value).collect();
        let family = VRayGlass {
            eta: st.model.eta,
            starts: [(0.5, 2.0); 2],
        };
        let gtr = family.build(&p).unwrap();
        let r_vray = rmse(
            &target_l(&gtr, &angles, st.model.eta, st.model.scale),
            &measured,
        );
        println!(
            "{} {}: direct GGX alpha {:.4} rmse {:.5}; Student-T alpha {:.4} gamma {:.3} rmse {:.5} -> GGX alpha {:.4} rmse {:.5} ({:+.1}%); -> V-Ray glossiness {:.4} gtr_gamma {:.3} rmse {:.5}",
            data.source.display(),
            sample.name,
            direct.model.alpha,
            direct.rmse_sqrt_l,
            st.model.alpha,
            st.model.gamma.value().unwrap(),
            st.rmse_sqrt_l,
            alpha,
            r,
            100.0 * (r / direct.rmse_sqrt_l - 1.0),
            p[0],
            p[1],
            r_vray
        );
        assert!(
            r <= 1.10 * direct.rmse_sqrt_l,
            "{}: translated rmse {r} vs direct {}",
            sample.name,
            direct.rmse_sqrt_l
        );
    }
}

#[test]
fn student_t_translated_to_ggx_fits_synthetic_data_within_10_percent_of_direct_ggx() {
    check(&load_path(&project_root().join("fits/example.csv")).unwrap());
}

#[test]
fn student_t_translated_to_ggx_fits_walter_data_within_10_percent_of_direct_ggx() {
    let Some(path) = walter_measurements("round_trip") else {
        return;
    };
    check(&load_path(&path).unwrap());
}
