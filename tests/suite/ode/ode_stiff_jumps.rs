//! A stiff problem with 100 state jumps and a closed form (issue 19 item 5), run through the
//! crate's event machinery: a time guard found by `find_first_event`, `truncate` to it, the
//! jump as a reset map, `reset` and on.
//!
//! $y_1' = -y_1$, $y_2' = 999 y_1 - 1000 y_2$ (eigenvalues $-1$ and $-1000$), $y(0) = (1, 1)$;
//! both components jump by $+1$ at $t_k = 0.05 k$, $k = 1, \dots, 100$. The state starts on the
//! slow eigenvector $(1, 1)$ and every jump moves it along that vector, so it never leaves it:
//! $y_1 = y_2 = c(t)$ with
//! $$c(t) = e^{-t} + \sum_{k:\thinspace t_k \le t} e^{-(t - t_k)}.$$
//! The fast mode is never excited, but an explicit method's step is still bounded by its
//! stability limit ($h \lesssim 6/1000$ for DOP853).
//!
//! `bench-compare/examples/stiff_jumps.rs` includes this file to put diffsol's solvers on the
//! same problem (hence the `pub` items).

use jeffcott::numeric::Direction;
use jeffcott::ode::{
    find_first_event, AnyIntegrator, EventOptions, EventSet, EventState, Integrator, Method,
    OdeError, Options,
};
use nalgebra::{SVector, U2};

type V2 = SVector<f64, 2>;

/// The methods the jump problem runs with, each with the scalar `(rtol, atol)` it needs for
/// [`MAX_ERROR`]. DOP853 works at its stability limit here, where
/// the error of the fast component is only loosely controlled (measured error at t = 5:
/// 1.4e-8 at rtol 1e-10 / atol 1e-12, 9.3e-11 at 1e-12 / 1e-12, 1.4e-9 at 1e-12 / 1e-14,
/// 2.9e-12 at 1e-13 / 1e-15).
const JUMP_METHODS: &[(Method, f64, f64)] = &[
    (Method::Radau5, 1e-12, 1e-14),
    (Method::Dop853, 1e-13, 1e-15),
];

/// Number of jumps.
pub const JUMPS: usize = 100;
/// Time between jumps.
pub const SPACING: f64 = 0.05;

/// The largest error allowed at the last jump, $t = 5$ (issue 19).
const MAX_ERROR: f64 = 1e-10;

/// The time of jump `k`.
pub fn jump_time(k: usize) -> f64 {
    SPACING * k as f64
}

/// The right-hand side.
fn stiff_pair(_t: f64, y: &V2, dy: &mut V2) {
    dy[0] = -y[0];
    dy[1] = 999.0 * y[0] - 1000.0 * y[1];
}

/// The guard of the next jump $k$: $g = t - t_k$, rising (a time guard: it does not depend on
/// the state).
struct NextJump {
    t_k: f64,
}

impl EventSet<U2> for NextJump {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Rising
    }
    fn value(&self, _i: usize, t: f64, _y: &V2) -> f64 {
        t - self.t_k
    }
}

/// The closed form $c(t)$ just after the jumps at $t_k \le t$ ($k \le$ `jumps_done`).
pub fn closed_form(t: f64, jumps_done: usize) -> f64 {
    (-t).exp()
        + (1..=jumps_done)
            .map(|k| (-(t - jump_time(k))).exp())
            .sum::<f64>()
}

/// What a run gives: the jumps found, the time and state just after the last one, the work.
pub struct JumpRun {
    /// Jumps found.
    pub jumps: usize,
    /// Time of the last jump.
    pub t: f64,
    /// State just after it.
    pub y: V2,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
}

/// Integrates from 0 through the last jump (stopping just after it).
pub fn run_jumps(method: Method, rtol: f64, atol: f64) -> Result<JumpRun, OdeError> {
    let sys = stiff_pair;
    let mut integ = AnyIntegrator::<U2>::new(method, Options::with_tol(rtol, atol))?;
    integ.reset(&sys, 0.0, &V2::new(1.0, 1.0), false)?;
    let (opts, mut state) = (EventOptions::default(), EventState::new());
    // Beyond the last jump, so that the last step can cross it.
    let t_stop = jump_time(JUMPS) + SPACING / 2.0;
    let mut jumps = 0;
    while jumps < JUMPS && integ.t() < t_stop {
        integ.step(&sys, t_stop)?;
        let guard = NextJump {
            t_k: jump_time(jumps + 1),
        };
        if let Some(hit) = find_first_event(&mut integ, &sys, &guard, &opts, &mut state)? {
            // The state to restart from is the integrator's after `truncate` (Radau5 steps
            // again to the event: its dense output, `hit.y`, is of lower order).
            let t_hit = hit.t;
            integ.truncate(&sys, t_hit)?;
            let y_hit = *integ.y();
            integ.reset(&sys, t_hit, &(y_hit + V2::new(1.0, 1.0)), true)?;
            state.reset();
            jumps += 1;
        }
    }
    let stats = integ.stats();
    Ok(JumpRun {
        jumps,
        t: integ.t(),
        y: *integ.y(),
        steps: stats.steps,
        rejected: stats.rejected,
    })
}

/// 100 of 100 jumps, each at its time, and both components within 1e-10 of the closed form
/// just after the last jump ($t = 5$). Prints the steps taken (issue 19 compares them with
/// diffsol's, see bench-compare).
#[test]
fn hundred_jumps_match_the_closed_form() {
    for &(method, rtol, atol) in JUMP_METHODS {
        let r = run_jumps(method, rtol, atol).unwrap_or_else(|e| panic!("{method:?}: {e}"));
        assert_eq!(r.jumps, JUMPS, "{method:?}: jumps found");
        assert!(
            (r.t - jump_time(JUMPS)).abs() <= 1e-12,
            "{method:?}: last jump at {} instead of {}",
            r.t,
            jump_time(JUMPS)
        );
        let c = closed_form(r.t, JUMPS);
        let err = (r.y[0] - c).abs().max((r.y[1] - c).abs());
        println!(
            "{method:?}: 100 jumps, error at t = 5: {err:.2e} (c = {c}), {} steps, {} rejected \
             (rtol {rtol:e}, atol {atol:e})",
            r.steps, r.rejected
        );
        assert!(
            err <= MAX_ERROR,
            "{method:?}: y(5) = {:?}, closed form {c}, error {err:e}",
            r.y.as_slice()
        );
        if method == Method::Radau5 {
            // Issue 19: fewer steps than diffsol's ESDIRK34 (559 in its book and measured by
            // bench-compare's stiff_jumps, for an error of 1.2e-6). Each jump's re-step counts.
            assert!(r.steps < 559, "Radau5: {} steps", r.steps);
        }
    }
}
