//! Least-squares fitting of friction-law parameters to a measured friction
//! series, and the model comparison of Lishman et al. (2011), section 5.
//!
//! A measured series is `mu(t)` recorded while the apparatus's load point
//! followed a known [`Protocol`]. A law is judged by what the spring-slider
//! predicts for that protocol: the model's `mu` is the simulated spring force
//! over the normal load, linearly interpolated to the data times. Three models
//! are fitted and compared by mean squared error (MSE):
//!
//! * constant friction: the mean of the data ("a constant friction
//!   coefficient chosen as the average friction over the cycle");
//! * rate-dependent friction (eq. 2): `mu0` and `C1` free;
//! * rate-and-state friction (eqs. 3a/3b): `mu0`, `A`, `B` and `L` free.
//!
//! The two simulated models are fitted by Levenberg-Marquardt with a
//! central-difference Jacobian (each column costs two simulations: there is
//! no cheap analytic sensitivity of a whole stiff simulation). `A` and `L` are
//! fitted through their logarithms, so every trial point keeps them positive;
//! standard errors come from the Gauss-Newton covariance `s^2 (J^T J)^-1`,
//! `s^2 = SSR / (n - p)`, mapped back to physical units by the delta method.
//! They assume independent, equal-variance errors and a model that is
//! locally linear over a standard error, as usual for nonlinear least squares.

use std::cell::Cell;

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{storage::Owned, DMatrix, DVector, Dyn};
use serde::{Deserialize, Serialize};

use crate::amontons::Amontons;
use crate::any_law::Law;
use crate::error::{finite, positive, FrictionError};
use crate::params::RateStateParams;
use crate::protocol::Protocol;
use crate::rate_dependent::RateDependent;
use crate::rate_state::RateState;
use crate::spring_slider::{Apparatus, SpringSlider};

/// A measured friction series: times and friction coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct FitData {
    t_s: Vec<f64>,
    mu: Vec<f64>,
}

impl FitData {
    /// Checks the series: equal lengths, at least 3 points, every value
    /// finite, times strictly increasing.
    pub fn new(t_s: Vec<f64>, mu: Vec<f64>) -> Result<Self, FrictionError> {
        if t_s.len() != mu.len() {
            return Err(FrictionError::Fit(format!(
                "{} times but {} friction values",
                t_s.len(),
                mu.len()
            )));
        }
        if t_s.len() < 3 {
            return Err(FrictionError::Fit(format!(
                "{} data points; at least 3 are needed",
                t_s.len()
            )));
        }
        for (i, (&t, &m)) in t_s.iter().zip(&mu).enumerate() {
            if !t.is_finite() || !m.is_finite() {
                return Err(FrictionError::Fit(format!(
                    "data point {i} is not finite: t_s = {t}, mu = {m}"
                )));
            }
        }
        if let Some(i) = t_s.windows(2).position(|w| w[1] <= w[0]) {
            return Err(FrictionError::Fit(format!(
                "times must increase strictly: t_s[{}] = {} follows t_s[{i}] = {}",
                i + 1,
                t_s[i + 1],
                t_s[i]
            )));
        }
        Ok(Self { t_s, mu })
    }

    /// Times, s.
    pub fn t_s(&self) -> &[f64] {
        &self.t_s
    }

    /// Friction coefficients.
    pub fn mu(&self) -> &[f64] {
        &self.mu
    }

    /// Number of data points.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// Always `false`: a series has at least 3 points.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }
}

/// What was done to the sample while the series was recorded: the load-point
/// protocol, the apparatus, and the speed of the steady sliding it started
/// from (as in [`SpringSlider::new`]). Time 0 of the data is the start of the
/// protocol.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Experiment {
    protocol: Protocol,
    apparatus: Apparatus,
    initial_velocity_m_per_s: f64,
}

impl Experiment {
    /// Checks the apparatus (stiffness, normal load and time step finite and
    /// > 0), the protocol's segments and the initial velocity (finite).
    pub fn new(
        protocol: Protocol,
        apparatus: Apparatus,
        initial_velocity_m_per_s: f64,
    ) -> Result<Self, FrictionError> {
        // Both have public fields or derive Deserialize, so they may not have
        // gone through their own checks.
        let apparatus = Apparatus::new(
            apparatus.stiffness_n_per_m,
            apparatus.normal_load_n,
            apparatus.dt_s,
        )?;
        let protocol = Protocol::new(protocol.segments().to_vec())?;
        finite("initial_velocity_m_per_s", initial_velocity_m_per_s)?;
        Ok(Self {
            protocol,
            apparatus,
            initial_velocity_m_per_s,
        })
    }

