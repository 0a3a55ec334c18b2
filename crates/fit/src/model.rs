//! The models fitted to measurements: their NDF family and shape ([`ModelKind`], [`Gamma`]),
//! what to fit ([`ModelSpec`]) and a fully specified model of the measured quantity
//! ([`Model`]), which evaluates itself ([`Model::predict`]).

use serde::{Deserialize, Serialize};
use stfit_core::bsdf::Masking;
use stfit_core::error::show;
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT};
use stfit_core::walk::ScatteringOrders;

use crate::data::Measurement;
use crate::fit::FitError;
use crate::forward::Forward;

/// The NDF family of a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    Beckmann,
    Ggx,
    StudentT,
}

impl ModelKind {
    /// The model's name as used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::Beckmann => "beckmann",
            Self::Ggx => "ggx",
            Self::StudentT => "student-t",
        }
    }
}

impl std::str::FromStr for ModelKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "beckmann" => Ok(Self::Beckmann),
            "ggx" => Ok(Self::Ggx),
            "student-t" => Ok(Self::StudentT),
            _ => Err(format!(
                "unknown model '{s}' (expected beckmann, ggx or student-t)"
            )),
        }
    }
}

/// The Student-T shape gamma of a model and how it was obtained: not applicable (Beckmann and
/// GGX), held fixed at a value, or free. In a fitted or simulated model `Free` carries the
/// value (`Gamma<f64>`, the default); in a [`ModelSpec`], which only says what to fit, it
/// carries nothing (`Gamma<()>`).
///
/// In JSON a `Gamma` is the two keys `gamma` (the value, `null` when not applicable) and
/// `gamma_fixed` (true when held fixed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Gamma<T = f64> {
    /// Beckmann and GGX have no shape parameter.
    NotApplicable,
    /// Held at this value rather than fitted.
    Fixed(f64),
    /// Fitted (or to be fitted).
    Free(T),
}

impl<T> Gamma<T> {
    /// Whether gamma is held fixed.
    pub fn is_fixed(&self) -> bool {
        matches!(self, Self::Fixed(_))
    }

    /// Whether gamma is (to be) fitted.
    pub fn is_free(&self) -> bool {
        matches!(self, Self::Free(_))
    }
}

impl Gamma {
    /// The value of gamma, `None` when not applicable.
    pub fn value(&self) -> Option<f64> {
        match *self {
            Self::NotApplicable => None,
            Self::Fixed(g) | Self::Free(g) => Some(g),
        }
    }
}

/// The JSON form of a [`Gamma`]: `gamma` and `gamma_fixed`.
#[derive(Serialize, Deserialize)]
struct GammaKeys {
    gamma: Option<f64>,
    gamma_fixed: bool,
}

impl Serialize for Gamma {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        GammaKeys {
            gamma: self.value(),
            gamma_fixed: self.is_fixed(),
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for Gamma {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let keys = GammaKeys::deserialize(d)?;
        match (keys.gamma, keys.gamma_fixed) {
            (None, false) => Ok(Self::NotApplicable),
            (Some(g), false) => Ok(Self::Free(g)),
            (Some(g), true) => Ok(Self::Fixed(g)),
            (None, true) => Err(serde::de::Error::custom(
                "gamma_fixed is true but gamma is null",
            )),
        }
    }
}

/// A model to fit: a family and, for Student-T, whether gamma is fitted or held at a value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelSpec {
    kind: ModelKind,
    gamma: Gamma<()>,
}

impl ModelSpec {
    /// Beckmann.
    pub fn beckmann() -> Self {
        Self {
            kind: ModelKind::Beckmann,
            gamma: Gamma::NotApplicable,
        }
    }

    /// GGX.
    pub fn ggx() -> Self {
        Self {
            kind: ModelKind::Ggx,
            gamma: Gamma::NotApplicable,
        }
    }

    /// Student-T with gamma fitted.
    pub fn student_t() -> Self {
        Self {
            kind: ModelKind::StudentT,
            gamma: Gamma::Free(()),
        }
    }

    /// Student-T with gamma held at `gamma` (> 3/2, checked by the fit).
    pub fn student_t_fixed(gamma: f64) -> Self {
        Self {
            kind: ModelKind::StudentT,
            gamma: Gamma::Fixed(gamma),
        }
    }

