//! The axes of a table: how their nodes are placed (the mapping from an evenly spaced
//! parameter to the tabulated quantity) and the supported range of each quantity.

use crate::error::SpecError;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;
use stfit_core::error::show;

/// How an axis maps its parameter `x` (evenly spaced from `start` to `end`) to the tabulated
/// value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mapping {
    /// The value is `x`.
    Lin,
    /// The value is `exp(x)` with `x` evenly spaced in `ln`: geometric spacing from `start` to
    /// `end`.
    Log,
    /// The value is `x^2` (Cycles' roughness axis: `alpha = r^2`).
    Sq,
    /// The value is `(1 + x^2) / (1 - x^2)`, `0 <= x < 1` (Cycles' index-of-refraction axis:
    /// `x = sqrt((eta - 1) / (eta + 1))`, the square root of the normal-incidence reflectance's
    /// square root).
    CyclesIor,
    /// The values are listed.
    List,
}

impl Mapping {
    /// The name used in axis specifications.
    pub fn name(self) -> &'static str {
        match self {
            Self::Lin => "lin",
            Self::Log => "log",
            Self::Sq => "sq",
            Self::CyclesIor => "cycles-ior",
            Self::List => "list",
        }
    }

    /// The value at parameter `x`.
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Self::Lin | Self::Log | Self::List => x,
            Self::Sq => x * x,
            Self::CyclesIor => (1.0 + x * x) / (1.0 - x * x),
        }
    }

    /// The formula, for the documentation written into C headers.
    pub fn formula(self) -> &'static str {
        match self {
            Self::Lin => "value = x",
            Self::Log => "value = x, geometrically spaced",
            Self::Sq => "value = x^2",
            Self::CyclesIor => "value = (1 + x^2) / (1 - x^2)",
            Self::List => "listed values",
        }
    }
}

/// The nodes of one axis: the parameters `x` and the tabulated values `mapping(x)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    pub mapping: Mapping,
    pub params: Vec<f64>,
    pub values: Vec<f64>,
}

impl Axis {
    /// An axis with the given mapping at the given parameters.
    pub fn from_params(mapping: Mapping, params: Vec<f64>) -> Self {
        let values = params.iter().map(|&x| mapping.apply(x)).collect();
        Self {
            mapping,
            params,
            values,
        }
    }

    /// An axis of listed values.
    pub fn list(values: Vec<f64>) -> Self {
        Self::from_params(Mapping::List, values)
    }

    /// An axis of listed values, as the text `v1,v2,...` gives them: finite, at most
    /// `MAX_NODES` of them, strictly increasing.
    pub fn listed(values: Vec<f64>) -> Result<Self, String> {
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return Err(format!("'{v}' is not a finite number"));
        }
        if values.len() > MAX_NODES {
            return Err(format!("more than {MAX_NODES} values"));
        }
        let axis = Self::list(values);
        axis.check_increasing()?;
        Ok(axis)
    }

    /// Checks that the values are strictly increasing (distinct nodes, in order).
    pub fn check_increasing(&self) -> Result<(), String> {
        match self.values.windows(2).find(|w| w[0] >= w[1]) {
            Some(w) => Err(format!(
                "values must be strictly increasing, got {} then {}",
                show(w[0]),
                show(w[1])
            )),
            None => Ok(()),
        }
    }

    /// Checks that the values are what the mapping gives at the parameters (one value per
    /// parameter), as in a file whose axis may have been edited.
    pub fn check_mapped(&self) -> Result<(), String> {
        let mapped = Self::from_params(self.mapping, self.params.clone());
        if mapped.values == self.values {
            return Ok(());
        }
        let name = self.mapping.name();
        if self.values.len() <= 10 && self.params.len() <= 10 {
            return Err(format!(
                "values {:?} are not what {name} gives at the parameters {:?}",
                self.values, self.params
            ));
        }
        // A long axis (up to MAX_NODES) is not echoed whole: its first difference is named.
        let (n, m) = (self.values.len(), self.params.len());
        Err(
            match self
                .values
                .iter()
                .zip(&mapped.values)
                .position(|(a, b)| a != b)
            {
                Some(k) => format!(
                    "values are not what {name} gives at the parameters: node {k} (from 0) is {}, \
                 {name} gives {} at the parameter {}",
                    show(self.values[k]),
                    show(mapped.values[k]),
                    show(self.params[k])
                ),
                None => format!("{n} values for {m} parameters (one value per parameter)"),
            },
        )
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// True when the axis has no node.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Checks that the axis has values, that they are what the mapping gives at the
    /// parameters ([`Axis::check_mapped`]), strictly increasing, finite and in `[lo, hi]` (`lo`
    /// excluded when `open_lo`), naming the axis in the error.
    pub(crate) fn check_range(
        &self,
        axis: &'static str,
        lo: f64,
        open_lo: bool,
        hi: f64,
    ) -> Result<(), SpecError> {
        let error = |message: String| SpecError::Axis { axis, message };
        if self.values.is_empty() {
            return Err(error("has no values".into()));
        }
        self.check_mapped().map_err(error)?;
        self.check_increasing().map_err(error)?;
        for &v in &self.values {
            let below = if open_lo { v <= lo } else { v < lo };
            if !v.is_finite() || below || v > hi {
                let open = if open_lo { "(" } else { "[" };
                return Err(SpecError::Axis {
                    axis,
                    message: format!(
                        "value {} is outside the supported range {open}{lo}, {hi}]",
                        show(v)
                    ),
                });
            }
        }
        Ok(())
    }
}