    /// The load-point protocol.
    pub fn protocol(&self) -> &Protocol {
        &self.protocol
    }

    /// The apparatus (stiffness, normal load, time step).
    pub fn apparatus(&self) -> &Apparatus {
        &self.apparatus
    }

    /// Load-point speed of the initial steady sliding, m/s.
    pub fn initial_velocity_m_per_s(&self) -> f64 {
        self.initial_velocity_m_per_s
    }

    /// Checks that times are finite, non-decreasing and within the protocol.
    fn check_times(&self, t_s: &[f64]) -> Result<(), FrictionError> {
        let end = self.protocol.duration_s();
        // Sample times are accumulated step by step, so the protocol's end is
        // only known to rounding.
        let slack = 1e-9 * end;
        for (i, &t) in t_s.iter().enumerate() {
            if !(t.is_finite() && (0.0..=end + slack).contains(&t)) {
                return Err(FrictionError::Fit(format!(
                    "time t_s[{i}] = {t} is outside the protocol, [0, {end}] s"
                )));
            }
        }
        if let Some(i) = t_s.windows(2).position(|w| w[1] < w[0]) {
            return Err(FrictionError::Fit(format!(
                "times must not decrease: t_s[{}] < t_s[{i}]",
                i + 1
            )));
        }
        Ok(())
    }
}

/// The spring-slider's friction coefficient under `law` at the times `t_s`
/// (s, non-decreasing, within the protocol), linearly interpolated between
/// step ends.
pub fn predict(law: &Law, experiment: &Experiment, t_s: &[f64]) -> Result<Vec<f64>, FrictionError> {
    experiment.check_times(t_s)?;
    let mut out = Vec::with_capacity(t_s.len());
    simulate_at(law, experiment, t_s, &mut out);
    Ok(out)
}

/// [`predict`] without the checks on the times.
fn simulate_at(law: &Law, experiment: &Experiment, t_s: &[f64], out: &mut Vec<f64>) {
    out.clear();
    let mut slider = SpringSlider::new(
        law.clone(),
        experiment.apparatus,
        experiment.initial_velocity_m_per_s,
    );
    let mut prev = slider.sample();
    let mut next = 0;
    slider.run(&experiment.protocol, |s| {
        while next < t_s.len() && t_s[next] <= s.t_s {
            let span = s.t_s - prev.t_s;
            let w = if span > 0.0 {
                ((t_s[next] - prev.t_s) / span).clamp(0.0, 1.0)
            } else {
                1.0
            };
            out.push(prev.mu + w * (s.mu - prev.mu));
            next += 1;
        }
        prev = *s;
    });
    // Times within rounding of the end of the protocol.
    out.resize(t_s.len(), prev.mu);
}

/// One fitted parameter, in physical units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FittedParameter {
    /// Parameter name, as in the law's fields (`mu0`, `a`, `b`,
    /// `critical_slip_m`, `c1`, `mu`).
    pub name: String,
    /// Best-fit value.
    pub value: f64,
    /// Standard error from the least-squares covariance. Infinite when the
    /// data do not determine the parameters (singular `J^T J`).
    pub std_error: f64,
    /// Unit (`"1"` for dimensionless).
    pub unit: String,
}

/// The result of fitting one model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelFit {
    /// Model name: `constant`, `rate` or `rate-state`.
    pub model: String,
    /// Free parameters, with standard errors.
    pub parameters: Vec<FittedParameter>,
    /// The law with the fitted parameters (the fixed ones from the template).
    pub law: Law,
    /// Mean squared error, `ssr / n`.
    pub mse: f64,
    /// Sum of squared residuals.
    pub ssr: f64,
    /// Number of data points.
    pub n: usize,
    /// Whether the optimiser met a convergence criterion (rather than running
    /// out of evaluations or meeting a numerical failure). Always `true` for
    /// the constant model, which has a closed form.
    pub converged: bool,
    /// Why the optimiser stopped, for diagnostics.
    pub termination: String,
    /// Spring-slider simulations run for this fit (0 for the constant model).
    pub simulations: usize,
}

impl ModelFit {
    /// The parameter called `name`, if the model has one.
    pub fn parameter(&self, name: &str) -> Option<&FittedParameter> {
        self.parameters.iter().find(|p| p.name == name)
    }
}

