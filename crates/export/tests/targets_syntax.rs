//! The exported scene snippets parse as their renderers' syntax and name only parameters those
//! renderers define; GGX fits round-trip exactly to GGX targets.

use std::process::Command;

use stfit_export::ExportModel;
use stfit_export::targets::{self, Target};
use stfit_fit::{Gamma, Model, ModelKind};
use stfit_test_support::{CaseDir, under_ci};

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

/// Parameters of V-Ray's `BRDFVRayMtl`, from ChaosGroup/vray_for_blender_addon,
/// python_exporter/plugins_desc/BRDF/BRDFVRayMtl.json (the subset a glass uses), and of
/// `MtlSingleBRDF` (its `brdf`).
const VRAY_BRDFVRAYMTL: [&str; 20] = [
    "brdf_type",
    "diffuse",
    "reflect",
    "reflect_glossiness",
    "hilight_glossiness",
    "hilight_glossiness_lock",
    "gtr_gamma",
    "fresnel",
    "fresnel_ior",
    "fresnel_ior_lock",
    "metalness",
    "gtr_energy_compensation",
    "refract",
    "refract_ior",
    "refract_glossiness",
    "refract_thin_walled",
    "option_use_roughness",
    "option_double_sided",
    "option_glossy_fresnel",
    "roughness",
];

fn model(kind: ModelKind, alpha: f64, gamma: Gamma) -> ExportModel {
    ExportModel::new(Model::single(kind, alpha, gamma, 0.98), "test fit").unwrap()
}

