//! Continuation of periodic orbits against known answers: the analytic grazing of the orbit
//! without contact (|e| + A(eta) = 1), the flips of the period-1 orbits of Fig. 8 and the fold
//! of the period-3 orbit (reference values, docs/global.md), branch switching at a flip, and a
//! fold passed by pseudo-arclength.

use jeffcott::params::{Params, Preset};
use jeffcott::stability::{
    continue_orbit, switch_at_flip, BranchEnd, ContinuationOptions, SpecialKind, StabilityError,
};
use jeffcott::JeffcottModel;

/// Radius of the steady orbit without contact, and its phase lag.
fn amplitude(p: &Params, eta: f64) -> (f64, f64) {
    let (re, im) = (1.0 - eta * eta, 2.0 * p.nu1 * eta);
    (p.beta * eta * eta / re.hypot(im), im.atan2(re))
}

/// The eta in (lo, hi) where |e| + A(eta) = 1, by bisection to rounding.
fn grazing_eta(p: &Params, mut lo: f64, mut hi: f64) -> f64 {
    let e = p.ex.hypot(p.ey);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if e + amplitude(p, mid).0 < 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn the_orbit_without_contact_grazes_where_e_plus_a_is_1_then_keeps_one_contact() {
    let base = Preset::Fig8a.params();
    let build = |eta: f64| JeffcottModel::new(base.with_eta(eta));
    let from = 0.4;
    let (a, psi) = amplitude(&base, from);
    // The exact steady orbit at tau = 0 (phi0 = 0): a circle of radius A about (ex, ey).
    let model = build(from).unwrap();
    let guess = model
        .state_at(
            [base.ex + a * psi.cos(), base.ey - a * psi.sin()],
            [a * from * psi.sin(), a * from * psi.cos()],
        )
        .unwrap();
    let config = ContinuationOptions::default();
    let branch = continue_orbit(build, from, 0.8, &guess, 1, &config).unwrap();
    assert_eq!(branch.end, BranchEnd::Reached, "{:?}", branch.end);
    let first = &branch.points[0];
    assert!((first.point[0] - (base.ex + a * psi.cos())).abs() < 1e-9);
    let eta_g = grazing_eta(&base, from, 0.8);
    let g: Vec<_> = branch
        .specials
        .iter()
        .filter(|s| s.kind == SpecialKind::Grazing)
        .collect();
    assert_eq!(
        g.len(),
        1,
        "{:?}",
        branch
            .specials
            .iter()
            .map(|s| (s.kind, s.parameter))
            .collect::<Vec<_>>()
    );
    println!(
        "grazing: continuation {:.12}, analytic {eta_g:.12}, difference {:.2e}, bracket {:?}",
        g[0].parameter,
        g[0].parameter - eta_g,
        g[0].bracket
    );
    assert!(
        (g[0].parameter - eta_g).abs() < 1e-7,
        "{} vs {eta_g}",
        g[0].parameter
    );
    assert_eq!(g[0].contacts, (0, 1));
    assert!(g[0].converged && g[0].unconverged.is_none());
    assert!((g[0].bracket.1 - g[0].bracket.0).abs() <= config.bracket_width);
    // Stable throughout, no contact before the grazing, one contact per period after it.
    for p in &branch.points {
        assert!(p.stable, "{}", p.parameter);
        // 1e-4 past the grazing the contact is entered at a margin of about 0.02
        // (margin ~ sqrt(eta - eta_g)): only points closer than that can be flagged.
        assert_eq!(
            p.grazing,
            p.min_margin < jeffcott::stability::GRAZING_MARGIN
        );
        assert!(
            !p.grazing || (p.parameter - eta_g).abs() < 1e-4,
            "{}",
            p.parameter
        );
        let expected = if p.parameter < eta_g { 0 } else { 1 };
        assert_eq!(p.contacts, expected, "at eta = {}", p.parameter);
    }
    let after = branch.points.iter().filter(|p| p.parameter > eta_g).count();
    assert!(after >= 5, "{after} points after the grazing");
}

#[test]
fn period_1_flips_at_the_reference_values_and_the_period_2_branch_is_found() {
    for (preset, x, flip_ref) in [
        (
            Preset::Fig8a,
            [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533],
            2.234843277,
        ),
        (
            Preset::Fig8b,
            [0.5100525457, -0.0204044359, 0.1180488481, -0.3107081594],
            2.272961816,
        ),
    ] {
        let base = preset.params();
        let build = |eta: f64| JeffcottModel::new(base.with_eta(eta));
        let guess = build(2.0)
            .unwrap()
            .state_at([x[0], x[1]], [x[2], x[3]])
            .unwrap();
        let config = ContinuationOptions::default();
        let branch = continue_orbit(build, 2.0, 2.3, &guess, 1, &config).unwrap();
        let flips: Vec<_> = branch
            .specials
            .iter()
            .filter(|s| s.kind == SpecialKind::Flip)
            .collect();
        assert_eq!(flips.len(), 1, "{preset}");
        let f = flips[0];
        println!(
            "{preset}: flip at {:.10} (reference {flip_ref}), multipliers {:?}",
            f.parameter, f.multipliers
        );
        // Reference bracket +-1e-8; ours 1e-8 plus the parameter difference's error.
        assert!(
            (f.parameter - flip_ref).abs() < 3e-8,
            "{preset}: {}",
            f.parameter
        );
        let m = f.multipliers[0];
        assert!((m.re + 1.0).abs() < 1e-5 && m.im.abs() < 1e-9, "{m:?}");
        // Stable before, unstable after.
        assert!(branch
            .points
            .iter()
            .all(|p| p.stable == (p.parameter < f.parameter)));
        // The period-2 branch from the flip: supercritical, on the far side, stable there.
        let doubled =
            switch_at_flip(build, f, 2.27 + (flip_ref - 2.234843277), 1, &config).unwrap();
        assert_eq!(doubled.period, 2);
        let p2 = &doubled.points[doubled.points.len() / 2];
        assert!(p2.parameter > f.parameter, "{preset}: {}", p2.parameter);
        assert!(p2.stable, "{preset}: {:?}", p2.multipliers);
        let dx = (p2.cycle[0][0] - p2.cycle[1][0]).abs();
        assert!(
            dx > 1e-3,
            "{preset}: the two points of period 2 differ by {dx}"
        );
        // A flip detected but not located (its bracket did not converge) is no place to
        // switch: its point and eigenvector belong to the bracket's near end, not the flip.
        let mut unlocated = f.clone();
        unlocated.converged = false;
        let refused = switch_at_flip(build, &unlocated, 2.3, 1, &config);
        assert!(
            matches!(refused, Err(StabilityError::NoSwitch { .. })),
            "{preset}: switched at an unconverged flip: {:?}",
            refused.map(|b| b.points.len())
        );
    }
}

#[test]
fn the_period_3_orbit_is_followed_through_its_fold() {
    // The period-3 orbit of Fig. 8a at eta = 2.17 (reference point), continued downwards: it
    // turns back in a fold at 2.1259324 and comes back up unstable.
    let base = Preset::Fig8a.params();
    let build = |eta: f64| JeffcottModel::new(base.with_eta(eta));
    let z = [0.4083372776, -0.0332339640, 0.0200130670, -0.3057623329];
    let guess = build(2.17)
        .unwrap()
        .state_at([z[0], z[1]], [z[2], z[3]])
        .unwrap();
    let config = ContinuationOptions::default();
    let branch = continue_orbit(build, 2.17, 2.10, &guess, 3, &config).unwrap();
    let folds: Vec<_> = branch
        .specials
        .iter()
        .filter(|s| s.kind == SpecialKind::Fold)
        .collect();
    assert!(
        !folds.is_empty(),
        "{:?}",
        branch
            .specials
            .iter()
            .map(|s| (s.kind, s.parameter))
            .collect::<Vec<_>>()
    );
    println!("fold at {:.10} (reference 2.1259324)", folds[0].parameter);
    assert!(
        (folds[0].parameter - 2.1259324).abs() < 2e-7,
        "{}",
        folds[0].parameter
    );
    // Past the fold the parameter grows again and the orbit is unstable.
    let i = folds[0].after_point + 1;
    let later = &branch.points[(i + 2).min(branch.points.len() - 1)];
    assert!(
        later.parameter > folds[0].parameter && !later.stable,
        "{} {:?}",
        later.parameter,
        later.multipliers
    );
}

use crate::support;

#[test]
fn the_example_prints_one_json_object_per_special_point() {
    let exe = support::example_exe("continuation");
    let dir = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .join("global_continuation_example");
    let run = support::run_ok(
        std::process::Command::new(&exe)
            .args([
                "--param", "eta", "--from", "0.4", "--to", "0.8", "--period", "1", "--out",
            ])
            .arg(&dir),
    );
    let text = String::from_utf8(run.stdout).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 1, "{text}");
    let g = &lines[0];
    assert_eq!(g["kind"], "grazing");
    assert_eq!(g["param"], "eta");
    assert_eq!(g["converged"], true, "{g}");
    let eta_g = grazing_eta(&Preset::Fig8a.params(), 0.4, 0.8);
    assert!((g["value"].as_f64().unwrap() - eta_g).abs() < 1e-7, "{g}");
    let m = g["multipliers"].as_array().unwrap();
    assert_eq!(m.len(), 4);
    assert!(m.iter().all(|p| p.as_array().unwrap().len() == 2));
    assert!(dir.join("branch.png").exists() && dir.join("branch.csv").exists());

    // From eta = 2 with --switch: the flip of period 1, then the period-2 branch and its own
    // flip at 2.3827.
    let run = support::run_ok(
        std::process::Command::new(&exe)
            .args([
                "--param", "eta", "--from", "2", "--to", "2.45", "--period", "1", "--switch",
                "--out",
            ])
            .arg(&dir),
    );
    let lines: Vec<serde_json::Value> = String::from_utf8(run.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let flip1 = lines
        .iter()
        .find(|l| l["kind"] == "flip" && l["period"] == 1)
        .unwrap();
    assert!((flip1["value"].as_f64().unwrap() - 2.234843277).abs() < 3e-8);
    assert!(lines
        .iter()
        .any(|l| l["kind"] == "flip" && l["period"] == 2));

    let bad = std::process::Command::new(&exe)
        .args(["--param", "eta", "--from", "2"])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
}

/// A located point is one whose bracket converged. Here the model cannot be built within
/// 1e-6 of the grazing of the orbit without contact (closed form), so the bisection cannot
/// narrow its bracket below a few 1e-6: the grazing is found but not located, and must say
/// so instead of passing a 1e-6 bracket for a 1e-8 one.
#[test]
fn an_unconverged_bracket_is_not_a_located_point() {
    let base = Preset::Fig8a.params();
    let eta_g = grazing_eta(&base, 0.4, 0.8);
    let build = |eta: f64| {
        if (eta - eta_g).abs() < 1e-6 {
            Err(format!("no model near the grazing (asked {eta})"))
        } else {
            JeffcottModel::new(base.with_eta(eta)).map_err(|e| e.to_string())
        }
    };
    let from = 0.4;
    let (a, psi) = amplitude(&base, from);
    let guess = JeffcottModel::new(base.with_eta(from))
        .unwrap()
        .state_at(
            [base.ex + a * psi.cos(), base.ey - a * psi.sin()],
            [a * from * psi.sin(), a * from * psi.cos()],
        )
        .unwrap();
    let config = ContinuationOptions::default();
    let branch = continue_orbit(build, from, 0.8, &guess, 1, &config).unwrap();
    let g: Vec<_> = branch
        .specials
        .iter()
        .filter(|s| s.kind == SpecialKind::Grazing)
        .collect();
    assert_eq!(g.len(), 1);
    let width = g[0].bracket.1 - g[0].bracket.0;
    println!("bracket {:?}, width {width:e}", g[0].bracket);
    // The bracket holds the grazing, and is wider than the 1e-6 hole.
    assert!(
        g[0].bracket.0.min(g[0].bracket.1) < eta_g && eta_g < g[0].bracket.0.max(g[0].bracket.1)
    );
    assert!(
        width.abs() > config.bracket_width,
        "the hole should stop the bisection"
    );
    assert!(
        !g[0].converged,
        "an unconverged bracket {:?} (width {width:e}) reported as located",
        g[0].bracket
    );
    let why = g[0]
        .unconverged
        .as_ref()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(why.contains("no model near the grazing"), "{why}");
}

/// The arclength norm scales the parameter: the flip of Fig. 8a's period-1 orbit continued in
/// a parameter 1000 times larger (q = 1000 eta, as a frequency in other units) is found at
/// 1000 times the reference, with about as many points. Unscaled, the steps of at most 0.02
/// in q (2e-5 in eta) would need some 15 000 points to cross the range.
#[test]
fn the_arclength_does_not_depend_on_the_parameter_units() {
    let base = Preset::Fig8a.params();
    let x = [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533];
    let build = |eta: f64| JeffcottModel::new(base.with_eta(eta));
    let guess = build(2.0)
        .unwrap()
        .state_at([x[0], x[1]], [x[2], x[3]])
        .unwrap();
    let config = ContinuationOptions::default();
    let branch = continue_orbit(build, 2.0, 2.3, &guess, 1, &config).unwrap();
    let in_q = |q: f64| JeffcottModel::new(base.with_eta(q / 1000.0));
    let scaled = config.with_bracket_width(1e-5);
    let branch_q = continue_orbit(in_q, 2000.0, 2300.0, &guess, 1, &scaled).unwrap();
    assert_eq!(branch_q.end, BranchEnd::Reached, "{:?}", branch_q.end);
    let flip = |b: &jeffcott::stability::Branch| {
        b.specials
            .iter()
            .find(|s| s.kind == SpecialKind::Flip)
            .map(|s| s.parameter)
    };
    let (f, fq) = (flip(&branch).unwrap(), flip(&branch_q).unwrap() / 1000.0);
    println!(
        "flip {f:.10}, in q {fq:.10}; points {} and {}",
        branch.points.len(),
        branch_q.points.len()
    );
    assert!((fq - 2.234843277).abs() < 3e-8, "{fq}");
    let (n, nq) = (branch.points.len() as f64, branch_q.points.len() as f64);
    assert!((nq - n).abs() <= 0.1 * n, "{n} vs {nq} points");
}

/// The paper's model under other guard labels (a user's model names its guards as it likes):
/// the contacts per orbit come from the model's own `is_contact_onset`, not from a label.
mod relabelled {
    use jeffcott::hybrid::{Flow, ModelError, RotorModel, Variational, Workspace};
    use jeffcott::nalgebra::{Dyn, OMatrix, OVector, U6};
    use jeffcott::numeric::Direction;
    use jeffcott::paper::{Cache, FreeSegment, JeffcottModel, Mode, State};

    type M6 = OMatrix<f64, U6, U6>;

    pub struct Relabelled(pub JeffcottModel);

    impl RotorModel for Relabelled {
        type Dim = U6;
        type Mode = Mode;
        type Segment = FreeSegment;
        type Cache = Cache;
        fn dim(&self) -> U6 {
            U6
        }
        fn new_cache(&self) -> Cache {
            self.0.new_cache()
        }
        fn initial_mode(&self, t: f64, y: &State) -> Result<Mode, ModelError> {
            self.0.initial_mode(t, y)
        }
        fn flow(&self, mode: Mode) -> Flow {
            self.0.flow(mode)
        }
        fn rhs(&self, mode: Mode, t: f64, y: &State, dy: &mut State, cache: &Cache) {
            self.0.rhs(mode, t, y, dy, cache)
        }
        fn is_algebraic(&self, i: usize) -> bool {
            self.0.is_algebraic(i)
        }
        fn guard_count(&self, mode: Mode) -> usize {
            self.0.guard_count(mode)
        }
        fn guard_direction(&self, mode: Mode, i: usize) -> Direction {
            self.0.guard_direction(mode, i)
        }
        fn is_contact_onset(&self, mode: Mode, i: usize) -> bool {
            self.0.is_contact_onset(mode, i)
        }
        fn guard_value(&self, mode: Mode, i: usize, t: f64, y: &State, cache: &Cache) -> f64 {
            self.0.guard_value(mode, i, t, y, cache)
        }
        fn guard_label(&self, mode: Mode, i: usize) -> &'static str {
            match self.0.guard_label(mode, i) {
                "contact onset" => "rotor meets the snubber",
                other => other,
            }
        }
        fn transition(
            &self,
            mode: Mode,
            g: usize,
            t: f64,
            y: &mut State,
        ) -> Result<Mode, ModelError> {
            self.0.transition(mode, g, t, y)
        }
        fn start_segment(&self, mode: Mode, t: f64, y: &State) -> FreeSegment {
            self.0.start_segment(mode, t, y)
        }
        fn project(&self, mode: Mode, t: f64, y: &mut State, cache: &Cache) {
            self.0.project(mode, t, y, cache)
        }
        fn mode_label(&self, mode: Mode) -> u8 {
            self.0.mode_label(mode)
        }
        fn forcing_period(&self) -> f64 {
            self.0.forcing_period()
        }
    }

    impl Variational for Relabelled {
        fn is_algebraic_variation(&self, i: usize) -> bool {
            self.0.is_algebraic_variation(i)
        }
        #[allow(clippy::too_many_arguments)]
        fn rhs_jacobian(
            &self,
            m: Mode,
            t: f64,
            y: &State,
            jac: &mut M6,
            c: &Cache,
            w: &mut Workspace<U6>,
        ) {
            self.0.rhs_jacobian(m, t, y, jac, c, w)
        }
        #[allow(clippy::too_many_arguments)]
        fn guard_gradient(
            &self,
            m: Mode,
            i: usize,
            t: f64,
            y: &State,
            g: &mut State,
            c: &Cache,
            w: &mut Workspace<U6>,
        ) -> f64 {
            self.0.guard_gradient(m, i, t, y, g, c, w)
        }
        #[allow(clippy::too_many_arguments)]
        fn transition_jacobian(
            &self,
            m: Mode,
            g: usize,
            t: f64,
            y: &State,
            after: &State,
            next: Mode,
            rx: &mut M6,
            rt: &mut State,
        ) -> Result<(), ModelError> {
            self.0.transition_jacobian(m, g, t, y, after, next, rx, rt)
        }
        fn segment_jacobian(&self, m: Mode, t0: f64, y0: &State, t: f64, jac: &mut M6) {
            self.0.segment_jacobian(m, t0, y0, t, jac)
        }
        fn algebraic_variation(
            &self,
            m: Mode,
            t: f64,
            y: &State,
            start: &OMatrix<f64, U6, Dyn>,
            v: &mut OMatrix<f64, U6, Dyn>,
            c: &Cache,
        ) {
            self.0.algebraic_variation(m, t, y, start, v, c)
        }
        fn section_state(&self, t: f64, template: &State, z: &[f64]) -> State {
            self.0.section_state(t, template, z)
        }
        fn section_openness(&self, m: Mode, t: f64, y: &OVector<f64, U6>) -> f64 {
            self.0.section_openness(m, t, y)
        }
        fn contact_depth(&self, m: Mode, t: f64, y: &State) -> Option<f64> {
            self.0.contact_depth(m, t, y)
        }
    }
}