/// The three models of Lishman et al. (2011), section 5, fitted to one series.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelComparison {
    /// Constant friction coefficient (the mean of the data).
    pub constant: ModelFit,
    /// Rate-dependent friction, eq. 2, evaluated at the load-point speed (see
    /// [`fit_rate_at_load_point`]).
    pub rate: ModelFit,
    /// Rate-and-state friction, eqs. 3a/3b.
    pub rate_state: ModelFit,
}

/// The best constant friction coefficient: the mean of the data. Its MSE is
/// the variance of the data about the mean; the standard error is that of the
/// mean, `s / sqrt(n)` with `s^2 = SSR / (n - 1)`.
pub fn fit_constant(data: &FitData) -> ModelFit {
    let n = data.len();
    let mean = data.mu.iter().sum::<f64>() / n as f64;
    let ssr: f64 = data.mu.iter().map(|m| (m - mean).powi(2)).sum();
    let std_error = (ssr / (n - 1) as f64 / n as f64).sqrt();
    ModelFit {
        model: "constant".into(),
        parameters: vec![FittedParameter {
            name: "mu".into(),
            value: mean,
            std_error,
            unit: "1".into(),
        }],
        law: Law::Amontons(Amontons { mu: mean }),
        mse: ssr / n as f64,
        ssr,
        n,
        converged: true,
        termination: "closed form".into(),
        simulations: 0,
    }
}

/// Fits `mu0`, `A`, `B` and `L` of the rate-and-state law; `V*`, the form and
/// the state law are those of `template`, whose parameters are the starting
/// guess.
pub fn fit_rate_state(
    data: &FitData,
    experiment: &Experiment,
    template: &RateState,
) -> Result<ModelFit, FrictionError> {
    template.params.validate()?;
    let p = template.params;
    let model = RateStateModel(*template);
    fit_simulated(
        &model,
        data,
        experiment,
        &[p.mu0, p.a, p.b, p.critical_slip_m],
    )
}

/// Fits `mu0` and `C1` of the rate-dependent law (eq. 2); `V*` and the floor
/// speed are those of `template`, whose `mu0` and `C1` are the starting guess.
///
/// On a stiff spring a velocity-weakening `C1` makes this law stick-slip (its
/// static friction, `mu` at the floor speed, exceeds its sliding friction),
/// so the least-squares surface has poor local minima. If the fit from the
/// template ends worse than the constant model, it is restarted from `mu0` =
/// the data mean, `C1 = 0`, and the better of the two is kept. At that point
/// the law is a constant coefficient, and for a protocol that starts in
/// steady sliding (`initial_velocity_m_per_s` != 0) and never reverses the
/// load point, the simulated friction there is exactly the data mean; since
/// Levenberg-Marquardt only accepts improving steps, the fit is then never
/// worse than the constant model (up to rounding).
pub fn fit_rate_dependent(
    data: &FitData,
    experiment: &Experiment,
    template: &RateDependent,
) -> Result<ModelFit, FrictionError> {
    finite("mu0", template.mu0)?;
    finite("c1", template.c1)?;
    positive("v_star_m_per_s", template.v_star_m_per_s)?;
    positive("v_floor_m_per_s", template.v_floor_m_per_s)?;
    let model = RateModel(*template);
    let first = fit_simulated(&model, data, experiment, &[template.mu0, template.c1]);
    let constant = fit_constant(data);
    if let Ok(fit) = &first {
        if fit.ssr <= constant.ssr {
            return first;
        }
    }
    let mean = constant.parameters[0].value;
    let mut restart = fit_simulated(&model, data, experiment, &[mean, 0.0])?;
    match first {
        Ok(mut fit) if fit.ssr <= restart.ssr => {
            fit.simulations += restart.simulations;
            Ok(fit)
        }
        Ok(fit) => {
            restart.simulations += fit.simulations;
            Ok(restart)
        }
        Err(_) => Ok(restart),
    }
}