/// Largest number of nodes on one axis.
pub const MAX_NODES: usize = 4096;

/// An axis as given on a command line: `START:END:COUNT` (evenly spaced, both ends included),
/// `MAP:START:END:COUNT` with `MAP` one of `lin`, `log`, `sq`, `cycles-ior` ([`Mapping`]), or a
/// comma-separated list of values.
impl FromStr for Axis {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        let number = |t: &str| -> Result<f64, String> {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("'{t}' is not a finite number"))
        };
        let parts: Vec<&str> = s.split(':').collect();
        if parts.len() == 1 {
            let values = s.split(',').map(number).collect::<Result<Vec<_>, _>>()?;
            return Self::listed(values);
        }
        let (mapping, rest) = match parts.as_slice() {
            [m, _, _] if m.trim().starts_with(|c: char| c.is_ascii_alphabetic()) => {
                return Err(format!("'{s}' is not MAP:START:END:COUNT"));
            }
            [a, b, n] => (Mapping::Lin, [*a, *b, *n]),
            [m, a, b, n] => {
                let mapping = match m.trim() {
                    "lin" => Mapping::Lin,
                    "log" => Mapping::Log,
                    "sq" => Mapping::Sq,
                    "cycles-ior" => Mapping::CyclesIor,
                    other => {
                        return Err(format!(
                            "unknown mapping '{other}' (expected lin, log, sq or cycles-ior)"
                        ));
                    }
                };
                (mapping, [*a, *b, *n])
            }
            _ => {
                return Err(format!(
                    "'{s}' is neither [MAP:]START:END:COUNT nor a list of values"
                ));
            }
        };
        let (start, end) = (number(rest[0])?, number(rest[1])?);
        let count: usize = rest[2]
            .trim()
            .parse()
            .ok()
            .filter(|&n| (1..=MAX_NODES).contains(&n))
            .ok_or_else(|| format!("COUNT '{}' must be an integer in [1, {MAX_NODES}]", rest[2]))?;
        if count == 1 && start != end {
            return Err("COUNT 1 needs START = END".into());
        }
        if count > 1 && start >= end {
            return Err(format!("COUNT {count} needs START < END"));
        }
        if mapping == Mapping::Sq && start < 0.0 {
            return Err("sq needs START >= 0".into());
        }
        if mapping == Mapping::Log && !(start > 0.0 && end > 0.0) {
            return Err("log spacing needs START > 0 and END > 0".into());
        }
        if mapping == Mapping::CyclesIor
            && !((0.0..1.0).contains(&start) && (0.0..1.0).contains(&end))
        {
            return Err("cycles-ior needs 0 <= START, END < 1".into());
        }
        let params = (0..count)
            .map(|i| {
                let f = if count == 1 {
                    0.0
                } else {
                    i as f64 / (count - 1) as f64
                };
                match mapping {
                    // The ends exactly: exp(ln(x)) may miss x by an ulp.
                    Mapping::Log if f == 0.0 || f == 1.0 => start + (end - start) * f,
                    Mapping::Log => (start.ln() + (end.ln() - start.ln()) * f).exp(),
                    _ => start + (end - start) * f,
                }
            })
            .collect();
        let axis = Self::from_params(mapping, params);
        axis.check_increasing()?;
        Ok(axis)
    }
}

impl fmt::Display for Axis {
    /// `MAPPING, N nodes: x = ... -> value = ...`, the description written into C headers.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.mapping.name(), self.mapping.formula())?;
        if self.mapping != Mapping::List && self.mapping != Mapping::Lin {
            write!(f, "; x = [")?;
            for (i, x) in self.params.iter().enumerate() {
                write!(f, "{}{x}", if i > 0 { ", " } else { "" })?;
            }
            write!(f, "]")?;
        }
        write!(f, "; values = [")?;
        for (i, v) in self.values.iter().enumerate() {
            write!(f, "{}{v}", if i > 0 { ", " } else { "" })?;
        }
        write!(f, "]")
    }
}

/// The nodes of Blender Cycles' energy tables (`src/app/cycles_precompute.cpp`): `n` nodes
/// `clamp(i / (n - 1), lo, hi)`, mapped.
fn cycles_axis(mapping: Mapping, n: usize, lo: f64, hi: f64) -> Axis {
    let params = (0..n)
        .map(|i| (i as f64 / (n - 1) as f64).clamp(lo, hi))
        .collect();
    Axis::from_params(mapping, params)
}

