//! The options of a table request, as `stfit tables` and the Python package `stfit.tables` take
//! them: the rules that turn them into a [`TableSpec`] (defaults, what applies to what, what
//! conflicts), the choice of output (a shard file, or a whole table in a format), and the run
//! that computes and encodes it. Both front ends call this module, so they accept the same
//! options and write the same bytes; only the names in messages differ ([`Naming`]).

use crate::compute::{self, LineResult, Shard, Table, work_units};
use crate::error::SpecError;
use crate::format::{Format, shard};
use crate::grid::Axis;
use crate::single::{Quadrature, TableMasking};
use crate::spec::{Family, Side, Surface, TableSpec};
use std::path::Path;
use stfit_core::walk::ScatteringOrders;

/// Walks per cell when none are given.
pub const DEFAULT_WALKS: u64 = 100_000;
/// Seed of the walks when none is given.
pub const DEFAULT_SEED: u64 = 1;

/// How messages name the options: as command-line flags (`--alpha-grid`, `--ndf student-t`)
/// or as Python keywords (`alpha_grid`, `ndf='student-t'`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Naming {
    Flags,
    Keywords,
}

impl Naming {
    /// The option `name` (its keyword spelling, `alpha_grid`).
    pub fn option(self, name: &str) -> String {
        match self {
            Self::Flags => format!("--{}", name.replace('_', "-")),
            Self::Keywords => name.to_owned(),
        }
    }

    /// The option `name` set to one of `values`: `--orders multiple or all`,
    /// `orders='multiple' or 'all'`.
    pub fn choice(self, name: &str, values: &[&str]) -> String {
        let quoted: Vec<String> = match self {
            Self::Flags => values.iter().map(|v| (*v).to_owned()).collect(),
            Self::Keywords => values.iter().map(|v| format!("'{v}'")).collect(),
        };
        let sep = match self {
            Self::Flags => " ",
            Self::Keywords => "=",
        };
        format!("{}{sep}{}", self.option(name), quoted.join(" or "))
    }

    /// How shards are merged, for messages.
    fn merge_command(self) -> &'static str {
        match self {
            Self::Flags => "stfit tables merge",
            Self::Keywords => "stfit.merge_table_shards",
        }
    }
}

/// A choice among named values, spelled as on the command line.
pub trait Choice: Sized + Copy + 'static {
    /// Every value, in the order of the documentation.
    const ALL: &'static [Self];
    /// The value's name.
    fn name(self) -> &'static str;

    /// The value named `name`, or an error naming the option `option` and the choices.
    fn parse(option: &str, name: &str) -> Result<Self, SpecError> {
        Self::ALL
            .iter()
            .copied()
            .find(|v| v.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|v| v.name()).collect();
                SpecError::Invalid(format!(
                    "{option}: unknown value '{name}' (expected {})",
                    names.join(", ")
                ))
            })
    }
}

impl Choice for Family {
    const ALL: &'static [Self] = &[Self::Beckmann, Self::Ggx, Self::StudentT];
    fn name(self) -> &'static str {
        Family::name(self)
    }
}

/// The side option: one side, or both (the default for dielectrics).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SideChoice {
    Outside,
    Inside,
    Both,
}

impl Choice for SideChoice {
    const ALL: &'static [Self] = &[Self::Outside, Self::Inside, Self::Both];
    fn name(self) -> &'static str {
        match self {
            Self::Outside => "outside",
            Self::Inside => "inside",
            Self::Both => "both",
        }
    }
}

/// The facet material option: a dielectric, or a conductor (Fresnel with `n` and `k`, else
/// mirror facets).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SurfaceKind {
    #[default]
    Dielectric,
    Conductor,
}

impl Choice for SurfaceKind {
    const ALL: &'static [Self] = &[Self::Dielectric, Self::Conductor];
    fn name(self) -> &'static str {
        match self {
            Self::Dielectric => "dielectric",
            Self::Conductor => "conductor",
        }
    }
}

impl Choice for ScatteringOrders {
    const ALL: &'static [Self] = &[Self::Single, Self::Multiple, Self::All];
    fn name(self) -> &'static str {
        crate::spec::orders_str(self)
    }
}

impl Choice for TableMasking {
    const ALL: &'static [Self] = &[Self::Correlated, Self::ReflectionForm, Self::Separable];
    fn name(self) -> &'static str {
        match self {
            Self::Correlated => "correlated",
            Self::ReflectionForm => "reflection-form",
            Self::Separable => "separable",
        }
    }
}

/// A fixed set of nodes instead of the grid options.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// The nodes of Blender Cycles' tables ([`TableSpec::cycles`]).
    Cycles,
}

impl Choice for Layout {
    const ALL: &'static [Self] = &[Self::Cycles];
    fn name(self) -> &'static str {
        "cycles"
    }
}