/// Eq. 2 as a friction curve of the imposed speed, `mu(t) = mu0 + C1
/// ln(max(|V_lp(t)|, v_floor) / V*)`, fitted by linear least squares.
///
/// This is the paper's rate-dependent model of section 5: a coefficient that
/// follows the slip rate with no memory and no apparatus. Run through a
/// spring instead ([`fit_rate_dependent`]) the law stick-slips wherever
/// `C1 < 0`, because it has no direct effect to stabilise sliding, and the
/// fit then measures that instability rather than the rate dependence.
/// `V*` and the floor speed come from `template`.
pub fn fit_rate_at_load_point(
    data: &FitData,
    experiment: &Experiment,
    template: &RateDependent,
) -> Result<ModelFit, FrictionError> {
    positive("v_star_m_per_s", template.v_star_m_per_s)?;
    positive("v_floor_m_per_s", template.v_floor_m_per_s)?;
    let n = data.len();
    if n < 3 {
        return Err(FrictionError::Fit(
            "the rate model needs at least 3 points".into(),
        ));
    }
    let x: Vec<f64> = data
        .t_s
        .iter()
        .map(|&t| {
            let v = experiment
                .protocol()
                .velocity_at(t)
                .abs()
                .max(template.v_floor_m_per_s);
            (v / template.v_star_m_per_s).ln()
        })
        .collect();
    let mean_x = x.iter().sum::<f64>() / n as f64;
    let mean_y = data.mu.iter().sum::<f64>() / n as f64;
    let sxx: f64 = x.iter().map(|xi| (xi - mean_x).powi(2)).sum();
    let sxy: f64 = x
        .iter()
        .zip(&data.mu)
        .map(|(xi, yi)| (xi - mean_x) * (yi - mean_y))
        .sum();
    // A single imposed speed leaves C1 undetermined: report it as such.
    let c1 = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let mu0 = mean_y - c1 * mean_x;
    let ssr: f64 = x
        .iter()
        .zip(&data.mu)
        .map(|(xi, yi)| (yi - mu0 - c1 * xi).powi(2))
        .sum();
    let s2 = ssr / (n - 2) as f64;
    let (se_c1, se_mu0) = if sxx > 0.0 {
        (
            (s2 / sxx).sqrt(),
            (s2 * (1.0 / n as f64 + mean_x * mean_x / sxx)).sqrt(),
        )
    } else {
        (f64::INFINITY, f64::INFINITY)
    };
    let dimensionless = |name: &str, value, std_error| FittedParameter {
        name: name.into(),
        value,
        std_error,
        unit: "1".into(),
    };
    Ok(ModelFit {
        model: "rate".into(),
        parameters: vec![
            dimensionless("mu0", mu0, se_mu0),
            dimensionless("c1", c1, se_c1),
        ],
        law: Law::RateDependent(RateDependent {
            mu0,
            c1,
            ..*template
        }),
        mse: ssr / n as f64,
        ssr,
        n,
        converged: true,
        termination: "closed form (linear least squares in ln V)".into(),
        simulations: 0,
    })
}

/// Fits the three models of section 5 to one series, starting the rate-and-
/// state fit from `rate_state` and the rate-dependent fit from `rate`.
pub fn compare_models(
    data: &FitData,
    experiment: &Experiment,
    rate_state: &RateState,
    rate: &RateDependent,
) -> Result<ModelComparison, FrictionError> {
    Ok(ModelComparison {
        constant: fit_constant(data),
        rate: fit_rate_at_load_point(data, experiment, rate)?,
        rate_state: fit_rate_state(data, experiment, rate_state)?,
    })
}

/// How a free parameter is represented to the optimiser.
#[derive(Debug, Clone, Copy)]
enum Scale {
    /// As is: may take any sign.
    Linear,
    /// Through its logarithm: stays > 0 at every trial point.
    Log,
}

/// Description of one free parameter.
struct Spec {
    name: &'static str,
    unit: &'static str,
    scale: Scale,
}

/// A law family with some parameters free.
trait Model {
    /// Name reported in [`ModelFit::model`].
    fn name(&self) -> &'static str;
    /// The free parameters, in order.
    fn specs(&self) -> &'static [Spec];
    /// The law for physical parameter values, or `None` outside its domain.
    fn law(&self, values: &[f64]) -> Option<Law>;
}

struct RateStateModel(RateState);

impl Model for RateStateModel {
    fn name(&self) -> &'static str {
        "rate-state"
    }

    fn specs(&self) -> &'static [Spec] {
        const SPECS: [Spec; 4] = [
            Spec {
                name: "mu0",
                unit: "1",
                scale: Scale::Linear,
            },
            Spec {
                name: "a",
                unit: "1",
                scale: Scale::Log,
            },
            // B is linear so that B = 0 (no state effect) is reachable and
            // its error bar symmetric; the law's own check rejects B < 0.
            Spec {
                name: "b",
                unit: "1",
                scale: Scale::Linear,
            },
            Spec {
                name: "critical_slip_m",
                unit: "m",
                scale: Scale::Log,
            },
        ];
        &SPECS
    }

    fn law(&self, v: &[f64]) -> Option<Law> {
        let params = RateStateParams {
            mu0: v[0],
            a: v[1],
            b: v[2],
            v_star_m_per_s: self.0.params.v_star_m_per_s,
            critical_slip_m: v[3],
        };
        params.validate().ok()?;
        Some(Law::RateState(RateState::new(
            params,
            self.0.form,
            self.0.state_law,
        )))
    }
}

