//! Radiance's own BSDF library reads the exported WINDOW XML files: `checkBSDF` (from the
//! pyradiance package, installed by `.ci/python-env` under the build folder) must load them,
//! and its hemispherical totals ("Max. Tot. Dir", the largest directional total over incident
//! Klems patches, per component) must match (a) the file's own matrices and (b) stfit's own
//! albedo of the same model at that patch, computed without the Klems basis, within the stated
//! error of the file. The exported model is the example frosted Student-T fit. Without the
//! environment the test says it did not run and passes, except under CI=true.

use stfit_core::Vec3;
use stfit_core::bsdf::AnalyticBsdf;
use stfit_core::quadrature::GaussLegendre;
use stfit_core::walk::ScatteringOrders;
use stfit_export::ExportModel;
use stfit_export::radiance::klems::{self, ring_of};
use stfit_export::radiance::layer::{Layer, Pane, RoughFace, albedo};
use stfit_export::radiance::{self, KlemsBsdf, LayerKind, QuadratureRule, RadianceOptions};
use stfit_fit::{FitsFile, Masking, Model};
use stfit_test_support::{CaseDir, Radiance, project_root};

/// checkBSDF's "Max. Tot. Dir" per WINDOW block name.
fn totals(output: &str) -> Vec<(&'static str, f64)> {
    let names = [
        ("Exterior Refl", "Reflection Front"),
        ("Interior Refl", "Reflection Back"),
        ("Ext->Int Trans", "Transmission Front"),
        ("Int->Ext Trans", "Transmission Back"),
    ];
    let mut out = Vec::new();
    let section = output
        .split("Max. Tot. Dir")
        .nth(1)
        .expect("checkBSDF printed no totals");
    for line in section.lines().take(5) {
        for (radiance, window) in names {
            if line.starts_with(radiance) {
                let pct = line
                    .split_whitespace()
                    .find(|t| t.ends_with('%'))
                    .expect("a percentage");
                out.push((
                    window,
                    pct.trim_end_matches('%').parse::<f64>().unwrap() / 100.0,
                ));
            }
        }
    }
    assert_eq!(out.len(), 4, "{output}");
    out
}

/// Gauss-Legendre nodes in `cos^2 theta` over the ring of patch `i`: the incident directions of
/// a patch, cosine-weighted (the model is isotropic, so azimuth does not matter), with weights
/// adding up to 1.
fn ring_nodes(i: usize) -> Vec<(f64, f64)> {
    let (r, _) = ring_of(i);
    let c0 = klems::THETA_LO_DEG[r].to_radians().cos().powi(2);
    let c1 = klems::theta_hi_deg(r).to_radians().cos().powi(2);
    GaussLegendre::new(6)
        .points()
        .map(|(x, w)| ((1.0 - 0.5 * (1.0 + x)) * c0 + 0.5 * (1.0 + x) * c1, 0.5 * w))
        .collect()
}

/// The incident direction toward the light of a node with `cos^2 theta = u` on a side.
fn wi_of(u: f64, front: bool) -> Vec3 {
    let (c, s) = (u.sqrt(), (1.0 - u).max(0.0).sqrt());
    Vec3::new(s, 0.0, if front { c } else { -c })
}

/// The hemispherical integral of `f(wo)` over the exit hemisphere on the side `sign` (+1 or
/// -1) by a fine composite Gauss-Legendre rule in `(cos^2 theta, phi)`, independent of the
/// Klems basis: 16 nodes in `u` on each of 60 panels 1.5 degrees wide in theta, 96 nodes in
/// `phi` on `[0, pi]` (the integrand is symmetric under `y -> -y`). `f` is the BSDF times
/// `|cos theta_o|` (per unit solid angle).
fn hemisphere(f: impl Fn(Vec3) -> f64, sign: f64) -> f64 {
    let gl = GaussLegendre::new(16);
    let gp = GaussLegendre::new(96);
    let edges: Vec<f64> = (0..=60)
        .rev()
        .map(|k| (1.5 * k as f64).to_radians().cos().powi(2))
        .collect();
    gl.integrate_panels(&edges, |u| {
        let (c, s) = (u.sqrt(), (1.0 - u).max(0.0).sqrt());
        // d omega = du dphi / (2 cos theta).
        2.0 * gp.integrate(0.0, std::f64::consts::PI, |phi| {
            let wo = Vec3::new(s * phi.cos(), s * phi.sin(), sign * c);
            if c > 0.0 { f(wo) / (2.0 * c) } else { 0.0 }
        })
    })
}

