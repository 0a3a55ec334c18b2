//! `stfit tables`: directional-albedo (energy-compensation) tables, and `stfit tables merge`.
//! Argument parsing and printing only; the work is in `stfit-tables`.

use super::{CmdError, CmdResult, OrdersArg, long_run, print_stdout, refuse_overwriting_input};
use clap::{Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use stfit_tables::format::{Format, shard};
use stfit_tables::grid::Axis;
use stfit_tables::options::{
    Layout, Naming, Plan, SideChoice, SurfaceKind, TableOptions, write_file,
};
use stfit_tables::single::TableMasking;
use stfit_tables::{Family, Shard, SpecError};

/// Arguments of `stfit tables`.
#[derive(Debug, clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct Args {
    #[command(flatten)]
    pub table: TableArgs,
    #[command(subcommand)]
    pub command: Option<TablesCommand>,
}

/// Subcommands of `stfit tables`.
#[derive(Debug, Subcommand)]
pub enum TablesCommand {
    /// Join the shard files of `--shard K/N` runs into the file one run writes.
    Merge(MergeArgs),
}

/// The table to compute (see tables-format.md for the axes and the files).
#[derive(Debug, clap::Args)]
pub struct TableArgs {
    /// NDF family.
    #[arg(long, value_enum, required = true)]
    pub ndf: Option<NdfArg>,
    /// Roughness axis: START:END:COUNT, MAP:START:END:COUNT (MAP lin, log, sq: alpha = x^2,
    /// or cycles-ior as for --eta-grid; see tables-format.md) or a list v1,v2,..., strictly
    /// increasing; alpha in [1e-8, 4].
    #[arg(long)]
    pub alpha_grid: Option<Axis>,
    /// Student-T shape axis (student-t only), as --alpha-grid; gamma in [1.6, 40].
    #[arg(long)]
    pub gamma_grid: Option<Axis>,
    /// Cosine-of-incidence axis, as --alpha-grid; mu in [1e-4, 1].
    #[arg(long)]
    pub mu_grid: Option<Axis>,
    /// Relative index n_inside / n_outside (dielectric only), as --alpha-grid (MAP may also be
    /// cycles-ior: eta = (1 + x^2) / (1 - x^2)); eta in (1, 100], |eta - 1| >= 0.005 with
    /// --orders multiple or all (random walks).
    #[arg(long)]
    pub eta_grid: Option<Axis>,
    /// Side of the light: outside (from the air), inside (from the glass), or both (the
    /// default for dielectrics).
    #[arg(long, value_enum)]
    pub side: Option<SideArg>,
    /// Facet material: dielectric, or conductor (Fresnel with --n and --k, else mirror facets
    /// that reflect everything).
    #[arg(long, value_enum, default_value_t = SurfaceArg::Dielectric)]
    pub surface: SurfaceArg,
    /// Real part of the conductor's index relative to the outside medium (with --k).
    #[arg(long, allow_negative_numbers = true)]
    pub n: Option<f64>,
    /// Imaginary part of the conductor's index (with --n).
    #[arg(long, allow_negative_numbers = true)]
    pub k: Option<f64>,
    /// Scattering orders: single (E_ss by quadrature), multiple (also orders >= 2 by random
    /// walks) or all (also E_all = E_ss with height-correlated masking + orders >= 2).
    #[arg(long, value_enum, default_value_t = OrdersArg::Single)]
    pub orders: OrdersArg,
    /// Masking of E_ss: correlated (Beta function for transmission), reflection-form
    /// (1 / (1 + Lambda_i + Lambda_o) for transmission too, as Cycles) or separable.
    #[arg(long, value_enum, default_value_t = MaskingArg::Correlated)]
    pub masking: MaskingArg,
    /// Use exactly the nodes of Blender Cycles' tables instead of the grid options: 16^3
    /// ggx_glass_E / ggx_glass_inv_E nodes for a dielectric (--orders single only: a node has
    /// eta = 1 + 2e-8), 32^2 ggx_E nodes otherwise.
    #[arg(long, value_enum)]
    pub layout: Option<LayoutArg>,
    /// Output format (default: from the extension of --out: .npy, .h/.hpp/.c/.inc for C, else
    /// CSV).
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Compute only slice K of N (lines i with i % N == K - 1) and write a shard file for
    /// `stfit tables merge`.
    #[arg(long)]
    pub shard: Option<Shard>,
    /// Random walks per cell (orders multiple or all).
    #[arg(long)]
    pub walks: Option<u64>,
    /// Seed of the random walks (orders multiple or all); every cell uses the same numbers.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Output file.
    #[arg(long, required = true)]
    pub out: Option<PathBuf>,
}