struct RateModel(RateDependent);

impl Model for RateModel {
    fn name(&self) -> &'static str {
        "rate"
    }

    fn specs(&self) -> &'static [Spec] {
        const SPECS: [Spec; 2] = [
            Spec {
                name: "mu0",
                unit: "1",
                scale: Scale::Linear,
            },
            Spec {
                name: "c1",
                unit: "1",
                scale: Scale::Linear,
            },
        ];
        &SPECS
    }

    fn law(&self, v: &[f64]) -> Option<Law> {
        if !(v[0].is_finite() && v[1].is_finite()) {
            return None;
        }
        Some(Law::RateDependent(RateDependent {
            mu0: v[0],
            c1: v[1],
            ..self.0
        }))
    }
}

/// Relative finite-difference step. The per-step solver converges to about
/// 1e-12, so the central-difference error is roughly `1e-12 / h + h^2`,
/// smallest near 1e-4.
const FD_STEP: f64 = 1e-4;
/// Smallest parameter magnitude the step is taken relative to, so that a
/// linear parameter at zero (e.g. `C1`) still gets a usable step; friction
/// coefficients are of order 0.1.
const FD_FLOOR: f64 = 0.1;
/// Residual reported at trial points outside a law's domain or where the
/// simulation is not finite: large enough that the optimiser rejects the step
/// and shrinks its trust region, finite so that it does not stop.
const BARRIER_RESIDUAL: f64 = 1e6;

/// The least-squares problem handed to Levenberg-Marquardt, in the
/// optimiser's coordinates (log of the `Scale::Log` parameters).
struct Problem<'a, M: Model> {
    model: &'a M,
    data: &'a FitData,
    experiment: &'a Experiment,
    x: DVector<f64>,
    /// Residuals at `x`, `None` outside the domain.
    residuals: Option<DVector<f64>>,
    simulations: Cell<usize>,
}

impl<M: Model> Problem<'_, M> {
    fn physical(&self, x: &DVector<f64>) -> Vec<f64> {
        self.model
            .specs()
            .iter()
            .zip(x.iter())
            .map(|(s, &xi)| match s.scale {
                Scale::Linear => xi,
                Scale::Log => xi.exp(),
            })
            .collect()
    }

    /// Model minus data at `x`, or `None` if `x` is outside the domain or
    /// the simulation is not finite there.
    fn evaluate(&self, x: &DVector<f64>) -> Option<DVector<f64>> {
        let law = self.model.law(&self.physical(x))?;
        self.simulations.set(self.simulations.get() + 1);
        let mut mu = Vec::with_capacity(self.data.len());
        simulate_at(&law, self.experiment, &self.data.t_s, &mut mu);
        let r = DVector::from_iterator(mu.len(), mu.iter().zip(&self.data.mu).map(|(m, d)| m - d));
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    fn step(&self, j: usize) -> f64 {
        match self.model.specs()[j].scale {
            Scale::Linear => FD_STEP * self.x[j].abs().max(FD_FLOOR),
            Scale::Log => FD_STEP,
        }
    }
}

impl<M: Model> LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, M> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.x.copy_from(x);
        self.residuals = self.evaluate(x);
    }

    fn params(&self) -> DVector<f64> {
        self.x.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        Some(
            self.residuals
                .clone()
                .unwrap_or_else(|| DVector::from_element(self.data.len(), BARRIER_RESIDUAL)),
        )
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let centre = self.residuals.as_ref()?;
        let mut jac = DMatrix::zeros(centre.len(), self.x.len());
        for j in 0..self.x.len() {
            let h = self.step(j);
            let mut shifted = self.x.clone();
            shifted[j] += h;
            let plus = self.evaluate(&shifted);
            shifted[j] = self.x[j] - h;
            let minus = self.evaluate(&shifted);
            // One-sided next to the edge of the domain (e.g. B near 0).
            let column = match (plus, minus) {
                (Some(p), Some(m)) => (p - m) / (2.0 * h),
                (Some(p), None) => (p - centre) / h,
                (None, Some(m)) => (centre - m) / h,
                (None, None) => return None,
            };
            jac.set_column(j, &column);
        }
        Some(jac)
    }
}