    /// The model of `kind`, with gamma held at `fixed_gamma` if given (Student-T only).
    pub fn new(kind: ModelKind, fixed_gamma: Option<f64>) -> Result<Self, FitError> {
        match (kind, fixed_gamma) {
            (ModelKind::StudentT, Some(g)) => Ok(Self::student_t_fixed(g)),
            (ModelKind::StudentT, None) => Ok(Self::student_t()),
            (kind, Some(_)) => Err(FitError::InvalidSpec(format!(
                "a fixed gamma applies to student-t only, not {}",
                kind.name()
            ))),
            (ModelKind::Beckmann, None) => Ok(Self::beckmann()),
            (ModelKind::Ggx, None) => Ok(Self::ggx()),
        }
    }

    /// The NDF family.
    pub fn kind(&self) -> ModelKind {
        self.kind
    }

    /// What is done with gamma.
    pub fn gamma(&self) -> Gamma<()> {
        self.gamma
    }

    /// The model as named in messages: `student-t (gamma = 3)` for a fixed shape.
    pub fn label(&self) -> String {
        label(self.kind, &self.gamma)
    }
}

/// A model family as named in messages, with its gamma if held fixed.
fn label<T>(kind: ModelKind, gamma: &Gamma<T>) -> String {
    match gamma {
        Gamma::Fixed(g) => format!("{} (gamma = {g})", kind.name()),
        _ => kind.name().to_owned(),
    }
}

/// The four models of `--model all`, in this order: Beckmann, GGX, Student-T with gamma fixed
/// at 3 (the seed paper's Figure 1), Student-T with free gamma.
pub fn all_models() -> [ModelSpec; 4] {
    [
        ModelSpec::beckmann(),
        ModelSpec::ggx(),
        ModelSpec::student_t_fixed(3.0),
        ModelSpec::student_t(),
    ]
}

/// A fully specified model of the measured quantity `L`: NDF, calibration scale, the glass and
/// the scattering computed. A fit finds one ([`crate::FitResult::model`]), `stfit synth`
/// simulates one, and [`Model::predict`] evaluates it.
///
/// With `orders` single, `L = scale * f(wi, wo) * cos(theta_i) / eta^2` with Walter et al.'s
/// single-scattering `f` and the chosen `masking`. With `orders` all,
/// `f = f_single + f_multi`: the single-scattering BSDF with height-correlated masking (exactly
/// the random walk's order 1) plus the walk's orders >= 2, estimated from `walks` walks per
/// incident direction seeded from `seed` (common random numbers: the same numbers at every
/// evaluation, so the model is a deterministic function of its parameters).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Model {
    /// The NDF family (JSON key `model`).
    #[serde(rename = "model")]
    pub kind: ModelKind,
    pub alpha: f64,
    #[serde(flatten)]
    pub gamma: Gamma,
    pub scale: f64,
    /// Relative index of refraction `n_inside / n_outside` of the glass.
    pub eta: f64,
    pub masking: Masking,
    /// `single` or `all`.
    pub orders: ScatteringOrders,
    /// Walks per incident direction of the orders >= 2 term (`null` for single scattering).
    pub walks: Option<u64>,
    /// Seed of those walks (`null` for single scattering).
    pub seed: Option<u64>,
}

impl Model {
    /// The single-scattering model of `kind` with roughness `alpha`, shape `gamma` (for
    /// Student-T; [`Gamma::NotApplicable`] otherwise) and `scale`, for the default glass
    /// ([`DEFAULT_ETA`](crate::DEFAULT_ETA)) with separable masking, as the published fits
    /// used; change any field with struct update syntax.
    ///
    /// ```
    /// use stfit_fit::{Gamma, Model, ModelKind};
    ///
    /// let frosted = Model::single(ModelKind::StudentT, 0.42, Gamma::Fixed(2.7), 1.0);
    /// let l = frosted.predict(&[(0.0, 180.0), (30.0, 170.0)])?;
    /// assert!(l[0] > l[1]);
    /// # Ok::<(), stfit_fit::FitError>(())
    /// ```
    pub fn single(kind: ModelKind, alpha: f64, gamma: Gamma, scale: f64) -> Self {
        Self {
            kind,
            alpha,
            gamma,
            scale,
            eta: crate::DEFAULT_ETA,
            masking: Masking::Separable,
            orders: ScatteringOrders::Single,
            walks: None,
            seed: None,
        }
    }

    /// The model as named in messages: `student-t (gamma = 3)` for a fixed shape.
    pub fn label(&self) -> String {
        label(self.kind, &self.gamma)
    }