/// stfit's single-scattering albedo of the interface for light spread over incident patch `i`:
/// the hemispherical integral of `f_cos` ([`hemisphere`]) at Gauss-Legendre nodes over the
/// patch. Returns (same side, other side).
fn interface_albedo(model: &ExportModel, front: bool, i: usize) -> [f64; 2] {
    let bsdf = model.single();
    let mut a = [0.0; 2];
    for (u, w) in ring_nodes(i) {
        let wi = wi_of(u, front);
        let side = wi.z.signum();
        a[0] += w * hemisphere(|wo| bsdf.f_cos(wi, wo), side);
        a[1] += w * hemisphere(|wo| bsdf.f_cos(wi, wo), -side);
    }
    a
}

/// stfit's albedo of a random-walk layer (the pane) for light spread over incident patch `i`:
/// `n` walks of the layer at each node. Returns (same side, its standard error, other side,
/// its standard error).
fn walk_albedo(layer: &impl Layer, front: bool, i: usize, n: u64) -> [f64; 4] {
    let mut a = [0.0; 4];
    for (k, (u, w)) in ring_nodes(i).into_iter().enumerate() {
        let e = albedo(layer, wi_of(u, front), n, 100 + k as u64);
        a[0] += w * e[0];
        a[1] += w * w * e[1] * e[1];
        a[2] += w * e[2];
        a[3] += w * w * e[3] * e[3];
    }
    [a[0], a[1].sqrt(), a[2], a[3].sqrt()]
}

/// Writes the model's file, runs checkBSDF on it and compares; `albedo_of(front, patch)`
/// gives stfit's own (same side, error, other side, error) for that patch.
fn check(
    rad: &Radiance,
    model: &ExportModel,
    opts: &RadianceOptions,
    albedo_of: impl Fn(bool, usize) -> [f64; 4],
) -> KlemsBsdf {
    let (xml, bsdf) = radiance::export(model, opts, "test").unwrap();
    let dir = CaseDir::new("checkbsdf");
    let file = dir.file("bsdf.xml", xml);
    let out = rad.command("checkBSDF").arg(&file).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "checkBSDF rejected {}: {}{}",
        file.display(),
        stdout,
        String::from_utf8_lossy(&out.stderr)
    );
    for (name, radiance) in totals(&stdout) {
        let block = bsdf.block(name).unwrap();
        let (i, &ours) = block
            .totals
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .unwrap();
        // (a) Radiance reads our matrices: its value is ours up to its 0.1% printing and its
        // 6e-4 position-specific perturbation (mBSDF_color in bsdf_m.c).
        let printing = 5e-4 + 6e-4 * ours + 1e-9;
        assert!(
            (radiance - ours).abs() <= printing,
            "{:?} {name}: checkBSDF {radiance} vs file {ours}",
            opts.layer
        );
        // (b) stfit's albedo of the same model at that patch, without the basis. The maximum
        // over the <= 24 patches of a ring exceeds its expectation by about 2.5 standard errors
        // at most; 4 covers it.
        let front = name.ends_with("Front");
        let a = albedo_of(front, i);
        let (value, se) = if name.starts_with("Reflection") {
            (a[0], a[1])
        } else {
            (a[2], a[3])
        };
        let quad = bsdf.quadrature_error().map_or(0.0, |e| e.max_total);
        let tol = printing + quad + 4.0 * block.totals_stderr[i] + 3.0 * se;
        println!(
            "{:?} {name}: checkBSDF {radiance:.4}, file {ours:.5} (patch {i}), stfit albedo {value:.5} (stderr {se:.1e}), |difference| {:.1e}, tolerance {tol:.1e}",
            opts.layer,
            (radiance - value).abs()
        );
        assert!(
            (radiance - value).abs() <= tol,
            "{:?} {name}: checkBSDF {radiance} vs stfit albedo {value} (tolerance {tol})",
            opts.layer
        );
    }
    bsdf
}