/// Arguments of `stfit tables merge`.
#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// Shard files written by `stfit tables --shard K/N`, every K once.
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// Output format (default: from the extension of --out).
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Output file.
    #[arg(long)]
    pub out: PathBuf,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum NdfArg {
    Beckmann,
    Ggx,
    #[value(name = "student-t")]
    StudentT,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SideArg {
    Outside,
    Inside,
    Both,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SurfaceArg {
    Dielectric,
    Conductor,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MaskingArg {
    Correlated,
    ReflectionForm,
    Separable,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LayoutArg {
    Cycles,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FormatArg {
    Csv,
    Npy,
    C,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Self {
        match f {
            FormatArg::Csv => Self::Csv,
            FormatArg::Npy => Self::Npy,
            FormatArg::C => Self::C,
        }
    }
}

fn usage(m: impl Into<String>) -> CmdError {
    CmdError::Usage(m.into())
}

/// Runs `stfit tables` or `stfit tables merge`.
pub fn run(args: Args) -> CmdResult {
    match args.command {
        Some(TablesCommand::Merge(m)) => merge(&m),
        None => compute_table(&args.table),
    }
}

/// The library's options of the command-line values.
fn options(a: &TableArgs) -> TableOptions {
    TableOptions {
        ndf: a.ndf.map(|f| match f {
            NdfArg::Beckmann => Family::Beckmann,
            NdfArg::Ggx => Family::Ggx,
            NdfArg::StudentT => Family::StudentT,
        }),
        alpha_grid: a.alpha_grid.clone(),
        gamma_grid: a.gamma_grid.clone(),
        mu_grid: a.mu_grid.clone(),
        eta_grid: a.eta_grid.clone(),
        side: a.side.map(|s| match s {
            SideArg::Outside => SideChoice::Outside,
            SideArg::Inside => SideChoice::Inside,
            SideArg::Both => SideChoice::Both,
        }),
        surface: match a.surface {
            SurfaceArg::Dielectric => SurfaceKind::Dielectric,
            SurfaceArg::Conductor => SurfaceKind::Conductor,
        },
        n: a.n,
        k: a.k,
        orders: a.orders.into(),
        masking: match a.masking {
            MaskingArg::Correlated => TableMasking::Correlated,
            MaskingArg::ReflectionForm => TableMasking::ReflectionForm,
            MaskingArg::Separable => TableMasking::Separable,
        },
        layout: a.layout.map(|LayoutArg::Cycles| Layout::Cycles),
        walks: a.walks,
        seed: a.seed,
    }
}

/// An invalid specification is a usage error (exit 2); a failed computation is not.
fn spec_error(e: SpecError) -> CmdError {
    match e {
        SpecError::NotFinite(m) => CmdError::Failed(m),
        e => usage(e.to_string()),
    }
}

/// The progress bar of a run, drawn when stderr is a terminal.
fn progress_bar(units: u64) -> Option<ProgressBar> {
    std::io::stderr().is_terminal().then(|| {
        let bar = ProgressBar::new(units);
        if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} cells, eta {eta}") {
            bar.set_style(style);
        }
        bar
    })
}

fn compute_table(a: &TableArgs) -> CmdResult {
    let out = a.out.as_deref().ok_or_else(|| usage("--out is required"))?;
    let plan = Plan::new(
        &options(a),
        a.format.map(Format::from),
        a.shard,
        Some(out),
        Naming::Flags,
    )
    .map_err(spec_error)?;
    long_run::note_if_long(
        plan.walk_seconds().map_err(spec_error)?,
        &plan.spec.walks_description(),
        "fewer --walks or fewer nodes make it shorter",
    );
    let bar = progress_bar(plan.work_units());
    let progress = |n| {
        if let Some(bar) = &bar {
            bar.inc(n);
        }
    };
    let run = plan.run(&progress).map_err(spec_error)?;
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    if let Some(warning) = run.truncation_warning() {
        eprintln!("warning: {warning}");
    }
    write(out, &run.bytes().map_err(spec_error)?)?;
    print_stdout(&format!("{}\n", run.summary(out)))
}

/// Writes `bytes` to `path`.
fn write(path: &Path, bytes: &[u8]) -> CmdResult {
    write_file(path, bytes).map_err(CmdError::Failed)
}

fn merge(m: &MergeArgs) -> CmdResult {
    refuse_overwriting_input(&m.out, &m.shards)?;
    let mut files = Vec::with_capacity(m.shards.len());
    for path in &m.shards {
        let text = stfit_fit::files::read_input_text(path)
            .map_err(|e| CmdError::Failed(format!("{}: cannot read: {e}", path.display())))?;
        files.push((path.display().to_string(), text));
    }
    let table = shard::merge(&files).map_err(|e| CmdError::Failed(e.to_string()))?;
    let format = m
        .format
        .map_or_else(|| Format::from_path(&m.out), Format::from);
    write(&m.out, &format.write(&table))?;
    let cells: usize = table.lines.iter().map(|l| l.cells.len()).sum();
    print_stdout(&format!(
        "{} shards, {cells} cells -> {}\n",
        m.shards.len(),
        m.out.display()
    ))
}
