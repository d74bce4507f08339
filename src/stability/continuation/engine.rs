//! The continuation core: the one stepping loop ([`march`]) with its step control, run by both
//! modes (pseudo-arclength, [`super::arclength`]; natural-parameter, [`super::loss`]), and the
//! one locator of special points ([`narrow`]).
//!
//! A mode is a corrector and what it makes of the points ([`Mode`]): the bordered arclength
//! corrector in $(z, p)$, or the fixed-parameter solve by
//! [`periodic_orbit`](crate::stability::periodic_orbit) that the arclength corrector
//! degenerates to when its constraint row is $e_p$.

use crate::numeric::{bisect, Bisection, Side};

/// The one step-size control: a failed correction halves the step while the half is at least
/// [`min`](Self::min) (else the mode's [`Mode::stall`] decides), a success sets the next step
/// by [`growth`](Self::growth).
#[derive(Debug, Clone, Copy)]
pub(super) struct StepControl {
    /// The first step.
    pub first: f64,
    /// The smallest step tried.
    pub min: f64,
    /// The largest step.
    pub max: f64,
    /// The step after a success.
    pub growth: Growth,
}

/// The step after a success.
#[derive(Debug, Clone, Copy)]
pub(super) enum Growth {
    /// Back to the first step.
    Reset,
    /// Times this factor, up to the largest step, after an easy correction ([`Mode::easy`]);
    /// kept otherwise.
    Grow(f64),
}

impl StepControl {
    /// Half of the failed step `ds`, or `None` below the smallest step.
    fn halved(&self, ds: f64) -> Option<f64> {
        let half = ds * 0.5;
        (half >= self.min).then_some(half)
    }

    /// The step after the successful step `ds`.
    fn after(&self, ds: f64, easy: bool) -> f64 {
        match self.growth {
            Growth::Reset => self.first,
            Growth::Grow(factor) if easy => (ds * factor).min(self.max),
            Growth::Grow(_) => ds,
        }
    }
}

/// Whether a continuation goes on from a point or ends.
pub(super) enum Flow<P, E> {
    /// It goes on from this point.
    Go(P),
    /// It ends so.
    Stop(E),
}

/// A mode of the continuation: its corrector, and what it makes of the points (their record,
/// the special points between two of them, its budget and range).
pub(super) trait Mode {
    /// A corrected point.
    type Point;
    /// Why a step failed.
    type Failure;
    /// How the continuation ends.
    type End;
    /// Whether it ends before a step from `cur` (its budget spent, its range reached).
    fn stop(&mut self, cur: &Self::Point) -> Option<Self::End>;
    /// One predictor-corrector step of size `ds > 0` from `cur`.
    fn step(&mut self, cur: &Self::Point, ds: f64) -> Result<Self::Point, Self::Failure>;
    /// Whether `next` was corrected easily (for [`Growth::Grow`]).
    fn easy(&self, next: &Self::Point) -> bool;
    /// Takes the step from `cur` to `next`: records `next`, detects and locates the special
    /// points between them.
    fn accept(&mut self, cur: Self::Point, next: Self::Point) -> Flow<Self::Point, Self::End>;
    /// The step from `cur` failed (`failure`) at the smallest step.
    fn stall(&mut self, cur: Self::Point, failure: Self::Failure) -> Flow<Self::Point, Self::End>;
}

/// The one stepping loop: from `first`, steps of `mode` under `control` until the mode ends.
pub(super) fn march<M: Mode>(mode: &mut M, first: M::Point, control: &StepControl) -> M::End {
    let (mut cur, mut ds) = (first, control.first);
    loop {
        if let Some(end) = mode.stop(&cur) {
            return end;
        }
        let (flow, easy) = match mode.step(&cur, ds) {
            Ok(next) => {
                let easy = mode.easy(&next);
                (mode.accept(cur, next), easy)
            }
            Err(failure) => match control.halved(ds) {
                Some(half) => {
                    ds = half;
                    continue;
                }
                None => {
                    // A stall the mode passed (a leap, a located grazing) starts afresh.
                    ds = control.first;
                    (mode.stall(cur, failure), false)
                }
            },
        };
        match flow {
            Flow::Go(next) => {
                cur = next;
                ds = control.after(ds, easy);
            }
            Flow::Stop(end) => return end,
        }
    }
}

/// What the locator's probe found at a midpoint.
pub(super) enum Probe<N, F> {
    /// A point like the near end: it replaces it.
    Near(N),
    /// A point like the far end (or no point, for a mode whose far end may be a failure): it
    /// replaces it.
    Far(F),
}