impl Choice for Format {
    const ALL: &'static [Self] = &[Self::Csv, Self::Npy, Self::C];
    fn name(self) -> &'static str {
        match self {
            Self::Csv => "csv",
            Self::Npy => "npy",
            Self::C => "c",
        }
    }
}

/// The options that describe a table, as given (`None`: not given).
#[derive(Debug, Clone, PartialEq)]
pub struct TableOptions {
    pub ndf: Option<Family>,
    pub alpha_grid: Option<Axis>,
    pub gamma_grid: Option<Axis>,
    pub mu_grid: Option<Axis>,
    pub eta_grid: Option<Axis>,
    pub side: Option<SideChoice>,
    pub surface: SurfaceKind,
    pub n: Option<f64>,
    pub k: Option<f64>,
    pub orders: ScatteringOrders,
    pub masking: TableMasking,
    pub layout: Option<Layout>,
    pub walks: Option<u64>,
    pub seed: Option<u64>,
}

impl Default for TableOptions {
    /// No option given: a dielectric, single scattering (`E_ss` only), correlated masking.
    fn default() -> Self {
        Self {
            ndf: None,
            alpha_grid: None,
            gamma_grid: None,
            mu_grid: None,
            eta_grid: None,
            side: None,
            surface: SurfaceKind::Dielectric,
            n: None,
            k: None,
            orders: ScatteringOrders::Single,
            masking: TableMasking::Correlated,
            layout: None,
            walks: None,
            seed: None,
        }
    }
}

impl TableOptions {
    /// The table specification the options describe, or an error naming the option
    /// ([`SpecError::Invalid`] or [`SpecError::Axis`]: the caller's arguments).
    pub fn spec(&self, naming: Naming) -> Result<TableSpec, SpecError> {
        let opt = |name: &str| naming.option(name);
        let choice = |name: &str, values: &[&str]| naming.choice(name, values);
        let invalid = |m: String| Err(SpecError::Invalid(m));
        let Some(family) = self.ndf else {
            return invalid(format!("{} is required", opt("ndf")));
        };
        let surface = match (self.surface, self.n, self.k) {
            (SurfaceKind::Dielectric, None, None) => Surface::Dielectric,
            (SurfaceKind::Dielectric, _, _) => {
                return invalid(format!(
                    "{} and {} apply only to {}",
                    opt("n"),
                    opt("k"),
                    choice("surface", &["conductor"])
                ));
            }
            (SurfaceKind::Conductor, None, None) => Surface::Mirror,
            (SurfaceKind::Conductor, Some(n), Some(k)) => Surface::Conductor { n, k },
            (SurfaceKind::Conductor, _, _) => {
                return invalid(format!("{} and {} go together", opt("n"), opt("k")));
            }
        };
        let student_t = choice("ndf", &["student-t"]);
        if family != Family::StudentT && self.gamma_grid.is_some() {
            return invalid(format!("{} applies only to {student_t}", opt("gamma_grid")));
        }
        if family == Family::StudentT && self.gamma_grid.is_none() {
            return invalid(format!("{} is required for {student_t}", opt("gamma_grid")));
        }
        let dielectric = surface == Surface::Dielectric;
        if !dielectric && self.eta_grid.is_some() {
            return invalid(format!(
                "{} applies only to {}",
                opt("eta_grid"),
                choice("surface", &["dielectric"])
            ));
        }
        let cycles = choice("layout", &["cycles"]);
        let mut spec = if self.layout == Some(Layout::Cycles) {
            for (set, name) in [
                (self.alpha_grid.is_some(), "alpha_grid"),
                (self.mu_grid.is_some(), "mu_grid"),
                (self.eta_grid.is_some(), "eta_grid"),
            ] {
                if set {
                    return invalid(format!("{} conflicts with {cycles}", opt(name)));
                }
            }
            TableSpec::cycles(
                family,
                surface,
                self.masking,
                self.orders,
                self.gamma_grid.clone(),
            )
        } else {
            let need = |axis: &Option<Axis>, name: &str| {
                axis.clone().ok_or_else(|| {
                    SpecError::Invalid(format!("{} is required (or {cycles})", opt(name)))
                })
            };
            TableSpec {
                family,
                surface,
                masking: self.masking,
                orders: self.orders,
                sides: vec![Side::Outside, Side::Inside],
                alpha: need(&self.alpha_grid, "alpha_grid")?,
                gamma: self.gamma_grid.clone(),
                eta: if dielectric {
                    Some(need(&self.eta_grid, "eta_grid")?)
                } else {
                    None
                },
                mu: need(&self.mu_grid, "mu_grid")?,
                walks: DEFAULT_WALKS,
                seed: DEFAULT_SEED,
            }
        };
        spec.sides = match (self.side, dielectric) {
            (None | Some(SideChoice::Both), true) => vec![Side::Outside, Side::Inside],
            (None | Some(SideChoice::Outside), _) => vec![Side::Outside],
            (Some(SideChoice::Inside), true) => vec![Side::Inside],
            (Some(_), false) => {
                return invalid(format!(
                    "{}: conductors are two-sided; tables are for light from outside",
                    opt("side")
                ));
            }
        };
        if self.orders == ScatteringOrders::Single {
            if self.walks.is_some() || self.seed.is_some() {
                return invalid(format!(
                    "{} and {} apply only to {}",
                    opt("walks"),
                    opt("seed"),
                    choice("orders", &["multiple", "all"])
                ));
            }
        } else {
            spec.walks = self.walks.unwrap_or(spec.walks);
            spec.seed = self.seed.unwrap_or(spec.seed);
        }
        spec.check().map_err(|e| match (self.layout, &spec.eta) {
            (Some(Layout::Cycles), Some(_)) if spec.walks_needed() => SpecError::Invalid(format!(
                "{cycles} for a dielectric is for {} only: its node z = 0 has eta = 1 + 2e-8 \
                 ({e})",
                choice("orders", &["single"])
            )),
            _ => e,
        })?;
        Ok(spec)
    }
}

