//! stfit-tables: directional-albedo tables of microfacet BSDFs, the energy-compensation tables
//! renderers precompute (Kulla and Conty 2017; Turquin 2019; Blender Cycles).
//!
//! - [`single`]: the single-scattering albedo by deterministic quadrature;
//! - [`spec`] and [`grid`]: what a table holds and where its nodes are;
//! - [`compute`](mod@compute): the parallel, deterministic computation of a table or a shard of
//!   it, with the random walks for orders >= 2;
//! - [`options`]: the options of `stfit tables` and `stfit.tables`, their defaults and checks,
//!   and the run that computes and encodes the file they ask for;
//! - [`format`](mod@format): CSV, NumPy `.npy`, C headers in Cycles' layout, and shard files
//!   with their merge.

pub mod compute;
pub mod error;
pub mod format;
pub mod grid;
pub mod options;
pub mod single;
pub mod spec;

pub use compute::{Shard, Table, compute, compute_table};
pub use error::{ShardError, SpecError};
pub use spec::{Family, Side, Surface, TableSpec};
