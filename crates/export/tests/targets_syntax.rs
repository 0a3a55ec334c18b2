//! The exported scene snippets parse as their renderers' syntax and name only parameters those
//! renderers define; GGX fits round-trip exactly to GGX targets.

use stfit_core::bsdf::Masking;
use stfit_core::ndf::{AnyNdf, Ggx, StudentT};
use stfit_core::walk::ScatteringOrders;
use stfit_export::ExportModel;
use stfit_export::targets::{self, Target};

/// Parameters of Mitsuba 3's `roughdielectric`, from mitsuba-renderer/mitsuba3,
/// src/bsdfs/roughdielectric.cpp (its `pluginparameters` and `Properties` reads).
const MITSUBA_ROUGHDIELECTRIC: [&str; 9] = [
    "int_ior",
    "ext_ior",
    "specular_reflectance",
    "specular_transmittance",
    "distribution",
    "alpha",
    "alpha_u",
    "alpha_v",
    "sample_visible",
];

/// Parameters of pbrt-v4's `dielectric` material, from mmp/pbrt-v4, src/pbrt/materials.cpp
/// (`DielectricMaterial::Create`; `normalmap` is read for every material by the scene loader).
const PBRT_DIELECTRIC: [&str; 7] = [
    "eta",
    "roughness",
    "uroughness",
    "vroughness",
    "remaproughness",
    "displacement",
    "normalmap",
];

fn model(ndf: AnyNdf) -> ExportModel {
    ExportModel::new(
        ndf,
        1.51,
        Masking::Separable,
        ScatteringOrders::Single,
        0.98,
        "test fit",
    )
    .unwrap()
}

fn student_t() -> ExportModel {
    model(StudentT::new(0.3, 2.6).unwrap().into())
}

/// The Mitsuba 3 export is one well-formed XML `bsdf` element of type roughdielectric whose
/// children name only roughdielectric parameters, with the types Mitsuba expects.
#[test]
fn mitsuba3_xml_parses_and_names_only_roughdielectric_parameters() {
    let e = targets::export(Target::Mitsuba3, &student_t(), "st").unwrap();
    let xml = &e.files.iter().find(|f| f.extension == "xml").unwrap().text;
    let doc = roxmltree::Document::parse(xml).expect("well-formed XML");
    let bsdf = doc.root_element();
    assert_eq!(bsdf.tag_name().name(), "bsdf");
    assert_eq!(bsdf.attribute("type"), Some("roughdielectric"));
    let mut names = Vec::new();
    for c in bsdf.children().filter(|n| n.is_element()) {
        let name = c.attribute("name").unwrap();
        assert!(
            MITSUBA_ROUGHDIELECTRIC.contains(&name),
            "unknown parameter {name}"
        );
        let value = c.attribute("value").unwrap();
        match c.tag_name().name() {
            "float" => assert!(value.parse::<f64>().unwrap().is_finite()),
            "string" => assert!(["ggx", "beckmann"].contains(&value), "{value}"),
            t => panic!("unexpected element {t}"),
        }
        names.push(name);
    }
    assert_eq!(names, ["distribution", "alpha", "int_ior", "ext_ior"]);
    // The Python dict names the same parameters.
    let py = &e.files.iter().find(|f| f.extension == "py").unwrap().text;
    for n in &names {
        assert!(py.contains(&format!("'{n}':")), "{n} missing from the dict");
    }
}

/// A token of pbrt's scene syntax.
#[derive(Debug, PartialEq)]
enum Tok {
    Ident(String),
    Str(String),
    Open,
    Close,
    Num(f64),
    Bool(bool),
}

/// pbrt's lexical rules: `#` comments to the end of the line, quoted strings, brackets, numbers,
/// bare identifiers (directives) and the bare words `true`/`false` in arrays.
fn lex(text: &str) -> Vec<Tok> {
    let mut toks = Vec::new();
    for line in text.lines() {
        let line = line.split('#').next().unwrap();
        let mut rest = line.trim_start();
        while !rest.is_empty() {
            let (tok, len) = if let Some(r) = rest.strip_prefix('"') {
                let end = r.find('"').expect("unterminated string");
                (Tok::Str(r[..end].to_string()), end + 2)
            } else if rest.starts_with('[') {
                (Tok::Open, 1)
            } else if rest.starts_with(']') {
                (Tok::Close, 1)
            } else {
                let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
                let w = &rest[..end];
                let t = match w {
                    "true" => Tok::Bool(true),
                    "false" => Tok::Bool(false),
                    _ => w
                        .parse()
                        .map_or_else(|_| Tok::Ident(w.to_string()), Tok::Num),
                };
                (t, end)
            };
            toks.push(tok);
            rest = rest[len..].trim_start();
        }
    }
    toks
}