fn student_t() -> ExportModel {
    model(ModelKind::StudentT, 0.3, Gamma::Free(2.6))
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
    // Mitsuba loads a file (mi.load_file, <include>) only if its root carries a version.
    assert_eq!(bsdf.attribute("version"), Some("3.0.0"));
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

/// The parameters of one pbrt-v4 `MakeNamedMaterial` directive from `toks[k]` on: its name,
/// the names of its parameters after `"string type" [ "dielectric" ]` (each `"type name" [ value
/// ]` of a type pbrt-v4's dielectric reads), and the index of the next directive.
fn pbrt_named_dielectric(toks: &[Tok], mut k: usize) -> (String, Vec<String>, usize) {
    assert_eq!(toks[k], Tok::Ident("MakeNamedMaterial".into()), "at {k}");
    let Tok::Str(id) = &toks[k + 1] else {
        panic!("expected the material's name: {:?}", toks[k + 1])
    };
    assert_eq!(
        toks[k + 2..k + 6],
        [
            Tok::Str("string type".into()),
            Tok::Open,
            Tok::Str("dielectric".into()),
            Tok::Close
        ]
    );
    k += 6;
    let mut names = Vec::new();
    while k < toks.len() {
        let Tok::Str(decl) = &toks[k] else {
            break;
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
    (id.clone(), names, k)
}

/// The pbrt-v4 export is one `MakeNamedMaterial "ID" "string type" [ "dielectric" ]` directive,
/// named by the fit's identifier, followed by typed parameters (`"type name" [ values ]`) that
/// pbrt-v4's dielectric defines.
#[test]
fn pbrt_v4_line_parses_and_names_only_dielectric_parameters() {
    let e = targets::export(Target::PbrtV4, &student_t(), "st").unwrap();
    let toks = lex(&e.files[0].text);
    let (id, names, end) = pbrt_named_dielectric(&toks, 0);
    assert_eq!(id, "st");
    assert_eq!(names, ["eta", "roughness", "remaproughness"]);
    assert_eq!(end, toks.len());
    assert!(
        e.files[0]
            .text
            .contains("# select it for the shapes that follow with: NamedMaterial \"st\"\n"),
        "{}",
        e.files[0].text
    );
}

/// Several fits in one pbrt-v4 file define one named material each, under its fit's name, and
/// no anonymous `Material`: in pbrt-v4 a `Material` directive replaces the current material
/// (mmp/pbrt-v4, src/pbrt/scene.cpp, `BasicSceneBuilder::Material` sets
/// `graphicsState.currentMaterialIndex`), so of several fits' `Material` lines only the last
/// would ever reach a shape, whereas `BasicSceneBuilder::MakeNamedMaterial` (same file) adds
/// each to the scene's named materials for `NamedMaterial "ID"` (and exits on a name defined
/// twice, which distinct fit identifiers avoid).
#[test]
fn pbrt_v4_file_of_several_fits_defines_one_named_material_per_fit() {
    let ids = ["frosted_ggx", "frosted_student_t", "etched_beckmann"];
    let models = [
        model(ModelKind::Ggx, 0.19, Gamma::NotApplicable),
        student_t(),
        model(ModelKind::Beckmann, 0.44, Gamma::NotApplicable),
    ];
    let exports: Vec<_> = ids
        .iter()
        .zip(&models)
        .map(|(id, m)| targets::export(Target::PbrtV4, m, id).unwrap())
        .collect();
    let joined = targets::join(&exports);
    assert_eq!(joined.len(), 1);
    let toks = lex(&joined[0].text);
    assert!(!toks.contains(&Tok::Ident("Material".into())));
    let mut k = 0;
    let mut defined = Vec::new();
    while k < toks.len() {
        let (id, names, next) = pbrt_named_dielectric(&toks, k);
        assert_eq!(names, ["eta", "roughness", "remaproughness"]);
        defined.push(id);
        k = next;
    }
    assert_eq!(defined, ids);
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
    let m = model(ModelKind::Ggx, alpha, Gamma::NotApplicable);
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
    // V-Ray: alpha = (1 - glossiness)^2 at gtr_gamma 2.
    let v = targets::export(Target::VRay, &m, "g")
        .unwrap()
        .translation
        .unwrap();
    assert!(((1.0 - v.params[0].value).powi(2) - alpha).abs() < 1e-6);
    assert_eq!(v.value("gtr_gamma"), Some(2.0));
    assert!(v.exact_ndf);
    // Mitsuba's GGX with separable exact G1 is the fitted model itself: no translation error.
    let t = targets::export(Target::Mitsuba3, &m, "g")
        .unwrap()
        .translation
        .unwrap();
    assert!(t.rmse < 1e-12 && t.exact_ndf, "{t:?}");
}

/// appleseed's glass_bsdf is GGX only (appleseedhq/appleseed, glassbsdf.cpp,
/// `GlassBSDFImpl`, since "Use GGX for all microfacet shading models", issue 2550): every
/// parameter written is one of the inputs it declares (no `mdf`, no `highlight_falloff`, which it
/// would ignore and render GGX), and a Student-T fit is translated by fitting the GGX roughness,
/// not mapped as if appleseed had the Student-T distribution.
#[test]
fn appleseed_writes_only_glass_bsdf_inputs_and_fits_student_t_with_ggx() {
    const DECLARED: [&str; 14] = [
        "surface_transmittance",
        "surface_transmittance_multiplier",
        "reflection_tint",
        "refraction_tint",
        "roughness",
        "anisotropy",
        "ior",
        "volume_transmittance",
        "volume_transmittance_distance",
        "volume_absorption",
        "volume_density",
        "volume_scale",
        "energy_compensation",
        "volume_parameterization",
    ];
    let e = targets::export(Target::Appleseed, &student_t(), "st").unwrap();
    let doc = roxmltree::Document::parse(&e.files[0].text).unwrap();
    let names: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("parameter"))
        .map(|n| n.attribute("name").unwrap())
        .collect();
    assert!(names.contains(&"roughness"), "{names:?}");
    for n in &names {
        assert!(DECLARED.contains(n), "glass_bsdf does not read {n}");
    }
    let t = e.translation.unwrap();
    assert!(!t.exact_ndf, "{t:?}");
    assert_eq!(t.value("highlight_falloff"), None);
    let fitted = t.value("roughness").unwrap();
    assert!(fitted > 0.0 && fitted <= 1.0, "{fitted}");
    // Below appleseed's alpha floor (0.001) it renders alpha 0.001: the reported error is that
    // of what renders, not 0, and the file says so.
    let sharp = model(ModelKind::Ggx, 3e-4, Gamma::NotApplicable);
    let e = targets::export(Target::Appleseed, &sharp, "g").unwrap();
    let t = e.translation.unwrap();
    assert!(t.rmse > 1e-3, "{t:?}");
    assert!(
        e.warnings.iter().any(|w| w.contains("floor")),
        "{:?}",
        e.warnings
    );
}

/// The translation searches alpha down to 1e-4 in every renderer's parameter: pbrt-v4's
/// `roughness = alpha^2` had been stopped at 1e-4 (alpha 0.01), so a Student-T fit at alpha
/// 0.005 got a 10 times worse GGX than Cycles', whose masking and NDF are the same.
#[test]
fn smooth_fits_translate_alike_whatever_the_parameter_mapping() {
    let m = model(ModelKind::StudentT, 0.005, Gamma::Free(3.0));
    let translated = |t: Target| targets::export(t, &m, "s").unwrap().translation.unwrap();
    let (pbrt, cycles) = (translated(Target::PbrtV4), translated(Target::Cycles));
    let (a_pbrt, a_cycles) = (pbrt.params[0].value.sqrt(), cycles.params[0].value.powi(2));
    assert!(a_pbrt < 0.0099, "pbrt-v4 alpha {a_pbrt}");
    assert!(
        (a_pbrt / a_cycles - 1.0).abs() < 1e-2,
        "{a_pbrt} vs {a_cycles}"
    );
    assert!(
        (pbrt.rmse / cycles.rmse - 1.0).abs() < 1e-2,
        "{pbrt:?} vs {cycles:?}"
    );
}

/// A `.vrscene` block: plugin type, name and `key=value` parameters.
type VrsceneBlock = (String, String, Vec<(String, String)>);

/// A `.vrscene` fragment: `Plugin name { key=value; ... }` blocks with `//` comments.
fn vrscene_blocks(text: &str) -> Vec<VrsceneBlock> {
    let body: String = text
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n");
    let mut blocks = Vec::new();
    let mut rest = body.as_str();
    while let Some(open) = rest.find('{') {
        let head: Vec<&str> = rest[..open].split_whitespace().collect();
        assert_eq!(head.len(), 2, "a block is `Type name {{`: {head:?}");
        let close = rest[open..].find('}').expect("a closing brace") + open;
        let params = rest[open + 1..close]
            .split(';')
            .map(str::trim)
            .filter(|p| !p.is_empty())
            .map(|p| {
                let (k, v) = p.split_once('=').expect("key=value");
                (k.trim().to_string(), v.trim().to_string())
            })
            .collect();
        blocks.push((head[0].to_string(), head[1].to_string(), params));
        rest = &rest[close + 1..];
    }
    assert!(rest.trim().is_empty(), "trailing text: {rest}");
    blocks
}

/// The V-Ray export is a BRDFVRayMtl naming only parameters V-Ray defines, with numbers,
/// colours and booleans where V-Ray takes them, and a MtlSingleBRDF using it.
#[test]
fn vray_vrscene_parses_and_names_only_brdfvraymtl_parameters() {
    let e = targets::export(Target::VRay, &student_t(), "st").unwrap();
    let blocks = vrscene_blocks(&e.files[0].text);
    assert_eq!(blocks.len(), 2);
    let (ty, name, params) = &blocks[0];
    assert_eq!((ty.as_str(), name.as_str()), ("BRDFVRayMtl", "st"));
    for (k, v) in params {
        assert!(
            VRAY_BRDFVRAYMTL.contains(&k.as_str()),
            "unknown parameter {k}"
        );
        if v.starts_with("AColor(") {
            let inner = v.trim_start_matches("AColor(").trim_end_matches(')');
            assert_eq!(
                inner
                    .split(',')
                    .filter_map(|c| c.trim().parse::<f64>().ok())
                    .count(),
                4
            );
        } else {
            assert!(v.parse::<f64>().unwrap().is_finite(), "{k}={v}");
        }
    }
    let get = |k: &str| {
        params
            .iter()
            .find(|(p, _)| p == k)
            .map(|(_, v)| v.parse::<f64>().unwrap())
    };
    assert_eq!(get("brdf_type"), Some(4.0));
    let g = get("reflect_glossiness").unwrap();
    assert!((0.0..1.0).contains(&g) && get("refract_glossiness") == Some(g));
    assert!((0.1..=10.0).contains(&get("gtr_gamma").unwrap()));
    assert_eq!(blocks[1].0, "MtlSingleBRDF");
    assert_eq!(blocks[1].2, vec![("brdf".to_string(), "st".to_string())]);
}

/// The Python outputs (Mitsuba 3's dict, Cycles' script) are valid Python: Python 3's own
/// parser reads them. Without python3 the test says it did not run (a failure under CI=true).
#[test]
fn python_exports_parse_as_python() {
    if Command::new("python3").arg("--version").output().is_err() {
        assert!(!under_ci(), "CI=true but python3 is missing");
        eprintln!("python_exports_parse_as_python: did not run for want of python3");
        return;
    }
    let dir = CaseDir::new("python-exports");
    for t in [Target::Mitsuba3, Target::Cycles] {
        let e = targets::export(t, &student_t(), "st").unwrap();
        assert_parses_as_python(&dir, t, &e);
    }
}

/// The first GGX fit of the example fits with a hostile sample name and data file: hyphens in
/// runs of three and at the end (XML forbids `--` in a comment), and a data file name with a
/// line break, a control character and code after it (a hand-edited fits file).
fn hostile_fit() -> stfit_fit::FitResult {
    let mut fit = example_fits()
        .into_iter()
        .find(|f| f.model.kind == ModelKind::Ggx)
        .unwrap();
    fit.sample = "a---b-->c-".into();
    fit.data = Some("x---\nimport os\u{1}\r\n// -->".into());
    fit
}

/// Free texts of a fit (sample, data file) cannot break a file's syntax: the XML files stay
/// well-formed and every line of the other files that is not a comment is the target's own
/// code (no text of the fit's data file outside a comment).
#[test]
fn hostile_sample_and_data_names_stay_inside_comments() {
    let fit = hostile_fit();
    // The interface by quadrature: the Radiance file without walks.
    let opts = stfit_export::radiance::RadianceOptions {
        layer: stfit_export::radiance::LayerKind::Interface,
        ..Default::default()
    };
    for t in Target::ALL {
        let e = stfit_export::export_fit(&fit, t, &opts).unwrap();
        for f in &e.files {
            let what = format!("{} .{}", t.name(), f.extension);
            match f.extension {
                "xml" | "mtlx" => {
                    roxmltree::Document::parse(&f.text)
                        .unwrap_or_else(|err| panic!("{what}: {err}\n{}", f.text));
                }
                _ => {
                    let comment = if f.extension == "vrscene" { "//" } else { "#" };
                    for line in f.text.lines() {
                        assert!(
                            line.trim_start().starts_with(comment) || !line.contains("import os"),
                            "{what}: the fit's data escaped its comment: {line:?}"
                        );
                    }
                }
            }
        }
    }
}

/// Several fits in one file: Mitsuba 3's XML is one document, a `scene` with the scene format's
/// version holding every fit's `bsdf` (as Mitsuba's `<include>` merges a scene's children), and
/// OpenPBR's one MaterialX document holding every fit's shader and material; a fit's comment
/// stays with its element. Texts that are not XML documents follow one another.
#[test]
fn several_fits_in_one_file_make_one_document() {
    let ids = ["a_ggx", "b_student_t", "c_beckmann"];
    let models = [
        model(ModelKind::Ggx, 0.2, Gamma::NotApplicable),
        student_t(),
        model(ModelKind::Beckmann, 0.4, Gamma::NotApplicable),
    ];
    for t in [Target::Mitsuba3, Target::OpenPbr, Target::PbrtV4] {
        let exports: Vec<_> = models
            .iter()
            .zip(ids)
            .map(|(m, id)| targets::export(t, m, id).unwrap())
            .collect();
        let joined = stfit_export::join(&exports);
        let file = &joined[0];
        let what = format!("{} .{}", t.name(), file.extension);
        let elements = |tag: &str| -> Vec<String> {
            let doc = roxmltree::Document::parse(&file.text)
                .unwrap_or_else(|e| panic!("{what}: {e}\n{}", file.text));
            let root = doc.root_element();
            match t {
                Target::Mitsuba3 => {
                    assert_eq!(root.tag_name().name(), "scene", "{what}");
                    assert_eq!(root.attribute("version"), Some("3.0.0"), "{what}");
                }
                _ => assert_eq!(root.tag_name().name(), "materialx", "{what}"),
            }
            let comments = root.children().filter(|n| n.is_comment()).count();
            assert_eq!(comments, ids.len(), "{what}: one comment per fit");
            root.children()
                .filter(|n| n.tag_name().name() == tag)
                .map(|n| {
                    n.attribute("id")
                        .or(n.attribute("name"))
                        .unwrap()
                        .to_string()
                })
                .collect()
        };
        match t {
            Target::Mitsuba3 => assert_eq!(elements("bsdf"), ids, "{what}"),
            Target::OpenPbr => assert_eq!(elements("open_pbr_surface"), ids, "{what}"),
            _ => {
                let texts: Vec<&str> = exports.iter().map(|e| e.files[0].text.as_str()).collect();
                assert_eq!(file.text, texts.join("\n"), "{what}");
            }
        }
    }
}

/// A sample named by a number (`2024`) still gives valid Python: its identifier, a Python
/// variable (Mitsuba 3) and function name (Cycles), does not start with a digit.
#[test]
fn python_exports_of_a_sample_named_by_a_number_parse_as_python() {
    if Command::new("python3").arg("--version").output().is_err() {
        assert!(!under_ci(), "CI=true but python3 is missing");
        eprintln!("python_exports_of_a_sample_named_by_a_number: did not run for want of python3");
        return;
    }
    let mut fit = hostile_fit();
    fit.sample = "2024".into();
    let dir = CaseDir::new("python-exports-number");
    let opts = stfit_export::radiance::RadianceOptions::default();
    for t in [Target::Mitsuba3, Target::Cycles] {
        let e = stfit_export::export_fit(&fit, t, &opts).unwrap();
        assert_parses_as_python(&dir, t, &e);
    }
}

/// Roughness below what a renderer renders as rough is said: pbrt-v4 scatters alpha < 1e-3 as
/// a smooth dielectric, Mitsuba 3 raises alpha to 1e-4. Alpha 1e-3 itself (the fits' own
/// floor) is rough in pbrt, in its single precision too.
#[test]
fn renderer_roughness_floors_are_warned() {
    let warned = |t: Target, alpha: f64, what: &str| {
        let m = model(ModelKind::Ggx, alpha, Gamma::NotApplicable);
        let e = targets::export(t, &m, "x").unwrap();
        e.warnings.iter().any(|w| w.contains(what))
    };
    assert!(warned(Target::PbrtV4, 5e-4, "perfectly smooth"));
    assert!(!warned(Target::PbrtV4, 1e-3, "perfectly smooth"));
    assert!(!warned(Target::PbrtV4, 0.2, "perfectly smooth"));
    assert!(warned(Target::Mitsuba3, 5e-5, "renders alpha 0.0001"));
    assert!(!warned(Target::Mitsuba3, 1e-3, "renders alpha"));
    // A near-smooth Student-T fit translated below pbrt's threshold.
    let st = model(ModelKind::StudentT, 1e-3, Gamma::Fixed(10.0));
    let e = targets::export(Target::PbrtV4, &st, "x").unwrap();
    let alpha = e.translation.unwrap().params[0].value.sqrt();
    assert!(alpha < 1e-3, "{alpha}");
    assert!(e.warnings.iter().any(|w| w.contains("perfectly smooth")));
}

/// A translation parameter that ends on a bound of its range is said: of the example
/// Beckmann fits, frosted's V-Ray `gtr_gamma` ends on its bound 10 (etched's and ground's,
/// 8.13 and 9.12, inside).
#[test]
fn translations_ending_on_a_bound_are_warned() {
    let fits = example_fits();
    let opts = stfit_export::radiance::RadianceOptions::default();
    let warned = |sample: &str| {
        let fit = find(&fits, sample, ModelKind::Beckmann);
        let e = stfit_export::export_fit(fit, Target::VRay, &opts).unwrap();
        let says = |w: &str| w.starts_with("gtr_gamma ") && w.contains("ended on a bound");
        assert_eq!(
            e.warnings.iter().any(|w| says(w)),
            e.files[0]
                .text
                .lines()
                .any(|l| l.strip_prefix("// warning: ").is_some_and(says)),
            "{sample}: the warning is in the file as on stderr"
        );
        e.warnings.iter().any(|w| says(w))
    };
    assert!(warned("frosted"));
    assert!(!warned("etched"));
    assert!(!warned("ground"));
}

/// OpenPBR's haze is written only where it gains as the reference MaterialX graph renders it
/// too: for the example ground Student-T fit the specification's reading gains (rmse 0.0177
/// against 0.0244 for one lobe), but the graph, which hazes reflection only, renders those
/// values at 0.0329, so one lobe is written.
#[test]
fn openpbr_haze_is_written_only_where_the_reference_graph_gains_too() {
    let fits = example_fits();
    let opts = stfit_export::radiance::RadianceOptions::default();
    let fit = find(&fits, "ground", ModelKind::StudentT);
    let e = stfit_export::export_fit(fit, Target::OpenPbr, &opts).unwrap();
    let text = &e.files[0].text;
    assert!(!text.contains("\"specular_haze\""), "{text}");
    assert!(text.contains("haze not written"), "{text}");
    assert_eq!(e.translation.unwrap().params.len(), 1);
}

/// Asserts that the `.py` file of export `e` to `t` parses as Python (`python3`'s `ast`),
/// written into `dir`.
fn assert_parses_as_python(dir: &CaseDir, t: Target, e: &targets::Export) {
    let py = &e.files.iter().find(|f| f.extension == "py").unwrap().text;
    let path = dir.file(&format!("{}.py", t.name()), py);
    let out = Command::new("python3")
        .args(["-c", "import ast, sys; ast.parse(open(sys.argv[1]).read())"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}: {}",
        t.name(),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The fits of `fits/example-fits.json`.
fn example_fits() -> Vec<stfit_fit::FitResult> {
    let path = stfit_test_support::project_root().join("fits/example-fits.json");
    stfit_fit::FitsFile::read(&path).unwrap().fits
}

/// The fit of `sample` and `kind` (gamma free) among `fits`.
fn find<'a>(
    fits: &'a [stfit_fit::FitResult],
    sample: &str,
    kind: ModelKind,
) -> &'a stfit_fit::FitResult {
    fits.iter()
        .find(|f| f.sample == sample && f.model.kind == kind && !f.model.gamma.is_fixed())
        .unwrap()
}

/// "Exact to rounding" is relative to the fit's own values: `sqrt(L)` scales with
/// `sqrt(scale)`, so at scale 1e-12 a real masking error (Cycles' Lambda sum for a separable
/// GGX fit at alpha 0.02, rmse 9e-12 there, which the absolute threshold 1e-9 called rounding)
/// is not called rounding, and at 1e12 Mitsuba's exact mapping (rmse 1e-10) is; the reported error
/// relative to the fit's rms is the same at every scale, and no rmse is printed as 0.0000 when
/// it is not rounding.
#[test]
fn exact_to_rounding_is_relative_to_the_fit_scale() {
    const ALPHA: f64 = 0.02;
    let at = |scale: f64, t: Target| {
        let m = ExportModel::new(
            Model::single(ModelKind::Ggx, ALPHA, Gamma::NotApplicable, scale),
            "test fit",
        )
        .unwrap();
        targets::export(t, &m, "g").unwrap()
    };
    let relative = |e: &targets::Export| {
        let t = e.translation.as_ref().unwrap();
        t.rmse / t.reference_rms
    };
    let cycles_at_1 = relative(&at(1.0, Target::Cycles));
    for scale in [1e-12, 1e12] {
        let cycles = at(scale, Target::Cycles);
        let t = cycles.translation.as_ref().unwrap();
        assert!(!t.exact_to_rounding(), "{scale}: {t:?}");
        assert!(
            (relative(&cycles) / cycles_at_1 - 1.0).abs() < 1e-6,
            "{scale}: {} vs {cycles_at_1}",
            relative(&cycles)
        );
        let text = &cycles.files[0].text;
        assert!(
            !text.contains("exact to rounding") && !text.contains("rmse sqrt(L): 0.0000"),
            "{scale}: {text}"
        );
        let mitsuba = at(scale, Target::Mitsuba3);
        let t = mitsuba.translation.as_ref().unwrap();
        assert!(t.exact_to_rounding(), "{scale}: {t:?}");
        assert!(
            mitsuba.files[0].text.contains("exact to rounding"),
            "{scale}"
        );
    }
}

/// A near-smooth fit (alpha 0.003, eta 1.05) has lobes far narrower than the standard grid's
/// nodes (48 Gauss-Legendre nodes per hemisphere, 36 in azimuth): the translation is made on
/// outgoing directions graded around the specular and refracted peaks of the incidences the
/// grid does not resolve. A Student-T fit at gamma 2 is exactly GGX and at gamma 400 nearly
/// Beckmann with the same alpha: translated to Mitsuba's GGX or Beckmann, alpha is recovered
/// within a few %.
#[test]
fn near_smooth_translation_recovers_alpha() {
    for (gamma, family) in [(2.0, "ggx"), (400.0, "beckmann")] {
        let m = ExportModel::new(
            Model {
                eta: 1.05,
                ..Model::single(ModelKind::StudentT, 0.003, Gamma::Free(gamma), 1.0)
            },
            "near-smooth test fit",
        )
        .unwrap();
        let e = targets::export(Target::Mitsuba3, &m, "s").unwrap();
        let t = e.translation.as_ref().unwrap();
        let alpha = t.value("alpha").unwrap();
        eprintln!(
            "gamma {gamma}: alpha {alpha} rmse {} warnings {:?}",
            t.rmse, e.warnings
        );
        assert!(
            e.files[0].text.contains(&format!("\"{family}\"")),
            "gamma {gamma}: {}",
            e.files[0].text
        );
        assert!(
            (alpha / 0.003 - 1.0).abs() < 0.03,
            "gamma {gamma}: alpha {alpha}"
        );
    }
}

/// An all-orders fit is translated against its full BSDF, higher orders included; Blender 4's
/// Multiscatter GGX scales the single-scattering lobe by its inverse albedo, which would add
/// them a second time: the Cycles script uses single-scattering GGX for both nodes and says
/// why.
#[test]
fn all_orders_fits_are_not_multiscattered_twice_in_cycles() {
    let m = ExportModel::new(
        Model {
            masking: stfit_core::bsdf::Masking::Correlated,
            orders: stfit_core::ScatteringOrders::All,
            walks: Some(16),
            seed: Some(1),
            ..Model::single(ModelKind::Ggx, 0.3, Gamma::NotApplicable, 1.0)
        },
        "all-orders test fit",
    )
    .unwrap();
    let text = &targets::export(Target::Cycles, &m, "a").unwrap().files[0].text;
    assert!(!text.contains("MULTI_GGX"), "{text}");
    assert!(
        text.contains("glass.distribution = 'GGX'")
            && text.contains("bsdf.distribution = 'GGX'")
            && text.contains("would add the higher orders a second time"),
        "{text}"
    );
}