    /// The model's NDF, or the parameter error for alpha <= 0, gamma <= 3/2, non-finite values
    /// or a gamma that does not fit the family.
    pub fn ndf(&self) -> Result<AnyNdf, FitError> {
        Ok(match (self.kind, self.gamma.value()) {
            (ModelKind::Beckmann, None) => Beckmann::new(self.alpha)?.into(),
            (ModelKind::Ggx, None) => Ggx::new(self.alpha)?.into(),
            (ModelKind::StudentT, Some(g)) => StudentT::new(self.alpha, g)?.into(),
            (ModelKind::StudentT, None) => {
                return Err(FitError::InvalidSpec("student-t needs a gamma".into()));
            }
            (_, Some(_)) => {
                return Err(FitError::InvalidSpec(
                    "gamma is a Student-T parameter; beckmann and ggx take none".into(),
                ));
            }
        })
    }

    /// Checks that the model can be evaluated: a valid NDF (alpha, gamma in their supported
    /// ranges), a finite scale > 0, a valid eta, `single` or `all` orders with a masking they
    /// allow (for `all`, gamma >= 1.501, where walks stay short), and walks and a seed exactly
    /// when the orders need them.
    pub fn check(&self) -> Result<(), FitError> {
        self.ndf()?;
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(FitError::InvalidSpec(format!(
                "scale must be finite and > 0, got {}",
                show(self.scale)
            )));
        }
        stfit_core::error::check_eta(self.eta)?;
        crate::options::check_orders(self.orders, self.masking)?;
        if let (ScatteringOrders::All, Some(g)) = (self.orders, self.gamma.value()) {
            stfit_core::error::check_walk_gamma(g)?;
        }
        match (self.orders, self.walks, self.seed) {
            (ScatteringOrders::Single, None, None) => Ok(()),
            (ScatteringOrders::Single, _, _) => Err(FitError::InvalidSpec(
                "walks and seed apply only to orders all".into(),
            )),
            (_, Some(w), Some(_)) => {
                stfit_core::walk::check_walks(w)?;
                Ok(())
            }
            _ => Err(FitError::InvalidSpec(
                "orders all need walks and a seed".into(),
            )),
        }
    }

    /// `L` at the in-plane configurations `(theta_i_deg, theta_o_deg)` (the data convention),
    /// computed in one batch: the NDF-independent geometry once per pair, Smith `Lambda` once
    /// per distinct direction, the walks once per incidence angle.
    pub fn predict(&self, angles: &[(f64, f64)]) -> Result<Vec<f64>, FitError> {
        let points: Vec<Measurement> = angles
            .iter()
            .map(|&(ti, to)| Measurement::in_plane(ti, to, 0.0, 1.0))
            .collect();
        self.predict_points(&points)
    }

    /// The model's value at every measured point, in that point's quantity (`L` of an in-plane
    /// point, the BSDF of a general one), in one batch as [`Model::predict`].
    /// Points whose angles are outside the data format's ranges are refused.
    pub fn predict_points(&self, points: &[Measurement]) -> Result<Vec<f64>, FitError> {
        let forward = self.forward(points)?;
        let mut out = Vec::with_capacity(points.len());
        forward.unit_model(&self.ndf()?, self.eta, &mut out)?;
        for (k, v) in out.iter_mut().enumerate() {
            let unit = *v;
            *v *= self.scale;
            if !v.is_finite() || (unit != 0.0 && *v == 0.0) {
                return Err(FitError::NotRepresentable(format!(
                    "point {} (counting from 1): the model value {unit:e} times the scale {:e} \
                     is not a representable number",
                    k + 1,
                    self.scale
                )));
            }
        }
        Ok(out)
    }

    /// Estimated wall time, in seconds, of the random walks of [`Model::predict_points`] at
    /// `points` on rayon's current pool, for a note before a long run: a pilot run of the same
    /// walks ([`Forward::walk_seconds`]: random numbers of its own, at most a sixteenth of the
    /// run's work); 0 for single scattering. Refuses what [`Model::predict_points`] refuses.
    pub fn walk_seconds(&self, points: &[Measurement]) -> Result<f64, FitError> {
        Ok(self.forward(points)?.walk_seconds(&self.ndf()?, self.eta)?)
    }

    /// The forward model of [`Model::predict_points`] at `points`, after checking the model
    /// and the points' angles.
    fn forward(&self, points: &[Measurement]) -> Result<Forward, FitError> {
        self.check()?;
        for (index, p) in points.iter().enumerate() {
            p.check_angles().map_err(|reason| FitError::InvalidData {
                sample: "predicted points".into(),
                index,
                reason,
            })?;
        }
        let pairs: Vec<_> = points.iter().map(Measurement::directions).collect();
        let quantity = points.iter().map(Measurement::quantity).collect();
        Forward::new(
            &pairs,
            quantity,
            self.masking,
            self.orders,
            self.walks.unwrap_or(0),
            self.seed.unwrap_or(0),
        )
    }
}