/// The pbrt-v4 export is one `Material "dielectric"` directive followed by typed parameters
/// (`"type name" [ values ]`) that pbrt-v4's dielectric defines.
#[test]
fn pbrt_v4_line_parses_and_names_only_dielectric_parameters() {
    let e = targets::export(Target::PbrtV4, &student_t(), "st").unwrap();
    let toks = lex(&e.files[0].text);
    assert_eq!(toks[0], Tok::Ident("Material".into()));
    assert_eq!(toks[1], Tok::Str("dielectric".into()));
    let mut k = 2;
    let mut names = Vec::new();
    while k < toks.len() {
        let Tok::Str(decl) = &toks[k] else {
            panic!(
                "expected a parameter declaration at token {k}: {:?}",
                toks[k]
            )
        };
        let mut parts = decl.split_whitespace();
        let (ty, name) = (parts.next().unwrap(), parts.next().unwrap());
        assert!(PBRT_DIELECTRIC.contains(&name), "unknown parameter {name}");
        assert_eq!(toks[k + 1], Tok::Open);
        match (ty, &toks[k + 2]) {
            ("float", Tok::Num(v)) => assert!(v.is_finite() && *v >= 0.0),
            ("bool", Tok::Bool(_)) => {}
            other => panic!("bad value for {name}: {other:?}"),
        }
        assert_eq!(toks[k + 3], Tok::Close);
        names.push(name.to_string());
        k += 4;
    }
    assert_eq!(names, ["eta", "roughness", "remaproughness"]);
}

/// The other XML targets are well-formed too.
#[test]
fn appleseed_and_openpbr_exports_are_well_formed_xml() {
    for t in [Target::Appleseed, Target::OpenPbr] {
        let e = targets::export(t, &student_t(), "st").unwrap();
        roxmltree::Document::parse(&e.files[0].text)
            .unwrap_or_else(|err| panic!("{}: {err}", t.name()));
    }
}

/// A GGX fit exported to a GGX target keeps alpha to 1e-6 in each target's own convention:
/// Mitsuba's alpha, pbrt-v4's roughness = alpha^2 (alpha = sqrt(roughness)), Cycles' and
/// OpenPBR's roughness = sqrt(alpha) (alpha = roughness^2), appleseed's roughness =
/// sqrt(alpha).
#[test]
fn ggx_fit_round_trips_to_ggx_targets() {
    let alpha = 0.36005;
    let m = model(Ggx::new(alpha).unwrap().into());
    let value = |t: Target| {
        targets::export(t, &m, "g")
            .unwrap()
            .translation
            .unwrap()
            .params[0]
            .value
    };
    assert!((value(Target::Mitsuba3) - alpha).abs() < 1e-6);
    assert!((value(Target::PbrtV4).sqrt() - alpha).abs() < 1e-6);
    assert!((value(Target::Cycles).powi(2) - alpha).abs() < 1e-6);
    assert!((value(Target::Appleseed).powi(2) - alpha).abs() < 1e-6);
    assert!((value(Target::OpenPbr).powi(2) - alpha).abs() < 1e-6);
    // Mitsuba's GGX with separable exact G1 is the fitted model itself: no translation error.
    let t = targets::export(Target::Mitsuba3, &m, "g")
        .unwrap()
        .translation
        .unwrap();
    assert!(t.rmse < 1e-12 && t.exact_ndf, "{t:?}");
}

/// appleseed maps (alpha, gamma) exactly inside its range and clamps gamma outside it with a
/// warning.
#[test]
fn appleseed_maps_student_t_exactly_and_clamps_gamma() {
    use stfit_export::targets::appleseed::gamma_of_falloff;
    let e = targets::export(Target::Appleseed, &student_t(), "st").unwrap();
    let t = e.translation.unwrap();
    assert!((t.value("roughness").unwrap().powi(2) - 0.3).abs() < 1e-9);
    assert!((gamma_of_falloff(t.value("highlight_falloff").unwrap()) - 2.6).abs() < 1e-9);
    assert!(e.warnings.is_empty(), "{:?}", e.warnings);
    let narrow = model(StudentT::new(0.3, 1.505).unwrap().into());
    let e = targets::export(Target::Appleseed, &narrow, "st").unwrap();
    assert!(
        e.warnings.iter().any(|w| w.contains("clamped")),
        "{:?}",
        e.warnings
    );
    assert_eq!(e.translation.unwrap().value("highlight_falloff"), Some(0.0));
}
