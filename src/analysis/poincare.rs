use super::AnalysisError;
use crate::numeric::{hermite_weights, illinois, Bracket, Direction, RootOptions};

/// Width of the final bracket of the Hermite search, in the interval's parameter `θ ∈ [0, 1]`.
const THETA_TOL: f64 = 1e-14;
/// Most evaluations of `h` per Hermite search: the root finder needs at most about four times
/// the 47 steps of bisection down to [`THETA_TOL`].
const MAX_STEPS: usize = 200;

/// One crossing of the section.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct Crossing {
    /// Index `k` of the sample that starts the interval `[t_k, t_{k+1}]` holding the crossing.
    pub interval: usize,
    /// Interpolated time of the crossing.
    pub t: f64,
    /// Interpolated state at the crossing.
    pub state: Vec<f64>,
    /// `true` for a rising crossing, `false` for a falling one.
    pub rising: bool,
    /// Times `(lo, hi)` between which `h` changes sign on the interpolant: the final bracket of
    /// the search (`(t, t)` for linear interpolation, solved in closed form).
    pub bracket: (f64, f64),
    /// Whether the search ended by its tolerance with a valid bracket (always `true` for
    /// linear interpolation). `false`: the crossing lies in `bracket`, but `t` and `state` are
    /// not located to the tolerance.
    pub converged: bool,
}

fn check_inputs<S: AsRef<[f64]>>(times: &[f64], states: &[S]) -> Result<usize, AnalysisError> {
    if times.len() != states.len() {
        return Err(AnalysisError::LengthMismatch {
            first: "times",
            first_len: times.len(),
            second: "states",
            second_len: states.len(),
        });
    }
    let dim = states.first().map_or(0, |s| s.as_ref().len());
    for (index, s) in states.iter().enumerate() {
        if s.as_ref().len() != dim {
            return Err(AnalysisError::DimensionMismatch {
                index,
                expected: dim,
                found: s.as_ref().len(),
            });
        }
    }
    for (index, &t) in times.iter().enumerate() {
        if !t.is_finite() {
            return Err(AnalysisError::InvalidValue {
                name: "times[i]",
                value: t,
                expected: "a finite time",
            });
        }
        if index > 0 && t <= times[index - 1] {
            return Err(AnalysisError::TimesNotIncreasing {
                index,
                previous: times[index - 1],
                time: t,
            });
        }
    }
    Ok(dim)
}

/// Evaluates `h` at every sample and reports the intervals holding a crossing of `direction`.
fn sign_changes<S, H>(
    times: &[f64],
    states: &[S],
    section: &H,
    direction: Direction,
) -> Result<Vec<(usize, f64, f64, bool)>, AnalysisError>
where
    S: AsRef<[f64]>,
    H: Fn(f64, &[f64]) -> f64,
{
    let mut hs = Vec::with_capacity(times.len());
    for (index, (t, s)) in times.iter().zip(states).enumerate() {
        let h = section(*t, s.as_ref());
        if h.is_nan() {
            return Err(AnalysisError::NonFiniteSample {
                index,
                component: 0,
                value: h,
            });
        }
        hs.push(h);
    }
    let mut out = Vec::new();
    for k in 0..hs.len().saturating_sub(1) {
        let (a, b) = (hs[k], hs[k + 1]);
        let rising = a < 0.0 && b >= 0.0;
        let falling = a > 0.0 && b <= 0.0;
        let wanted = match direction {
            Direction::Rising => rising,
            Direction::Falling => falling,
            Direction::Either => rising || falling,
        };
        if wanted {
            out.push((k, a, b, rising));
        }
    }
    Ok(out)
}

/// Crossings of the section `h(t, x) = 0`, located by linear interpolation.
///
/// `states[k]` is the state at `times[k]`; the section function is called once per sample.
///
/// # Errors
///
/// [`AnalysisError::LengthMismatch`] if `times` and `states` differ in length,
/// [`AnalysisError::DimensionMismatch`] if the states differ in length,
/// [`AnalysisError::InvalidValue`] / [`AnalysisError::TimesNotIncreasing`] if the times are not
/// finite and strictly increasing, [`AnalysisError::NonFiniteSample`] if `h` returns NaN
/// (`index` is the sample).
///
/// ```
/// use jeffcott::analysis::section_crossings;
/// use jeffcott::numeric::Direction;
/// let times: Vec<f64> = (0..=100).map(|k| k as f64 * 0.1).collect();
/// let states: Vec<[f64; 1]> = times.iter().map(|t| [t.sin()]).collect();
/// let c = section_crossings(&times, &states, |_, x| x[0], Direction::Falling).unwrap();
/// assert!((c[0].t - std::f64::consts::PI).abs() < 1e-2);
/// ```
pub fn section_crossings<S, H>(
    times: &[f64],
    states: &[S],
    section: H,
    direction: Direction,
) -> Result<Vec<Crossing>, AnalysisError>
where
    S: AsRef<[f64]>,
    H: Fn(f64, &[f64]) -> f64,
{
    check_inputs(times, states)?;
    let changes = sign_changes(times, states, &section, direction)?;
    Ok(changes
        .into_iter()
        .map(|(k, a, b, rising)| {
            let theta = if a == b { 1.0 } else { a / (a - b) };
            let x0 = states[k].as_ref();
            let x1 = states[k + 1].as_ref();
            let t = times[k] + theta * (times[k + 1] - times[k]);
            Crossing {
                interval: k,
                t,
                bracket: (t, t),
                converged: true,
                state: x0
                    .iter()
                    .zip(x1)
                    .map(|(u, v)| u + theta * (v - u))
                    .collect(),
                rising,
            }
        })
        .collect())
}