/// Cycles' roughness axis of `n` nodes: `r = clamp(x / (n - 1), 1e-4, 1)`, `alpha = r^2`.
pub fn cycles_roughness(n: usize) -> Axis {
    cycles_axis(Mapping::Sq, n, 1e-4, 1.0)
}

/// Cycles' cosine axis of `n` nodes: `mu = clamp(y / (n - 1), 1e-4, 1)`.
pub fn cycles_mu(n: usize) -> Axis {
    cycles_axis(Mapping::Lin, n, 1e-4, 1.0)
}

/// Cycles' index-of-refraction axis of `n` nodes: `t = clamp(z / (n - 1), 1e-4, 0.99)`,
/// `eta = ior_from_F0(t^4) = (1 + t^2) / (1 - t^2)`.
pub fn cycles_ior(n: usize) -> Axis {
    cycles_axis(Mapping::CyclesIor, n, 1e-4, 0.99)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_ranges_mappings_and_lists() {
        let a: Axis = "0:1:5".parse().unwrap();
        assert_eq!(a.values, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        let a: Axis = "sq:0.5:1:2".parse().unwrap();
        assert_eq!(a.values, vec![0.25, 1.0]);
        let a: Axis = "log:0.01:1:3".parse().unwrap();
        assert!((a.values[1] - 0.1).abs() < 1e-15);
        let a: Axis = "log:1e-8:4:6".parse().unwrap();
        assert_eq!((a.values[0], a.values[5]), (1e-8, 4.0));
        let a: Axis = "1.5, 2,3".parse().unwrap();
        assert_eq!((a.mapping, a.values), (Mapping::List, vec![1.5, 2.0, 3.0]));
        let a: Axis = "cycles-ior:0.5:0.5:1".parse().unwrap();
        assert_eq!(a.values, vec![1.25 / 0.75]);
        for bad in [
            "",
            "a:1:2",
            "0:1:0",
            "0:1:x",
            "0:1",
            "cubic:0:1:3",
            "1:2:1",
            "log:0:1:3",
        ] {
            assert!(bad.parse::<Axis>().is_err(), "{bad}");
        }
    }

    #[test]
    fn nodes_must_be_distinct_and_increasing() {
        for (bad, message) in [
            ("0.5:0.5:3", "COUNT 3 needs START < END"),
            ("0.5:0.3:3", "COUNT 3 needs START < END"),
            ("0.3,0.3", "strictly increasing, got 0.3 then 0.3"),
            ("0.5,0.3", "strictly increasing, got 0.5 then 0.3"),
            ("sq:-2:1:3", "sq needs START >= 0"),
            (
                "1:1.0000000000000002:3",
                "strictly increasing, got 1 then 1",
            ),
        ] {
            let err = bad.parse::<Axis>().unwrap_err();
            assert!(err.contains(message), "{bad}: {err}");
        }
        assert_eq!(
            Axis::listed(vec![0.2, 0.1]).unwrap_err(),
            "values must be strictly increasing, got 0.2 then 0.1"
        );
        let a: Axis = "sq:0:1:3".parse().unwrap();
        assert_eq!(a.values, vec![0.0, 0.25, 1.0]);
    }

    #[test]
    fn values_must_be_what_the_mapping_gives() {
        let mut a: Axis = "0.1:0.5:3".parse().unwrap();
        a.values[1] = 0.2;
        let err = a
            .check_range("alpha", 0.0, false, 1.0)
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "alpha axis values [0.1, 0.2, 0.5] are not what lin gives at the parameters \
             [0.1, 0.30000000000000004, 0.5]"
        );
        a.values.pop();
        assert!(a.check_mapped().is_err());
        // A long axis is not echoed whole (a shard file's axis of 4096 nodes made a message of
        // 80 kB): its first difference is named.
        let mut long: Axis = "0.1:0.5:4096".parse().unwrap();
        long.values[7] = 0.2;
        let err = long.check_mapped().unwrap_err();
        assert!(
            err.starts_with(
                "values are not what lin gives at the parameters: node 7 (from 0) is 0.2"
            ) && err.len() < 200,
            "{err}"
        );
        long.values[7] = long.params[7];
        long.values.pop();
        assert_eq!(
            long.check_mapped().unwrap_err(),
            "4095 values for 4096 parameters (one value per parameter)"
        );
    }

    #[test]
    fn cycles_axes_follow_the_precompute_tool() {
        let r = cycles_roughness(16);
        assert_eq!(r.params[0], 1e-4);
        assert_eq!(r.values[0], 1e-8);
        assert_eq!(r.values[15], 1.0);
        assert!((r.values[3] - 0.04).abs() < 1e-16);
        let mu = cycles_mu(16);
        assert_eq!((mu.values[0], mu.values[15]), (1e-4, 1.0));
        let ior = cycles_ior(16);
        assert_eq!(ior.params[15], 0.99);
        assert!((ior.values[15] - 1.9801 / 0.0199).abs() < 1e-9);
        assert!((ior.values[1] - 226.0 / 224.0).abs() < 1e-15);
    }
}
