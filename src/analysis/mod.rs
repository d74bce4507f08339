//! Analyses of simulations: period detection, stroboscopic orbits, phase portraits and
//! Poincaré sections, parallel parameter sweeps, bifurcation diagrams and a bifurcation
//! locator.
//!
//! Nothing here knows about a particular model: the sample-level tools work on plain `f64`
//! data and user closures, and the simulation-level tools work on any
//! [`RotorModel`](crate::hybrid::RotorModel)(crate::hybrid::RotorModel), a swept parameter being a closure that builds
//! the model at each value (see [bifurcation diagrams](#bifurcation-diagrams)). The paper's model has
//! ready-made families over its parameters in [`crate::paper::ParamSweep`].
//!
//! * [Period detection](#period-detection): is a sampled orbit periodic, and with which period ([`PeriodTest`] for
//!   state vectors)? How many distinct values does a bifurcation-diagram column hold?
//! * [Stroboscopic orbits](#stroboscopic-orbits): stroboscopic orbits of a model after a transient ([`strobe_orbit`]).
//! * [Phase portraits](#phase-portraits): dense samples with the event log, split into smooth pieces, and Poincaré
//!   sections through them ([`phase_portrait`]).
//! * [Poincaré sections](#poincaré-sections): where a densely sampled trajectory crosses a section.
//! * [Parallel sweeps](#parallel-sweeps): run a computation over a list of parameter values in parallel, with
//!   independent values or with the state carried from one value to the next, with results
//!   that are bitwise independent of the number of threads.
//! * [Bifurcation diagrams](#bifurcation-diagrams): bifurcation diagrams of a model family.
//! * [Per-revolution outputs](per_revolution) of a run at a varying speed: the largest
//!   radius, the time in contact and in each regime, revolution by revolution ([`Revolution`]).
//! * [Spectra and order tracking](#spectra-and-order-tracking): whirl spectra of an orbit $x + iy$, spectra in
//!   shaft orders, and order tracking through a run-up ([`order_track`]).
//! * [Locating a change of period](#locating-a-change-of-period): where the detected period changes along a parameter, by bisection.
//!
//! # Period detection
//!
//! Period detection for sampled (stroboscopic) orbits, and counting distinct values.
//!
//! ## The test
//!
//! Let `x_0, …, x_{n-1}` be the samples (state vectors of equal length `d`, taken once per
//! forcing period after the transient). Define
//!
//! * the *extent* `E = max_c (max_i x_i[c] − min_i x_i[c])`, the largest side of the orbit's
//!   bounding box;
//! * the *scale* `S = max(1, E)`;
//! * the *threshold* `θ = tol · S`.
//!
//! Lag `p` passes if **every** sample `i ≥ p` satisfies `‖x_i − x_{i−p}‖∞ ≤ θ`.
//! [`detect_period`] takes the smallest passing `p` with `1 ≤ p ≤ max_period` and reports it as
//! the period if the orbit has converged (see below; else [`Periodicity::NotConverged`]), or
//! [`Periodicity::NotPeriodic`] if no lag passes.
//!
//! So `tol` is relative to the orbit's size for large orbits and absolute for orbits smaller
//! than 1 (in the non-dimensional units of the model the gap is 1, so a fixed point with
//! `tol = 1e-6` is resolved to 1e-6 gap; other units: see [below](#units)). Because every
//! sample is checked, a single outlier (for example a transient not fully discarded) rejects
//! the period: this is deliberate.
//! A period `p` is only tested with at least `p` comparisons, which is why at least
//! `2 · max_period` samples are required.
//!
//! A multiple of the period also passes the test; the smallest passing `p` is the candidate.
//! Quasi-periodic and chaotic orbits pass for no `p` (up to the tolerance: a quasi-periodic
//! orbit whose rotation number is close to `q/p` may pass for `p` if `tol` is loose).
//!
//! ## Units
//!
//! The test above is written for components of order 1. A model in other units (SI: metres
//! and m/s) gives each component its typical magnitude, [`RotorModel::state_scale`]: the
//! samples are then tested in units of their scale, `x_i[c] / scale[c]` (everything above,
//! the extent, `S`, the threshold and the residuals, in those units), so that
//! `|x_i[c] − x_{i−p}[c]| ≤ tol · scale[c] · max(1, E)`: absolute in units of the scale for
//! orbits smaller than it, relative to the orbit's size for larger ones.
//! [`PeriodTest::detect_scaled`], [`detect_period_scaled`] and
//! [`StrobeOrbit::period`](StrobeOrbit::period) (which carries its model's scale) do
//! this; with a scale of 1 (the paper's model) the result is bitwise that of [`detect_period`].
//!
//! [`RotorModel::state_scale`]: crate::hybrid::RotorModel::state_scale
//!
//! ## A converging orbit is not a cycle
//!
//! Passing the tolerance is not enough. Near a Neimark-Sacker point (a multiplier pair
//! `m e^{±2πi a/b}` with `|m|` just below 1) the transient of a stable **fixed point** is a
//! slowly shrinking spiral that turns `a` times in `b` samples, so the lag-`b` differences are
//! about `(1 − m^b)/|m e^{2πi a/b} − 1|` times the lag-1 ones (1/12 for `m = 0.98`, `a/b =
//! 3/8`): lag `b` (or any lag where the spiral nearly closes) passes while lag 1 does not, and a
//! fixed point would be reported as a cycle of period 8. A flip multiplier near −1 does the same
//! with lag 2. So the candidate `p` is only reported as [`Periodicity::Period`] after two checks
//! on the residuals **per window**: the comparisons `i = p, …, n−1` are cut into
//! `W = min(4, n − p)` consecutive windows of (nearly) equal length, and the residual of a
//! window is the largest `‖x_i − x_{i−p}‖∞` in it ([`window_residuals`], relative to `S`).
//!
//! 1. **A shorter period that explains the points wins.** If for a proper divisor `q` of `p`
//!    the lag-`q` residual is still shrinking (last window at most 0.9 times the first), the
//!    points may be converging to a period-`q` orbit. For a genuine period-`p` cycle the lag-`q`
//!    residual is the distance between distinct cycle points: stationary, well above the
//!    tolerance, so a fall of 10 % is not noise.
//! 2. **The cycle itself has converged.** If the lag-`p` residual is still shrinking (falling
//!    from every window to the next, the last at most half the first: noise at the
//!    tolerance's level rarely does both), its geometric decay is extrapolated: with the contraction
//!    per lag `s = (ρ_last/ρ_first)^{p/Δ}` (`Δ` the distance in samples between the centres of
//!    the first and the last window), the points still have to move by about
//!    `ρ_last · s/(1 − s)`; if that exceeds `tol`, the cycle has not converged. Residuals at the
//!    round-off or integration-noise level, far below `tol`, pass this check whatever their
//!    trend.
//!
//! If either check fails, the answer is [`Periodicity::NotConverged`], with what was seen:
//! the passing lag and the shrinking lag, each with its residual per window. Run longer (as
//! [`crate::global::find_attractor`] does) and test again. The checks are conservative: a
//! genuine cycle whose lag-`q` residual is within a few tolerances of zero and noisy at the
//! tolerance's level may be reported as not converged rather than as a cycle; a fixed point
//! whose multipliers are within about `1e-3` of a root of unity can still show a lag-`p`
//! residual that neither shrinks visibly within the record nor exceeds the tolerance.
//!
//! # Stroboscopic orbits
//!
//! **One convention: `(transient, record)`.** Every analysis that runs a model to its
//! stroboscopic points ([`strobe_orbit`], [`BifurcationOptions`], [`LocatorOptions`],
//! [`crate::global::AttractorOptions`], [`crate::stability::LyapunovOptions`]) discards
//! `transient` forcing periods and keeps the next `record`. The driver's own
//! [`OutputPlan::strobe`](crate::hybrid::OutputPlan::strobe) and the paper model's
//! [`strobe_range`](crate::paper::JeffcottModel::strobe_range) take the raw index range
//! `first..=last` instead, and say so in their name.
//!
//! Stroboscopic orbits of any [`RotorModel`](crate::hybrid::RotorModel): the Poincaré map of the forcing phase.
//!
//! ## Conventions
//!
//! * Time starts at $t = 0$; stroboscopic point `k` is the state at $t_k = kP$, $P$ the
//!   model's [`forcing_period`](crate::hybrid::RotorModel::forcing_period) (for the paper's model
//!   $P = 2\pi/\eta$, so the forcing phase is $\varphi_0$ at every point).
//! * "`transient` periods discarded, `record` periods kept" means the run covers
//!   `transient + record` periods and keeps the points `k = transient + 1 ..= transient + record`
//!   (the state at the *end* of each recorded period). The state handed on to the next
//!   parameter value of a carry-over sweep is the last one, at `k = transient + record`.
//! * Because every run starts at $t = 0$, a state carried from one parameter value to the next
//!   is taken at the same forcing phase, as in a physical run-up where the speed is changed
//!   slowly.
//!
//! # Phase portraits
//!
//! Phase portraits of any [`RotorModel`](crate::hybrid::RotorModel): dense samples that know where the state's
//! derivative jumps, and Poincaré sections through them.
//!
//! # Poincaré sections
//!
//! Section crossings of a densely sampled trajectory (generic Poincaré-section helpers).
//!
//! Given samples `(t_k, x_k)` of a trajectory and a *section function* `h(t, x)`, a crossing is
//! a sign change of `h_k = h(t_k, x_k)` between two consecutive samples:
//!
//! * rising: `h_k < 0 ≤ h_{k+1}`; falling: `h_k > 0 ≥ h_{k+1}`.
//!
//! The half-open test counts a sample lying exactly on the section once (in the interval that
//! ends on it). A trajectory that touches the section and turns back between two samples is
//! missed; one that touches it exactly at a sample counts as a crossing. Sample densely enough
//! that `h` changes sign at most once per interval.
//!
//! Within the interval the crossing is located either
//!
//! * linearly ([`section_crossings`]): `θ = h_k / (h_k − h_{k+1})`, state and time interpolated
//!   linearly (error `O(Δt²)`); or
//! * with cubic Hermite interpolation ([`section_crossings_hermite`]), which also uses the time
//!   derivatives `x'_k` (error `O(Δt⁴)`): `h` along the Hermite cubic is solved for `θ` by the
//!   crate's root finder [`numeric::illinois`](crate::numeric::illinois), a fixed number
//!   of steps at most, so the result is deterministic.
//!
//! Every [`Crossing`] carries the final bracket of its search ([`Crossing::bracket`]) and
//! whether the search converged ([`Crossing::converged`]): the located point is an end of the
//! bracket, where `h` has the sign it has after the crossing (or is zero), unless the other
//! end has the smaller `|h|`. An unconverged search (it ran out of steps, or `h` returned NaN
//! on the interpolant) is reported, flagged, never passed off as located: check `converged`.
//!
//! The stroboscopic map of a periodically forced system (`t = t_0 + 2πk/η`) needs no search; it
//! comes from the simulation directly ([`strobe_orbit`]); for a
//! simulated run, [`PhasePortrait::crossings`](PhasePortrait::crossings) applies the
//! Hermite search to the dense samples of each smooth piece.
//!
//! Which crossings count is a [`numeric::Direction`](crate::numeric::Direction), the type guards use:
//! `Rising` (`h` goes from negative to non-negative), `Falling` (from positive to
//! non-positive) or `Either`.
//!
//! # Parallel sweeps
//!
//! A parallel, deterministic parameter sweep.
//!
//! [`sweep`] runs a user-supplied *runner* once per parameter value and returns the results in
//! parameter order. The runner has the signature
//!
//! ```text
//! Fn(&P, Option<S>) -> Result<(T, S), E>
//! ```
//!
//! It receives the parameter value and, optionally, the state `S` left by the previous value;
//! it returns what to record (`T`) and the state to hand on, or an error `E`. `None` means
//! "start from your reset state" (for the rotor: zero initial conditions); a runner that needs
//! a longer transient after a reset can tell from the `None`.
//!
//! ## Modes
//!
//! * [`SweepMode::Reset`]: every value starts from the reset state (the runner always gets
//!   `None`). The values are independent and run in parallel, one task per value.
//! * [`SweepMode::CarryOver`]: the state at the end of value `k` seeds value `k + 1`, as when a
//!   physical experiment turns the speed up slowly. A chain is sequential by nature, so the list
//!   is split into `chunks` contiguous chunks ([`chunk_ranges`]); each chunk starts from the
//!   reset state and the chunks run in parallel. With `chunks = 1` the whole sweep is one chain
//!   (serial); more chunks use more cores at the price of a fresh transient at each chunk start.
//!
//! ## Determinism
//!
//! The chunk boundaries depend only on the number of values and on `chunks`, which the caller
//! fixes; they never depend on the number of threads. Each value is computed by exactly one call
//! of the runner, with inputs (the parameter and the carried state) that are themselves fixed by
//! the parameter list and the mode. So if the runner is a deterministic function of its inputs,
//! the results are **bitwise identical for any number of threads** (1, 2 or the whole machine),
//! and they are returned in parameter order whatever order the threads finish in.
//!
//! ## Failures
//!
//! A runner error at one value is recorded in that value's slot (`Err(e)`) and the sweep goes
//! on. In carry-over mode there is no state to carry past a failure, so the **next value starts
//! from the reset state** (the runner gets `None`), exactly as at a chunk start. A panic inside
//! the runner is not caught: it propagates out of [`sweep`] (a panic is a bug, not a result).
//!
//! ## Progress
//!
//! After each value a [`Progress`] observer, if given, is called with `(done, total)`. Calls come
//! from the worker threads; each `done` in `1..=total` is reported exactly once, but not
//! necessarily in increasing order. [`StderrProgress`] prints a throttled progress line.
//!
//! # Bifurcation diagrams
//!
//! Bifurcation diagrams of any one-parameter family of [`RotorModel`](crate::hybrid::RotorModel)s.
//!
//! A family is given by two closures:
//!
//! * `build: Fn(f64) -> Result<M, E>` makes the model at a parameter value (`E` is the
//!   builder's own error, e.g. invalid parameters);
//! * `start: Fn(&M, Option<&OVector<f64, M::Dim>>) -> Result<OVector<f64, M::Dim>, ModelError>`
//!   gives
//!   the initial state of the run at that value. It receives `None` for a run from the reset
//!   state (every value in [`SweepMode::Reset`], each chunk start and
//!   the value after a failure in carry-over mode, every evaluation of the locator) and
//!   `Some(y)`, the previous value's final state, when the state is carried over. A model with
//!   algebraic components (e.g. a massless ring placed by its contact law) re-places them here
//!   if the parameter moves them. [`start_from`] is the common rule "reset runs start from a
//!   fixed state, carried states are used as they are".
//!
//! Each value's run discards `transient` forcing periods, records `record` stroboscopic points
//! ([`strobe_orbit`]) and detects their period ([`PeriodTest`]); the conventions are those of
//! [stroboscopic orbits](#stroboscopic-orbits). The paper's model has ready-made families over its parameters:
//! [`crate::paper::ParamSweep`].
//!
//! # Locating a change of period
//!
//! Locating a change of the detected period (a bifurcation) along a parameter, by bisection.
//!
//! Near a bifurcation the transient decays slowly, so a periodic orbit may still be reported as
//! "not periodic" after a short transient: the locator therefore takes its own, longer
//! transient ([`LocatorOptions::transient`]).
//!
//! # Spectra and order tracking
//!
//! [`full_spectrum`] and [`amplitude_spectrum`] for records equally spaced in time,
//! [`AngleSamples`] for records at equal steps of the shaft's angle (taken as they are or
//! resampled) with their spectrum in shaft orders ([`AngleSamples::order_spectrum`]), and
//! [`order_track`]: the whirl amplitudes of chosen orders against the speed through a run-up.
//!
//! **The transform and its amplitude.** A record $z_0, \dots, z_{N-1}$ at the step $\Delta$
//! (time, or revolutions for angle samples) is weighted by a window $w_n$ and transformed,
//! $Z_k = \sum_n w_n z_n e^{-2\pi i kn/N}$ ([`rustfft`]). The window's coherent gain
//! $G = \frac1N\sum_n w_n$ (1 rectangular, 1/2 Hann) corrects the amplitude: a circular whirl
//! $z = A e^{i(2\pi f t + \psi)}$ of frequency $f = k/(N\Delta)$ on a bin reads
//! $|Z_k|/(NG) = A$ exactly (forward, $f > 0$), and a backward whirl $A e^{-i(2\pi f t + \psi)}$
//! reads $A$ at $Z_{N-k}$. So [`FullSpectrum::forward`]`[k]` $= |Z_k|/(NG)$ and
//! [`FullSpectrum::backward`]`[k]` $= |Z_{N-k}|/(NG)$ are the radii of the circular whirls
//! forward and backward at the frequency $k/(N\Delta)$, $0 < k < N/2$; bin 0 holds the mean
//! $|\bar z|$ in `forward` (0 in `backward`); the Nyquist bin is left out. For a real signal
//! ([`amplitude_spectrum`]) $x = A\cos(2\pi f t + \psi)$ is half forward and half backward:
//! its amplitude is $A = $ forward + backward.
//!
//! **Off the bins.** The periodic Hann window $w_n = \frac12(1 - \cos(2\pi n/N))$ spreads an
//! on-bin component over its bin and the two neighbours only (the others read 0), so components
//! two bins apart or more are read without leakage. A frequency between bins reads low at the
//! nearest bin by at most the scalloping loss [`Window::scalloping_loss`]: 15.1 % for Hann
//! (1.42 dB, half a bin off: $\frac{2}{\pi}/\frac34 = 0.8488$), 36.3 % rectangular. Records of
//! a whole number of revolutions put every order that is a multiple of 1/revolutions on a bin.
//!
//! **Resampling in the angle domain.** A record at any times $t_i$, with the shaft's phase
//! $\varphi_i = \varphi(t_i)$ there (from the speed profile: `SpeedProfile::phase`), is
//! interpolated at the phases $2\pi k/S$ by 6-point Lagrange interpolation in the phase (the
//! three samples each side; at the record's ends the six nearest): for a coordinate smooth in
//! the phase its error is at most $\frac{225}{64\cdot720}h^6\max|f^{(6)}| = 0.0049\thinspace h^6
//! \max|f^{(6)}|$ at an interval's middle, $h$ the local phase step (measured in
//! `tests/suite/analysis/order.rs`). Contact makes the orbit's velocity jump: the interpolation loses
//! its order on the samples around a touch, so a record already at the phases (the strobes of
//! `ProfiledJeffcott::with_strobes_per_revolution`) is better taken as it is
//! ([`AngleSamples::new`]).
//!
//! **Tracking.** Windows of $W$ revolutions ($N = WS$ samples), one every `hop_revolutions`,
//! are weighted (Hann by default) and transformed as in [`full_spectrum`]
//! with the step $1/S$ revolution: bin $k$ is the order $k/W$, so the orders that are
//! multiples of $1/W$ fall on bins (no scalloping), and the Hann window reads an order two bins
//! or more from the others without leakage. The row's centre is the sample $c = N/2$, about which the periodic Hann window is symmetric: an amplitude that varies
//! linearly with the phase across the window is read exactly at the centre (a curvature of the
//! envelope over the window is averaged). Its speed is the angular speed there, $1/t^\prime(\varphi)$
//! by the fourth-order central difference of the samples' times,
//! $t^\prime \approx (-t_{c+2} + 8t_{c+1} - 8t_{c-1} + t_{c-2})/(12\thinspace\Delta\varphi)$ (the window's
//! mean speed would lag in a fast ramp).

