//! The observer of the long single computations (`analysis::Progress`): told of each unit of
//! work, and obeyed when it asks to stop. The truths: a run that is never asked to stop is the
//! plain function's bit for bit; a stopped run returns exactly what a shorter complete run
//! computes (the Lyapunov exponents of the periods recorded so far, the branch's first
//! points).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use jeffcott::analysis::Progress;
use jeffcott::paper::{JeffcottModel, State};
use jeffcott::params::{ParamError, Preset};
use jeffcott::stability::{
    continue_orbit, continue_orbit_with_progress, lyapunov_exponents,
    lyapunov_exponents_with_progress, BranchEnd, ContinuationOptions, LyapunovOptions, SpecialKind,
    StabilityError,
};

/// Records every update; asks to stop after `stop_after` updates (never if `None`), or
/// (`stop_in_bisection`) at the second question with no update since the last (the first
/// question a special point's bisection asks).
#[derive(Default)]
struct Recorder {
    updates: Mutex<Vec<(usize, usize)>>,
    stop_after: Option<usize>,
    stop_in_bisection: bool,
    questions_since_update: AtomicUsize,
}

impl Progress for Recorder {
    fn update(&self, done: usize, total: usize) {
        self.updates.lock().unwrap().push((done, total));
        self.questions_since_update.store(0, Ordering::SeqCst);
    }

    fn should_stop(&self) -> bool {
        let asked = self.questions_since_update.fetch_add(1, Ordering::SeqCst) + 1;
        let updates = self.updates.lock().unwrap().len();
        self.stop_after.is_some_and(|n| updates >= n) || (self.stop_in_bisection && asked >= 2)
    }
}

fn lyapunov_case() -> (JeffcottModel, State, LyapunovOptions) {
    let model = JeffcottModel::new(Preset::Fig9c.params()).unwrap();
    let y0 = model.state_at([0.5, 0.0], [0.0, 0.0]).unwrap();
    let opts = LyapunovOptions::default()
        .with_transient(20)
        .with_align(10)
        .with_periods(60)
        .with_batch(10);
    (model, y0, opts)
}

#[test]
fn lyapunov_exponents_never_stopped_are_the_plain_functions_and_count_every_period() {
    let (model, y0, opts) = lyapunov_case();
    let observer = Recorder::default();
    let observed = lyapunov_exponents_with_progress(&model, &y0, &opts, &observer).unwrap();
    assert_eq!(observed, lyapunov_exponents(&model, &y0, &opts).unwrap());
    let expected: Vec<_> = (1..=70).map(|k| (k, 70)).collect();
    assert_eq!(*observer.updates.lock().unwrap(), expected);
}

#[test]
fn stopped_lyapunov_exponents_are_those_of_the_periods_recorded_so_far() {
    let (model, y0, opts) = lyapunov_case();
    // Stopped after 10 periods of alignment and 30 recorded: a run of 30 periods.
    let observer = Recorder {
        stop_after: Some(40),
        ..Recorder::default()
    };
    let err = lyapunov_exponents_with_progress(&model, &y0, &opts, &observer).unwrap_err();
    let StabilityError::Stopped {
        done,
        total,
        partial,
    } = err
    else {
        panic!("not Stopped: {err:?}");
    };
    assert_eq!((done, total), (40, 70));
    let shorter = lyapunov_exponents(&model, &y0, &opts.with_periods(30)).unwrap();
    let partial = partial.expect("30 recorded periods");
    assert_eq!(partial.per_period.samples, 30);
    assert_eq!(*partial, shorter);
    // Asked to stop before anything: nothing recorded.
    let at_once = Recorder {
        stop_after: Some(0),
        ..Recorder::default()
    };
    let err = lyapunov_exponents_with_progress(&model, &y0, &opts, &at_once).unwrap_err();
    assert!(
        matches!(
            err,
            StabilityError::Stopped {
                done: 0,
                total: 70,
                partial: None
            }
        ),
        "{err:?}"
    );
}