/// What a run writes: a shard file, or the whole table in a format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    Shard(Shard),
    Whole(Format),
}

/// A checked table request: the specification and what to write.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub spec: TableSpec,
    pub output: Output,
}

impl Plan {
    /// The request of `options` with the output options: `shard` (a shard file, which has no
    /// format) or `format` (default: from the extension of `out`, [`Format::from_path`]).
    pub fn new(
        options: &TableOptions,
        format: Option<Format>,
        shard: Option<Shard>,
        out: Option<&Path>,
        naming: Naming,
    ) -> Result<Self, SpecError> {
        let spec = options.spec(naming)?;
        let output = match (shard, format) {
            (Some(_), Some(_)) => {
                return Err(SpecError::Invalid(format!(
                    "{} does not apply to {} (shards are merged with {})",
                    naming.option("format"),
                    naming.option("shard"),
                    naming.merge_command()
                )));
            }
            (Some(part), None) => {
                part.check(spec.lines())?;
                Output::Shard(part)
            }
            (None, Some(f)) => Output::Whole(f),
            (None, None) => Output::Whole(out.map_or(Format::Csv, Format::from_path)),
        };
        Ok(Self { spec, output })
    }

    /// The slice of the table computed.
    pub fn part(&self) -> Shard {
        match self.output {
            Output::Shard(part) => part,
            Output::Whole(_) => Shard::WHOLE,
        }
    }

    /// Number of progress units of the run ([`work_units`]).
    pub fn work_units(&self) -> u64 {
        work_units(&self.spec, self.part())
    }

    /// Estimated wall time, in seconds, of the plan's random walks, for a note before a long
    /// run ([`compute::walk_seconds`]); 0 for single scattering.
    pub fn walk_seconds(&self) -> Result<f64, SpecError> {
        compute::walk_seconds(&self.spec, self.part())
    }

    /// Computes the lines of the plan, calling `progress(1)` after each unit of
    /// [`Plan::work_units`] (from any thread), with the default quadrature.
    pub fn run(self, progress: &(dyn Fn(u64) + Sync)) -> Result<Run, SpecError> {
        let lines = compute::compute(&self.spec, self.part(), &Quadrature::default(), progress)?;
        Ok(Run { plan: self, lines })
    }
}

/// The computed lines of a plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    pub plan: Plan,
    pub lines: Vec<LineResult>,
}

impl Run {
    /// Number of cells computed.
    pub fn cells(&self) -> usize {
        self.lines.iter().map(|l| l.cells.len()).sum()
    }

    /// The warning of a run whose walks reached the safety cap on scattering events, with
    /// the largest fraction of a cell's flux they dropped.
    pub fn truncation_warning(&self) -> Option<String> {
        let truncated = self
            .lines
            .iter()
            .flat_map(|l| &l.cells)
            .filter_map(|c| c.walk.map(|w| w.truncated))
            .fold(0.0, f64::max);
        (truncated > 0.0).then(|| {
            format!(
                "walks that reached the safety cap on scattering events dropped up to \
                 {truncated:.3e} of the flux of a cell"
            )
        })
    }

    /// The file's bytes: the shard file's JSON text, or the table in its format.
    pub fn bytes(&self) -> Result<Vec<u8>, SpecError> {
        match self.plan.output {
            Output::Shard(part) => shard::write(&self.plan.spec, part, &self.lines)
                .map(String::into_bytes)
                .map_err(|e| SpecError::NotFinite(format!("cannot encode the shard: {e}"))),
            Output::Whole(format) => Ok(format.write(&self.table())),
        }
    }