#[test]
fn checkbsdf_reads_exports_and_matches_stfit_albedo() {
    let Some(rad) = stfit_test_support::radiance("radiance_checkbsdf") else {
        return;
    };
    let fits = FitsFile::read(&project_root().join("fits/example-fits.json")).unwrap();
    let fit = fits
        .fits
        .iter()
        .find(|f| f.sample == "frosted" && f.model.gamma.is_free())
        .unwrap();
    let model = ExportModel::from_fit(fit).unwrap();

    // The single rough interface, by deterministic quadrature (a rule lighter than the
    // default, for speed; its stated error is larger).
    let interface = RadianceOptions {
        layer: LayerKind::Interface,
        rule: QuadratureRule {
            theta_incident: 6,
            theta_exit: 12,
            azimuth: 8,
        },
        ..Default::default()
    };
    let bsdf = check(&rad, &model, &interface, |front, i| {
        let a = interface_albedo(&model, front, i);
        [a[0], 0.0, a[1], 0.0]
    });
    assert_eq!(
        bsdf.max_total_stderr(),
        0.0,
        "a quadrature has no Monte Carlo error"
    );

    // The lossless pane, by random walks: every walk leaves through one side with weight 1.
    let pane = RadianceOptions {
        walks_per_patch: 16_384,
        ..Default::default()
    };
    let layer = Pane::new(RoughFace::all_orders(&model).unwrap(), model.eta(), 0.0).unwrap();
    let bsdf = check(&rad, &model, &pane, |front, i| {
        walk_albedo(&layer, front, i, 40_000)
    });
    let (tf, rf) = (
        bsdf.block("Transmission Front").unwrap(),
        bsdf.block("Reflection Front").unwrap(),
    );
    for i in 0..klems::N_PATCHES {
        assert!(
            (tf.totals[i] + rf.totals[i] - 1.0).abs() < 1e-9,
            "patch {i}"
        );
    }

    // The interface of an all-orders fit: order 1 by quadrature plus orders >= 2 by walks. It
    // conserves energy, so the deterministic and the Monte Carlo parts must add up to 1 at
    // every patch within the stated error.
    let all = ExportModel::new(
        Model {
            masking: Masking::Correlated,
            orders: ScatteringOrders::All,
            walks: Some(1000),
            seed: Some(1),
            ..fit.model
        },
        "frosted, all orders",
    )
    .unwrap();
    let hybrid = RadianceOptions {
        walks_per_patch: 4096,
        ..interface
    };
    let (xml, bsdf) = radiance::export(&all, &hybrid, "all").unwrap();
    let dir = CaseDir::new("checkbsdf-all");
    let out = rad
        .command("checkBSDF")
        .arg(dir.file("all.xml", xml))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let quad = bsdf.quadrature_error().unwrap().max_total;
    let mut worst: f64 = 0.0;
    for (t, r) in [
        ("Transmission Front", "Reflection Front"),
        ("Transmission Back", "Reflection Back"),
    ] {
        let (t, r) = (bsdf.block(t).unwrap(), bsdf.block(r).unwrap());
        for i in 0..klems::N_PATCHES {
            let e = (t.totals[i] + r.totals[i] - 1.0).abs();
            let tol = 2.0 * quad + 4.0 * (t.totals_stderr[i] + r.totals_stderr[i]);
            worst = worst.max(e / tol);
            assert!(
                e <= tol,
                "patch {i}: T + R = {} (tolerance {tol})",
                t.totals[i] + r.totals[i]
            );
        }
    }
    println!("all-orders interface: largest |T + R - 1| over patches {worst:.2} of its tolerance");
}
