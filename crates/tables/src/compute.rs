//! Computing a table, or an exact slice of it (a shard), on all cores.
//!
//! The work is split into tasks (the average of a line, and each cell) that rayon runs in any
//! order; each task is computed sequentially from the specification alone and results are
//! assembled in cell order, so the output is bit-identical whatever the number of threads and
//! however the table is sharded. The random walks of every cell start from the same seed, so
//! cells share their random numbers (common random numbers): neighbouring cells' estimates are
//! strongly correlated and the table is smooth even where each estimate is noisy. Within a
//! cell, the walk estimator of `stfit-core` is itself deterministic for a seed whatever the
//! number of threads.

use crate::error::SpecError;
use crate::single::{self, Albedo, Interface, Quadrature, TableMasking, TableNdf};
use crate::spec::{Family, Line, Surface, TableSpec};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;
use stfit_core::Vec3;
use stfit_core::ndf::{Beckmann, Ggx, StudentT};
use stfit_core::walk::{
    DielectricFacet, Estimator, Microsurface, ScatteringOrders, WalkCost, pilot_seed,
};

/// A Monte Carlo estimate and its standard error.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Value {
    pub mean: f64,
    pub stderr: f64,
}

/// What the random walks add to a cell: orders >= 2 (`Multiple`) or all orders (`All`: the
/// height-correlated single-scattering albedo plus the walks' orders >= 2), reflected,
/// transmitted and in total.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WalkResult {
    pub reflected: Value,
    pub transmitted: Value,
    pub total: Value,
    /// Fraction of the flux dropped by walks that reached the safety cap on scattering events
    /// (`stfit_core::walk::MAX_BOUNCES`); zero in practice.
    pub truncated: f64,
}

/// One cell: the single-scattering albedo and, when walks were asked for, what they give.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CellResult {
    pub single: Albedo,
    pub walk: Option<WalkResult>,
}

/// One line: the cosine-weighted average of the single-scattering albedo and the cells, in
/// the order of the mu axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineResult {
    /// The line's index.
    pub index: usize,
    pub average: Albedo,
    pub cells: Vec<CellResult>,
}

/// A computed table: the specification and every line, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub spec: TableSpec,
    pub lines: Vec<LineResult>,
}

/// Slice `index` (1-based) of `count` of a table: the lines `i` with `i % count == index - 1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// The whole table.
    pub const WHOLE: Shard = Shard { index: 1, count: 1 };

    /// The lines of the shard among `lines`.
    pub fn lines(self, lines: usize) -> impl Iterator<Item = usize> {
        (self.index - 1..lines).step_by(self.count)
    }

    /// Checks the shard against a table of `lines` lines: `1 <= K <= N <= lines`.
    pub fn check(self, lines: usize) -> Result<(), SpecError> {
        if self.count > lines {
            return Err(SpecError::Invalid(format!(
                "shard {self}: the table has only {lines} lines (side, gamma, eta, alpha) to share"
            )));
        }
        Ok(())
    }
}

impl FromStr for Shard {
    type Err = String;

