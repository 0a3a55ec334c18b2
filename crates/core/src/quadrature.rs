//! Gauss-Legendre quadrature.

/// An `n`-point Gauss-Legendre rule on [-1, 1], exact for polynomials of degree `2n - 1`.
#[derive(Debug, Clone, PartialEq)]
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl GaussLegendre {
    /// Computes the nodes and weights by Newton iteration on the Legendre polynomial `P_n`
    /// (accurate to rounding for `n` up to a few hundred). `n >= 1`.
    pub fn new(n: usize) -> Self {
        let n = n.max(1);
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        for i in 0..n.div_ceil(2) {
            // Tricomi's initial guess for the i-th root, then Newton.
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(n, x);
            dp = if d != 0.0 { d } else { dp };
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        Self { nodes, weights }
    }

    /// The nodes on [-1, 1] with their weights, in increasing order of the node.
    pub fn points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.nodes.iter().copied().zip(self.weights.iter().copied())
    }

    /// `integral_a^b f(x) dx` by this rule mapped to [a, b].
    pub fn integrate(&self, a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        let sum: f64 = self
            .nodes
            .iter()
            .zip(&self.weights)
            .map(|(&x, &w)| w * f(mid + half * x))
            .sum();
        sum * half
    }

    /// `integral f` over consecutive panels `[edges[k], edges[k+1]]`, each with this rule.
    pub fn integrate_panels(&self, edges: &[f64], mut f: impl FnMut(f64) -> f64) -> f64 {
        edges
            .windows(2)
            .filter(|e| e[1] > e[0])
            .map(|e| self.integrate(e[0], e[1], &mut f))
            .sum()
    }

    /// `integral_a^b f` where `f` behaves like `|x - a|^p` (p > 0 not an integer) near `a`:
    /// substitutes `x = a + (b - a) t^2`, which makes such integrands smooth in `t`. `a` may be
    /// the upper limit (`a > b`); the result is the integral from `min` to `max` either way.
    pub fn integrate_endpoint_singular(
        &self,
        a: f64,
        b: f64,
        mut f: impl FnMut(f64) -> f64,
    ) -> f64 {
        let len = b - a;
        let integral = self.integrate(0.0, 1.0, |t| 2.0 * len * t * f(a + len * t * t));
        integral * len.signum()
    }
}

/// `(P_n(x), P_n'(x))` by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    if n == 0 {
        return (1.0, 0.0);
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_of_degree_2n_minus_1_exactly() {
        let rule = GaussLegendre::new(8);
        let got = rule.integrate(-1.0, 2.0, |x| x.powi(15) - 3.0 * x.powi(4) + 1.0);
        let want = (2f64.powi(16) - 1.0) / 16.0 - 3.0 * (32.0 + 1.0) / 5.0 + 3.0;
        assert!((got - want).abs() < 1e-10 * want.abs(), "{got} vs {want}");
    }

    #[test]
    fn points_are_the_rule() {
        let rule = GaussLegendre::new(5);
        let by_points: f64 = rule.points().map(|(x, w)| w * x.exp()).sum();
        assert_eq!(by_points, rule.integrate(-1.0, 1.0, f64::exp));
        assert!(rule.points().is_sorted_by(|a, b| a.0 < b.0));
    }

    #[test]
    fn weights_sum_to_interval_length() {
        for n in [1, 2, 7, 64, 200] {
            let rule = GaussLegendre::new(n);
            assert!(
                (rule.integrate(0.0, 3.0, |_| 1.0) - 3.0).abs() < 1e-12,
                "n = {n}"
            );
        }
    }

    #[test]
    fn integrates_smooth_functions_accurately() {
        let rule = GaussLegendre::new(32);
        let got = rule.integrate(0.0, std::f64::consts::PI, f64::sin);
        assert!((got - 2.0).abs() < 1e-14);
    }
}