/// Fits `model` from the physical starting values `start` and computes the
/// standard errors at the optimum.
fn fit_simulated<M: Model>(
    model: &M,
    data: &FitData,
    experiment: &Experiment,
    start: &[f64],
) -> Result<ModelFit, FrictionError> {
    let specs = model.specs();
    let (n, p) = (data.len(), specs.len());
    if n <= p {
        return Err(FrictionError::Fit(format!(
            "{n} data points cannot determine {p} parameters of the {} model",
            model.name()
        )));
    }
    experiment.check_times(&data.t_s)?;
    let mut x0 = DVector::zeros(p);
    for (j, (s, &v)) in specs.iter().zip(start).enumerate() {
        x0[j] = match s.scale {
            Scale::Linear => v,
            Scale::Log => v.ln(),
        };
    }
    if model.law(start).is_none() || x0.iter().any(|v| !v.is_finite()) {
        return Err(FrictionError::Fit(format!(
            "starting parameters {start:?} are outside the {} model's domain",
            model.name()
        )));
    }
    let mut problem = Problem {
        model,
        data,
        experiment,
        x: x0.clone(),
        residuals: None,
        simulations: Cell::new(0),
    };
    problem.set_params(&x0);
    if problem.residuals.is_none() {
        return Err(FrictionError::Fit(format!(
            "the {} model's simulation is not finite at the starting parameters {start:?}",
            model.name()
        )));
    }

    // The residuals carry finite-difference noise of order 1e-8, so machine-
    // precision tolerances would only burn simulations; 1e-10 in relative SSR
    // is far below any statistical meaning.
    let (problem, report) = LevenbergMarquardt::new()
        .with_ftol(1e-10)
        .with_xtol(1e-10)
        .with_gtol(1e-10)
        .with_patience(30)
        .minimize(problem);

    let r = problem.residuals.as_ref().ok_or_else(|| {
        FrictionError::Fit(format!(
            "the {} fit ended outside the model's domain ({:?})",
            model.name(),
            report.termination
        ))
    })?;
    let ssr = r.norm_squared();
    let values = problem.physical(&problem.x);
    let law = model.law(&values).ok_or_else(|| {
        FrictionError::Fit(format!("fitted {} parameters are invalid", model.name()))
    })?;
    let internal_errors = match problem.jacobian() {
        Some(jac) => standard_errors(&jac, ssr / (n - p) as f64),
        None => vec![f64::INFINITY; p],
    };
    let parameters = specs
        .iter()
        .zip(values.iter().zip(&internal_errors))
        .map(|(s, (&value, &se))| FittedParameter {
            name: s.name.into(),
            value,
            // d(e^y) = e^y dy: a log-space error is a relative error.
            std_error: match s.scale {
                Scale::Linear => se,
                Scale::Log => value * se,
            },
            unit: s.unit.into(),
        })
        .collect();
    Ok(ModelFit {
        model: model.name().into(),
        parameters,
        law,
        mse: ssr / n as f64,
        ssr,
        n,
        converged: report.termination.was_successful(),
        termination: format!("{:?}", report.termination),
        simulations: problem.simulations.get(),
    })
}

/// Square roots of the diagonal of `s2 (J^T J)^-1`; infinite if `J^T J` is
/// singular.
fn standard_errors(jac: &DMatrix<f64>, s2: f64) -> Vec<f64> {
    let p = jac.ncols();
    // Scaling the columns to unit norm first keeps the factorisation well
    // conditioned when parameters differ in sensitivity by orders of
    // magnitude (mu0 against L in log space).
    let norms: Vec<f64> = jac.column_iter().map(|c| c.norm()).collect();
    if norms.iter().any(|&c| !(c.is_finite() && c > 0.0)) {
        return vec![f64::INFINITY; p];
    }
    let mut scaled = jac.clone();
    for (j, &c) in norms.iter().enumerate() {
        scaled.column_mut(j).unscale_mut(c);
    }
    let Some(chol) = (scaled.transpose() * &scaled).cholesky() else {
        return vec![f64::INFINITY; p];
    };
    let inv = chol.inverse();
    (0..p)
        .map(|j| (s2 * inv[(j, j)]).sqrt() / norms[j])
        .collect()
}