mod bifurcation;
mod error;
mod locate;
mod orbit;
mod order;
mod order_track;
mod period;
mod poincare;
mod portrait;
mod revolutions;
mod sweep;

pub use bifurcation::{bifurcation, start_from, Bifurcation, BifurcationOptions, Column, Failure};
pub use error::{AnalysisError, OrbitError};
pub use locate::{locate_period_change, LocatedChange, LocatorOptions, PeriodChange};
pub use orbit::{strobe_orbit, PoincareMap, StrobeOrbit};
pub use order::{amplitude_spectrum, full_spectrum, FullSpectrum, Spectrum, Window};
pub use order_track::{order_track, AngleSamples, OrderRow, OrderTrackOptions};
pub use period::{
    count_distinct, detect_period, detect_period_scalar, detect_period_scaled, distinct_values,
    recurrence_residual, window_residuals, LagResiduals, PeriodTest, Periodicity, MAX_WINDOWS,
};
pub use poincare::{section_crossings, section_crossings_hermite, Crossing};
pub use portrait::{phase_portrait, PhasePortrait};
pub use revolutions::{per_revolution, Revolution};
pub(crate) use sweep::on_pool;
pub use sweep::{
    chunk_ranges, linspace, sweep, Progress, StderrProgress, SweepMode, SweepOptions, SweepResult,
};