/// The period-1 orbit of Fig. 8a at eta = 2 (reference point, tests/suite/global) and its family.
fn fig8a_start() -> (impl Fn(f64) -> Result<JeffcottModel, ParamError>, State) {
    let base = Preset::Fig8a.params();
    let build = move |eta: f64| JeffcottModel::new(base.with_eta(eta));
    let x = [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533];
    let guess = build(2.0)
        .unwrap()
        .state_at([x[0], x[1]], [x[2], x[3]])
        .unwrap();
    (build, guess)
}

#[test]
fn a_stopped_branch_holds_the_points_computed_before_the_stop() {
    let (build, guess) = fig8a_start();
    let observer = Recorder {
        stop_after: Some(3),
        ..Recorder::default()
    };
    let opts = ContinuationOptions::default();
    let branch =
        continue_orbit_with_progress(&build, 2.0, 2.3, &guess, 1, &opts, &observer).unwrap();
    let shorter = continue_orbit(&build, 2.0, 2.3, &guess, 1, &opts.with_max_points(3)).unwrap();
    assert_eq!(shorter.end, BranchEnd::MaxPoints);
    assert_eq!(branch.points, shorter.points);
    let last = branch.points[2].parameter;
    assert_eq!(branch.end, BranchEnd::Stopped { parameter: last });
    assert_eq!(
        *observer.updates.lock().unwrap(),
        thousandths(&branch.points, 2.0, 2.3, 5000)
    );
}

/// The progress a branch from `from` to `to` reports at each of its points, as documented: the
/// thousandths of the larger of the points' share of `max_points` and the share of the way to
/// `to` reached so far.
fn thousandths(
    points: &[jeffcott::stability::BranchPoint],
    from: f64,
    to: f64,
    max_points: usize,
) -> Vec<(usize, usize)> {
    let mut reach = 0.0f64;
    (1..=points.len())
        .map(|k| {
            reach = reach.max((points[k - 1].parameter - from) / (to - from));
            let share = (k as f64 / max_points as f64).max(reach).min(1.0);
            ((1000.0 * share).floor() as usize, 1000)
        })
        .collect()
}

/// A branch that reaches its end in far fewer points than `max_points` says so: its progress
/// follows the parameter's way to the end, 1000 of 1000 at the last point (counted in points
/// it showed a few per cent there).
#[test]
fn a_branch_reports_its_way_to_the_end_not_its_share_of_max_points() {
    let (build, guess) = fig8a_start();
    let observer = Recorder::default();
    let opts = ContinuationOptions::default();
    let branch =
        continue_orbit_with_progress(&build, 2.0, 2.3, &guess, 1, &opts, &observer).unwrap();
    assert_eq!(branch.end, BranchEnd::Reached);
    assert!(
        branch.points.len() < opts.max_points / 10,
        "{}",
        branch.points.len()
    );
    let updates = observer.updates.lock().unwrap();
    assert_eq!(
        *updates,
        thousandths(&branch.points, 2.0, 2.3, opts.max_points)
    );
    assert_eq!(updates.last(), Some(&(1000, 1000)));
}

#[test]
fn a_stop_inside_a_bisection_leaves_the_flip_unconverged_in_its_first_bracket() {
    let (build, guess) = fig8a_start();
    let observer = Recorder {
        stop_in_bisection: true,
        ..Recorder::default()
    };
    let opts = ContinuationOptions::default();
    let branch =
        continue_orbit_with_progress(&build, 2.0, 2.3, &guess, 1, &opts, &observer).unwrap();
    assert_eq!(branch.specials.len(), 1, "{:?}", branch.specials);
    let flip = &branch.specials[0];
    assert_eq!(flip.kind, SpecialKind::Flip);
    assert!(!flip.converged);
    assert!(
        matches!(flip.unconverged, Some(StabilityError::Stopped { .. })),
        "{:?}",
        flip.unconverged
    );
    // The bracket never narrowed: it is the two points either side, the last of the branch.
    let i = flip.after_point;
    assert_eq!(branch.points.len(), i + 2);
    let (near, far) = (branch.points[i].parameter, branch.points[i + 1].parameter);
    assert_eq!(flip.bracket, (near, far));
    assert!(near < 2.234843277 && 2.234843277 < far, "{near} {far}");
    assert_eq!(branch.end, BranchEnd::Stopped { parameter: far });
}