    /// `K/N` with `1 <= K <= N`.
    fn from_str(s: &str) -> Result<Self, String> {
        let parse = |t: &str| t.trim().parse::<usize>().ok();
        match s.split_once('/').map(|(k, n)| (parse(k), parse(n))) {
            Some((Some(index), Some(count))) if index >= 1 && index <= count => {
                Ok(Self { index, count })
            }
            _ => Err(format!("'{s}' is not K/N with 1 <= K <= N")),
        }
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Number of progress units of a shard: one per line (its average) and one per cell.
pub fn work_units(spec: &TableSpec, shard: Shard) -> u64 {
    let per_line = 1 + spec.mu.len() as u64;
    shard.lines(spec.lines()).count() as u64 * per_line
}

/// Lines whose walks a pilot run times ([`walk_seconds`]), spread evenly over a shard.
pub const PILOT_LINES: usize = 8;

/// Estimated wall time, in seconds, on rayon's current pool, of the random walks of the cells
/// of `shard` (0 for single scattering), for a note before a long run: a pilot run
/// ([`WalkCost::measure`], random numbers of its own, at most a sixteenth of a cell's walks) of
/// the walks of the middle `mu` of at most [`PILOT_LINES`] lines spread evenly over the shard;
/// their mean time per walk times `spec.walks` walks of every cell.
pub fn walk_seconds(spec: &TableSpec, shard: Shard) -> Result<f64, SpecError> {
    let lines: Vec<usize> = shard.lines(spec.lines()).collect();
    if spec.orders == ScatteringOrders::Single || lines.is_empty() {
        return Ok(0.0);
    }
    let mu = spec.mu.values[spec.mu.values.len() / 2];
    let picked: Vec<usize> = lines
        .iter()
        .copied()
        .step_by(lines.len().div_ceil(PILOT_LINES))
        .collect();
    let mut seconds = 0.0;
    for &i in &picked {
        let line = spec.line(i);
        let cost = with_ndf(spec, line, |n| {
            let ms = n.walk_surface(spec, line)?;
            Ok::<_, SpecError>(WalkCost::measure(
                &*ms,
                spec.wi(line, mu),
                spec.walks,
                pilot_seed(spec.seed),
            ))
        })??;
        seconds += cost.seconds(spec.walks);
    }
    Ok(seconds / picked.len() as f64 * (lines.len() * spec.mu.values.len()) as f64)
}

/// Computes the lines of `shard`, in order, calling `progress(1)` after each unit of
/// [`work_units`] (from any thread). Parallel over all of rayon's threads.
pub fn compute(
    spec: &TableSpec,
    shard: Shard,
    rule: &Quadrature,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<LineResult>, SpecError> {
    spec.check()?;
    shard.check(spec.lines())?;
    let lines: Vec<usize> = shard.lines(spec.lines()).collect();
    // Check every line's parameters before starting the work.
    for &i in &lines {
        spec.interface(spec.line(i))?;
        with_ndf(spec, spec.line(i), |_| ())?;
    }
    let n_mu = spec.mu.len();
    let averages: Vec<Result<Albedo, SpecError>> = lines
        .par_iter()
        .map(|&i| {
            let out = average(spec, spec.line(i), rule);
            progress(1);
            out
        })
        .collect();
    let cells: Vec<Result<CellResult, SpecError>> = (0..lines.len() * n_mu)
        .into_par_iter()
        .map(|k| {
            let out = cell(spec, spec.line(lines[k / n_mu]), k % n_mu, rule);
            progress(1);
            out
        })
        .collect();
    let mut cells = cells.into_iter();
    let out: Vec<LineResult> = lines
        .iter()
        .zip(averages)
        .map(|(&index, average)| {
            Ok(LineResult {
                index,
                average: average?,
                cells: cells.by_ref().take(n_mu).collect::<Result<_, _>>()?,
            })
        })
        .collect::<Result<_, SpecError>>()?;
    for line in &out {
        check_finite(spec, line)?;
    }
    Ok(out)
}

/// Refuses a line with a value that is not finite, naming the cell, so that no file ever
/// holds NaN or inf.
fn check_finite(spec: &TableSpec, line: &LineResult) -> Result<(), SpecError> {
    let albedo = |a: &Albedo| [a.reflected, a.transmitted];
    let value = |v: &Value| [v.mean, v.stderr];
    let l = spec.line(line.index);
    let at = |mu: Option<f64>| {
        let mut s = format!(
            "side {}, alpha {}",
            spec.sides[l.side].name(),
            spec.alpha.values[l.alpha]
        );
        if let Some(g) = spec.gamma_value(l) {
            s += &format!(", gamma {g}");
        }
        if let Some(e) = spec.eta_value(l) {
            s += &format!(", eta {e}");
        }
        match mu {
            Some(mu) => s + &format!(", mu {mu}"),
            None => s + " (E_avg)",
        }
    };
    if !albedo(&line.average).iter().all(|v| v.is_finite()) {
        return Err(SpecError::NotFinite(format!(
            "a value is not finite at {}",
            at(None)
        )));
    }
    for (y, c) in line.cells.iter().enumerate() {
        let mut values = albedo(&c.single).to_vec();
        if let Some(w) = &c.walk {
            for v in [&w.reflected, &w.transmitted, &w.total] {
                values.extend(value(v));
            }
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(SpecError::NotFinite(format!(
                "a value is not finite at {}",
                at(Some(spec.mu.values[y]))
            )));
        }
    }
    Ok(())
}

/// The whole table.
pub fn compute_table(
    spec: &TableSpec,
    rule: &Quadrature,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Table, SpecError> {
    Ok(Table {
        spec: spec.clone(),
        lines: compute(spec, Shard::WHOLE, rule, progress)?,
    })
}

/// Calls `f` with the NDF of a line.
fn with_ndf<T>(
    spec: &TableSpec,
    line: Line,
    f: impl FnOnce(&dyn AnyTableNdf) -> T,
) -> Result<T, SpecError> {
    let alpha = spec.alpha.values[line.alpha];
    let err = |e: stfit_core::ParamError| SpecError::Invalid(e.to_string());
    Ok(match spec.family {
        Family::Beckmann => f(&Beckmann::new(alpha).map_err(err)?),
        Family::Ggx => f(&Ggx::new(alpha).map_err(err)?),
        Family::StudentT => {
            let gamma = spec
                .gamma_value(line)
                .ok_or_else(|| SpecError::Invalid("student-t needs a gamma axis".into()))?;
            f(&StudentT::new(alpha, gamma).map_err(err)?)
        }
    })
}

/// The work of a task on a line's NDF, behind one object type so that [`with_ndf`] can hand
/// out the three NDFs; each method runs the generic (monomorphised) code.
trait AnyTableNdf {
    fn single(&self, i: Interface, m: TableMasking, mu: f64, rule: &Quadrature) -> Albedo;
    fn average(&self, i: Interface, m: TableMasking, rule: &Quadrature) -> Albedo;
    /// The microsurface of the line whose walks give its cells' orders >= 2
    /// ([`multiple_scattering`]).
    fn walk_surface(&self, spec: &TableSpec, line: Line) -> Result<Box<dyn Estimator>, SpecError>;
}

impl<N: TableNdf + Copy + 'static> AnyTableNdf for N {
    fn single(&self, i: Interface, m: TableMasking, mu: f64, rule: &Quadrature) -> Albedo {
        single::single_scattering(self, i, m, mu, rule)
    }
    fn average(&self, i: Interface, m: TableMasking, rule: &Quadrature) -> Albedo {
        single::average(self, i, m, rule)
    }
    fn walk_surface(&self, spec: &TableSpec, line: Line) -> Result<Box<dyn Estimator>, SpecError> {
        let orders = ScatteringOrders::Multiple;
        Ok(match spec.surface {
            Surface::Dielectric => {
                let eta = spec
                    .eta_value(line)
                    .ok_or_else(|| SpecError::Invalid("a dielectric needs an eta axis".into()))?;
                let facet = DielectricFacet::new(eta)
                    .map_err(|e| SpecError::Invalid(format!("eta: {e}")))?;
                Box::new(Microsurface::new(*self, facet).with_orders(orders))
            }
            Surface::Conductor { .. } | Surface::Mirror => {
                Box::new(Microsurface::new(*self, spec.conductor()?).with_orders(orders))
            }
        })
    }
}

/// Orders >= 2 from a cell's walks: reflected, transmitted, total, and the truncated flux.
struct WalkAlbedo {
    reflected: Value,
    transmitted: Value,
    total: Value,
    truncated: f64,
}

/// Estimates the flux that walks on the microsurface `ms` (orders >= 2,
/// [`AnyTableNdf::walk_surface`]) send back and through after two or more scattering events,
/// from `spec.walks` walks from `wi` seeded with `spec.seed`. A walk leaves on one
/// side only, so the per-walk reflected and transmitted weights have product zero and the
/// standard error of their sum follows from theirs: `se_E^2 = se_R^2 + se_T^2 - 2 R T / (n - 1)`.
///
/// Walk weights are at most 1, and where few walks contribute the sample variance understates
/// the error (with none it is 0): every standard error is kept at least `1 / n`, that of one
/// walk of weight 1 among `n`, except for the transmission of opaque facets, which is exactly 0.
fn multiple_scattering(ms: &dyn Estimator, wi: Vec3, spec: &TableSpec) -> WalkAlbedo {
    let a = ms.albedo(wi, spec.walks, spec.seed);
    let n = a.walks as f64;
    let var_e = if n > 1.0 {
        a.reflectance_stderr.powi(2) + a.transmittance_stderr.powi(2)
            - 2.0 * a.reflectance * a.transmittance / (n - 1.0)
    } else {
        0.0
    };
    let floor = 1.0 / n;
    let opaque = spec.surface != Surface::Dielectric;
    WalkAlbedo {
        reflected: Value {
            mean: a.reflectance,
            stderr: a.reflectance_stderr.max(floor),
        },
        transmitted: Value {
            mean: a.transmittance,
            stderr: if opaque {
                a.transmittance_stderr
            } else {
                a.transmittance_stderr.max(floor)
            },
        },
        total: Value {
            mean: a.reflectance + a.transmittance,
            stderr: var_e.max(0.0).sqrt().max(floor),
        },
        truncated: a.truncated,
    }
}

/// The cosine-weighted average of a line's single-scattering albedo.
fn average(spec: &TableSpec, line: Line, rule: &Quadrature) -> Result<Albedo, SpecError> {
    let interface = spec.interface(line)?;
    with_ndf(spec, line, |n| n.average(interface, spec.masking, rule))
}

/// One cell: the single-scattering albedo and, if asked for, the walks.
fn cell(
    spec: &TableSpec,
    line: Line,
    y: usize,
    rule: &Quadrature,
) -> Result<CellResult, SpecError> {
    let interface = spec.interface(line)?;
    let mu = spec.mu.values[y];
    with_ndf(spec, line, |n| {
        let single = n.single(interface, spec.masking, mu, rule);
        let walk = match spec.orders {
            ScatteringOrders::Single => None,
            orders => {
                let ms =
                    multiple_scattering(&*n.walk_surface(spec, line)?, spec.wi(line, mu), spec);
                // All orders: the walks' first order is the height-correlated albedo.
                let first = match orders {
                    ScatteringOrders::All if spec.masking == TableMasking::Correlated => single,
                    ScatteringOrders::All => {
                        n.single(interface, TableMasking::Correlated, mu, rule)
                    }
                    _ => Albedo::default(),
                };
                let shift = |v: Value, by: f64| Value {
                    mean: v.mean + by,
                    stderr: v.stderr,
                };
                Some(WalkResult {
                    reflected: shift(ms.reflected, first.reflected),
                    transmitted: shift(ms.transmitted, first.transmitted),
                    total: shift(ms.total, first.total()),
                    truncated: ms.truncated,
                })
            }
        };
        Ok(CellResult { single, walk })
    })?
}