/// Cubic Hermite interpolation of one interval at `theta ∈ [0, 1]`.
fn hermite(x0: &[f64], x1: &[f64], d0: &[f64], d1: &[f64], dt: f64, theta: f64) -> Vec<f64> {
    let [h00, h10, h01, h11] = hermite_weights(theta);
    (0..x0.len())
        .map(|c| h00 * x0[c] + h10 * dt * d0[c] + h01 * x1[c] + h11 * dt * d1[c])
        .collect()
}

/// Crossings of the section `h(t, x) = 0`, located on the cubic Hermite interpolant built from
/// the states and their time derivatives `derivatives[k] = x'(t_k)`.
///
/// The crossing parameter `θ` is found by [`illinois`] in at most
/// 200 evaluations, stopping when the bracket is narrower than `1e-14` (relative to the
/// interval); the section function is called about ten extra times per crossing for a smooth
/// `h`. Each crossing carries its final bracket and whether the search converged (see the
/// [module docs](super)).
///
/// # Errors
///
/// As [`section_crossings`], plus [`AnalysisError::LengthMismatch`] /
/// [`AnalysisError::DimensionMismatch`] if `derivatives` does not match `states`.
pub fn section_crossings_hermite<S, D, H>(
    times: &[f64],
    states: &[S],
    derivatives: &[D],
    section: H,
    direction: Direction,
) -> Result<Vec<Crossing>, AnalysisError>
where
    S: AsRef<[f64]>,
    D: AsRef<[f64]>,
    H: Fn(f64, &[f64]) -> f64,
{
    let dim = check_inputs(times, states)?;
    if derivatives.len() != states.len() {
        return Err(AnalysisError::LengthMismatch {
            first: "states",
            first_len: states.len(),
            second: "derivatives",
            second_len: derivatives.len(),
        });
    }
    for (index, d) in derivatives.iter().enumerate() {
        if d.as_ref().len() != dim {
            return Err(AnalysisError::DimensionMismatch {
                index,
                expected: dim,
                found: d.as_ref().len(),
            });
        }
    }
    let changes = sign_changes(times, states, &section, direction)?;
    let mut out = Vec::with_capacity(changes.len());
    for (k, a, b, rising) in changes {
        let (x0, x1) = (states[k].as_ref(), states[k + 1].as_ref());
        let (d0, d1) = (derivatives[k].as_ref(), derivatives[k + 1].as_ref());
        let (t0, dt) = (times[k], times[k + 1] - times[k]);
        let eval = |theta: f64| -> (f64, Vec<f64>) {
            let x = hermite(x0, x1, d0, d1, dt, theta);
            (section(t0 + theta * dt, &x), x)
        };
        let opts = RootOptions::default()
            .with_tol(THETA_TOL)
            .with_max_evaluations(MAX_STEPS);
        // `a`, `b` change sign (`sign_changes`); were they not a bracket, the interval's ends
        // are reported, not converged.
        let found = illinois((0.0, a), (1.0, b), &opts, |theta| eval(theta).0).unwrap_or(Bracket {
            lo: 0.0,
            g_lo: a,
            hi: 1.0,
            g_hi: b,
            evaluations: 0,
            converged: false,
            nan_at: None,
        });
        // The end to report: the one with the smaller |h| (NaN counts as infinite), `hi` (the
        // side after the crossing) on a tie.
        let size = |g: f64| if g.is_nan() { f64::INFINITY } else { g.abs() };
        let theta = if size(found.g_lo) < size(found.g_hi) {
            found.lo
        } else {
            found.hi
        };
        let (_, state) = eval(theta);
        out.push(Crossing {
            interval: k,
            t: t0 + theta * dt,
            state,
            rising,
            bracket: (t0 + found.lo * dt, t0 + found.hi * dt),
            converged: found.converged && !found.g_lo.is_nan() && !found.g_hi.is_nan(),
        });
    }
    Ok(out)
}