/// The one locator of special points: bisects (by [`bisect`], on `interval` with its `tol`
/// and at most `max` probes) between a `near` and a `far` end, `probe(x, &near, &far)`
/// correcting a point at the midpoint `x` and saying which end it replaces, or stopping the
/// search with its error. Returns the final ends and the bisection's outcome.
pub(super) fn narrow<N, F, E>(
    (near, far): (N, F),
    interval: (f64, f64),
    (tol, max): (f64, usize),
    mut probe: impl FnMut(f64, &N, &F) -> Result<Probe<N, F>, E>,
) -> (N, F, Result<Bisection, E>) {
    let (mut near, mut far) = (near, far);
    let out = bisect(interval.0, interval.1, tol, max, |x| {
        Ok(match probe(x, &near, &far)? {
            Probe::Near(n) => {
                near = n;
                Side::Near
            }
            Probe::Far(f) => {
                far = f;
                Side::Far
            }
        })
    });
    (near, far, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A toy mode on the real line: a step from `x` by `ds` fails beyond `limit`; it records
    /// every step tried and stops at `stop_at` or at a stall (returning where it stood).
    struct Line {
        limit: f64,
        stop_at: f64,
        tried: Vec<f64>,
    }

    impl Mode for Line {
        type Point = f64;
        type Failure = ();
        type End = f64;
        fn stop(&mut self, cur: &f64) -> Option<f64> {
            (*cur >= self.stop_at).then_some(*cur)
        }
        fn step(&mut self, cur: &f64, ds: f64) -> Result<f64, ()> {
            self.tried.push(ds);
            (cur + ds <= self.limit).then_some(cur + ds).ok_or(())
        }
        fn easy(&self, _: &f64) -> bool {
            true
        }
        fn accept(&mut self, _: f64, next: f64) -> Flow<f64, f64> {
            Flow::Go(next)
        }
        fn stall(&mut self, cur: f64, _: ()) -> Flow<f64, f64> {
            Flow::Stop(cur)
        }
    }

    fn control(min: f64, growth: Growth) -> StepControl {
        StepControl {
            first: 0.25,
            min,
            max: 0.5,
            growth,
        }
    }

    #[test]
    fn a_failed_step_is_halved_down_to_the_smallest_then_the_mode_stalls() {
        let mut line = Line {
            limit: 1.0,
            stop_at: 10.0,
            tried: Vec::new(),
        };
        // Four steps of 0.25 reach 1 exactly; from there every step fails, halved while the
        // half is at least 1/32.
        let end = march(&mut line, 0.0, &control(1.0 / 32.0, Growth::Reset));
        assert_eq!(end, 1.0);
        let tried = [0.25, 0.25, 0.25, 0.25, 0.25, 0.125, 0.0625, 0.03125];
        assert_eq!(line.tried, tried);
    }

    #[test]
    fn a_success_resets_or_grows_the_step() {
        let mut line = Line {
            limit: 10.0,
            stop_at: 1.0,
            tried: Vec::new(),
        };
        // Growth by 2 up to the largest step, 0.5: 0.25, then 0.5 twice reach 1.25.
        let end = march(&mut line, 0.0, &control(0.01, Growth::Grow(2.0)));
        assert_eq!(
            (end, line.tried.as_slice()),
            (1.25, [0.25, 0.5, 0.5].as_slice())
        );
        // A failed step (limit 0.3) halved to 1/32, then back to 0.25 after the success; the
        // second time down to 1/64, the third time it stalls.
        let mut line = Line {
            limit: 0.3,
            stop_at: 10.0,
            tried: Vec::new(),
        };
        let end = march(&mut line, 0.0, &control(0.01, Growth::Reset));
        assert_eq!(end, 0.25 + 0.03125 + 0.015625);
        assert_eq!(line.tried[..6], [0.25, 0.25, 0.125, 0.0625, 0.03125, 0.25]);
    }

    #[test]
    fn the_natural_floor_halves_exactly_the_steps_wider_than_the_width() {
        // locate_loss halves a failed step while it is wider than the bracket width `w`: the
        // smallest half is the next float above w / 2.
        for w in [1e-8_f64, 0.3, 1.0, 5e-300] {
            let c = control((0.5 * w).next_up(), Growth::Reset);
            assert_eq!(c.halved(w), None);
            assert_eq!(c.halved(w.next_up()), Some(0.5 * w.next_up()));
            assert_eq!(c.halved(4.0 * w), Some(2.0 * w));
        }
    }

    #[test]
    fn the_locator_keeps_the_ends_and_stops_on_the_probes_error() {
        // The test "x < 0.3" bisected on [0, 1]: the final ends hold the change.
        let probe = |x: f64, _: &f64, _: &f64| {
            Ok::<_, ()>(if x < 0.3 {
                Probe::Near(x)
            } else {
                Probe::Far(x)
            })
        };
        let (near, far, out) = narrow((0.0, 1.0), (0.0, 1.0), (1e-9, 100), probe);
        assert!(near < 0.3 && 0.3 <= far && far - near <= 1e-9);
        assert!(out.unwrap().converged);
        // A probe that fails at its third call returns the ends of the two before.
        let mut calls = 0;
        let failing = |x: f64, _: &f64, _: &f64| {
            calls += 1;
            if calls == 3 {
                Err(calls)
            } else {
                Ok(Probe::Far(x))
            }
        };
        let (near, far, out) = narrow((0.0, 1.0), (0.0, 1.0), (1e-9, 100), failing);
        assert_eq!((near, far, out.err()), (0.0, 0.25, Some(3)));
    }
}