#[test]
fn contacts_are_counted_by_the_models_onset_guards_whatever_their_labels() {
    let base = Preset::Fig8a.params();
    let build = |eta: f64| JeffcottModel::new(base.with_eta(eta)).map(relabelled::Relabelled);
    let from = 0.67;
    let (a, psi) = amplitude(&base, from);
    let guess = JeffcottModel::new(base.with_eta(from))
        .unwrap()
        .state_at(
            [base.ex + a * psi.cos(), base.ey - a * psi.sin()],
            [a * from * psi.sin(), a * from * psi.cos()],
        )
        .unwrap();
    let config = ContinuationOptions::default();
    let branch = continue_orbit(build, from, 0.70, &guess, 1, &config).unwrap();
    let eta_g = grazing_eta(&base, 0.4, 0.8);
    let g = branch
        .specials
        .iter()
        .find(|s| s.kind == SpecialKind::Grazing)
        .expect("the grazing");
    assert!((g.parameter - eta_g).abs() < 1e-7, "{}", g.parameter);
    assert_eq!(g.contacts, (0, 1));
    let last = branch.points.last().unwrap();
    assert!(
        last.structure.contains(&"rotor meets the snubber"),
        "{:?}",
        last.structure
    );
    assert_eq!(last.contacts, 1);
}