    /// The lines as a table (the whole table unless the plan is a shard).
    pub fn table(&self) -> Table {
        Table {
            spec: self.plan.spec.clone(),
            lines: self.lines.clone(),
        }
    }

    /// The one-line summary of a run written to `out`: `N cells -> OUT`, or
    /// `shard K/N: L lines, N cells -> OUT`.
    pub fn summary(&self, out: &Path) -> String {
        match self.plan.output {
            Output::Shard(part) => format!(
                "shard {part}: {} lines, {} cells -> {}",
                self.lines.len(),
                self.cells(),
                out.display()
            ),
            Output::Whole(_) => format!("{} cells -> {}", self.cells(), out.display()),
        }
    }
}

/// Writes `bytes` to `path`, with a message naming the file on failure.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options() -> TableOptions {
        TableOptions {
            ndf: Some(Family::Ggx),
            alpha_grid: Some("0.1,0.5".parse().unwrap()),
            mu_grid: Some("0.5,1".parse().unwrap()),
            eta_grid: Some("1.5".parse().unwrap()),
            ..TableOptions::default()
        }
    }

    fn message(o: &TableOptions, naming: Naming) -> String {
        o.spec(naming).unwrap_err().to_string()
    }

    #[test]
    fn defaults_give_both_sides_and_the_default_walks() {
        let mut o = options();
        let spec = o.spec(Naming::Flags).unwrap();
        assert_eq!(spec.sides, [Side::Outside, Side::Inside]);
        assert_eq!(spec.surface, Surface::Dielectric);
        assert_eq!((spec.walks, spec.seed), (DEFAULT_WALKS, DEFAULT_SEED));
        o.orders = ScatteringOrders::All;
        o.walks = Some(50);
        let spec = o.spec(Naming::Flags).unwrap();
        assert_eq!((spec.walks, spec.seed), (50, DEFAULT_SEED));
    }

    #[test]
    fn messages_name_flags_or_keywords() {
        let mut o = options();
        o.walks = Some(10);
        assert_eq!(
            message(&o, Naming::Flags),
            "--walks and --seed apply only to --orders multiple or all"
        );
        assert_eq!(
            message(&o, Naming::Keywords),
            "walks and seed apply only to orders='multiple' or 'all'"
        );
        let mut o = options();
        o.ndf = Some(Family::StudentT);
        assert_eq!(
            message(&o, Naming::Keywords),
            "gamma_grid is required for ndf='student-t'"
        );
        o.alpha_grid = None;
        o.gamma_grid = Some("3".parse().unwrap());
        assert_eq!(
            message(&o, Naming::Flags),
            "--alpha-grid is required (or --layout cycles)"
        );
    }

    #[test]
    fn walks_refuse_eta_near_1_before_any_work() {
        let mut o = options();
        o.orders = ScatteringOrders::All;
        o.eta_grid = Some("1.0000000001,1.5".parse().unwrap());
        let err = message(&o, Naming::Flags);
        assert!(
            err.starts_with("eta axis value 1.0000000001 cannot be walked (orders multiple"),
            "{err}"
        );
        o.eta_grid = None;
        o.alpha_grid = None;
        o.mu_grid = None;
        o.layout = Some(Layout::Cycles);
        let err = message(&o, Naming::Flags);
        assert!(
            err.starts_with(
                "--layout cycles for a dielectric is for --orders single only: its node z = 0 \
                 has eta = 1 + 2e-8 (eta axis value 1.00000002 cannot be walked"
            ),
            "{err}"
        );
        o.orders = ScatteringOrders::Single;
        assert!(o.spec(Naming::Flags).is_ok());
    }

    #[test]
    fn a_shard_has_no_format_and_fits_the_table() {
        let o = options();
        let part = Some("1/2".parse().unwrap());
        let err = Plan::new(&o, Some(Format::Csv), part, None, Naming::Keywords).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("format does not apply to shard")
        );
        let err = Plan::new(&o, None, Some("1/9".parse().unwrap()), None, Naming::Flags);
        assert!(err.unwrap_err().to_string().contains("only 4 lines"));
        let plan = Plan::new(&o, None, None, Some(Path::new("t.h")), Naming::Flags).unwrap();
        assert_eq!(plan.output, Output::Whole(Format::C));
    }

    #[test]
    fn choices_parse_by_their_command_line_names() {
        assert_eq!(
            TableMasking::parse("masking", "reflection-form").unwrap(),
            TableMasking::ReflectionForm
        );
        let err = Family::parse("ndf", "gauss").unwrap_err().to_string();
        assert_eq!(
            err,
            "ndf: unknown value 'gauss' (expected beckmann, ggx, student-t)"
        );
    }
}
