//! Stability of non-smooth orbits: linearisation of the hybrid flow through its events,
//! periodic orbits and their Floquet multipliers, Lyapunov exponents, and where an orbit loses
//! stability along a parameter.
//!
//! Smooth variational equations are wrong across a contact: a perturbation that moves an event
//! in time picks up the jump of the vector field there, the **saltation matrix**
//! ([`saltation()`]). Integrated with the state through every event, the variational
//! equations give the Jacobian of the stroboscopic map exactly where the map is smooth, and
//! say where it is not (grazing, with its margin).
//!
//! What a model supplies for its linearisation is the trait [`Variational`](crate::hybrid::Variational) of
//! [`crate::hybrid`] (field and reset Jacobians, guard gradients, the closed form's Jacobian,
//! its algebraic components, with finite-difference defaults), implemented with each model:
//! analytic for [`crate::paper::JeffcottModel`], the ring's parts analytic for
//! [`crate::rotor::RingedRotor`]. This module uses the trait only and names no model. The
//! layers, bottom up:
//!
//! | item | role |
//! |---|---|
//! | [`saltation()`] | the saltation matrix of one event, any dimension, typed grazing flag |
//! | [`StroboscopicMap`] | $P^n$ on the non-algebraic components and its Jacobian $DP^n$ (or $DP^n Q$) |
//! | [`periodic_orbit`] | Newton on $P^n(z) - z$: point, residual, multipliers, grazing margins |
//! | [`dominant_multipliers`] | the multipliers of largest modulus matrix-free: Arnoldi on the Jacobian-vector products $DP^n q$, never the dense $DP^n$ (large models) |
//! | [`lyapunov_exponents`] | QR (Benettin) spectrum with batch-means errors, two-trajectory check |
//! | [`continue_orbit`], [`switch_at_flip`] | the continuation core: pseudo-arclength along a parameter (a closure builds the model) through folds, with fold, flip, Neimark–Sacker and grazing located, and branch switching at a flip |
//! | [`lyapunov_exponents_with_progress`], [`continue_orbit_with_progress`] | the same with a [`Progress`](crate::analysis::Progress) observer, told of each period or point and asked between them whether to stop (Ctrl-C, a time limit): a stopped run returns what it computed ([`StabilityError::Stopped`], [`BranchEnd::Stopped`]) |
//! | [`rub_map`] | a branch continued in the speed (or any parameter), each orbit measured at the ring: largest radius, fraction of the period in contact, largest normal force, stability ([the rub map](#the-rub-map)) |
//! | [`locate_loss`] | its natural-parameter case: where a stable orbit loses stability (flip, fold, Neimark–Sacker, grazing), or a failure with its error |
//! | [`multipliers`], [`newton_fixed_point`], [`BatchEstimate`] | the numerics underneath, on plain matrices and closures ([Floquet multipliers](#floquet-multipliers), [Newton](#newton), [batch means and QR](#batch-means-and-qr)) |
//!
//! The ring's own derivatives are in [the ring's module](crate::ring#derivatives-of-the-element), the paper's free flight's
//! transition matrix in [`crate::paper::FreeOscillator::transition_matrix`]. The
//! method, every saltation matrix of the model written out, the cross-checks and the results
//! are in [stability.md](https://docs.rs/crate/jeffcott/latest/source/docs/stability.md).
//!
//! # Saltation matrices
//!
//! The saltation matrix: how a perturbation passes through an event of a hybrid flow.
//!
//! A trajectory of $x^\prime = f^-(t, x)$ meets the guard $g(t, x) = 0$ at $(t_e, x^-)$; the
//! reset $x^+ = R(t_e, x^-)$ starts the flow $x^\prime = f^+(t, x)$. A neighbouring trajectory,
//! $\delta x^-$ away just before the event (both taken at the nominal $t_e$, the perturbed one
//! continued smoothly), meets the guard at $t_e + \delta t_e$ with
//!
//! $$\delta t_e = -\frac{\nabla g\cdot\delta x^-}{\nabla g\cdot f^- + g_t},$$
//!
//! and leaves it $\delta x^+ = S\thinspace \delta x^-$ away, with the **saltation matrix**
//!
//! $$S = R_x + \frac{(f^+ - R_x f^- - R_t)\thinspace \nabla g^{\mathsf T}}{\nabla g\cdot f^- + g_t}.$$
//!
//! All quantities at the event: $f^\pm = f^\pm(t_e, x^\pm)$, $\nabla g = \partial g/\partial x$,
//! $g_t = \partial g/\partial t$, $R_x = \partial R/\partial x$, $R_t = \partial R/\partial t$
//! (identity and zero when the state is not reset). The Jacobian of a flow through an event is
//! then $\Phi^+\thinspace S\thinspace \Phi^-$.
//!
//! ## Grazing
//!
//! The denominator $\nabla g\cdot f^- + g_t$ is the rate at which the guard crosses zero. When
//! it vanishes the trajectory touches the guard tangentially (grazing), the event map is not
//! differentiable there, and $S$ grows like its inverse unless the numerator vanishes with it.
//! Its size is judged relative to the scale of the terms it is made of,
//!
//! $$\text{margin} = \frac{|\nabla g\cdot f^- + g_t|}{|\nabla g|\thinspace|f^-|_{\nabla g} + |g_t|}
//! \in [0, 1],$$
//!
//! $|f^-|_{\nabla g}$ the norm of $f^-$ over the components where $\nabla g$ is not zero (so that a
//! guard on positions is not judged against accelerations), both norms in the coordinates
//! $x_c/s_c$ scaled by the model's [`RotorModel::state_scale`](crate::hybrid::RotorModel::state_scale)
//! when the event gives it ([`EventLinearization::state_scale`]; so that a guard on positions
//! and velocities is judged alike in any units): the cosine of the angle at which the
//! flow crosses the guard, corrected for its explicit time dependence. [`saltation`] returns
//! [`SaltationError::Grazing`] when the margin is below the threshold it is given
//! ([`GRAZING_MARGIN`] $= 10^{-3}$ by default), never a matrix that rounding or the
//! non-smoothness of the event map has made meaningless without saying so. Whether a saltation
//! stays bounded at grazing is a property of the model (for the snubber ring, the onset and
//! preload-crossing saltations do, the loss saltation does not: `docs/stability.md`); a caller
//! that knows its limit may pass a smaller threshold, and reads the margin on the result.
//!
//! # The stroboscopic map
//!
//! The stroboscopic map and its Jacobian.
//!
//! $P^n$ maps the state at $\tau = 0$ to the state $n$ forcing periods later
//! ($\tau_k = 2\pi k/\eta$ for the paper's model). It acts on the model's **non-algebraic**
//! components $z$ (the rotor's four states $(x, y, x^\prime, y^\prime)$ for the paper's model):
//! the algebraic ones are placed by the model from $z$ at the section
//! ([`Variational::section_state`](crate::hybrid::Variational::section_state)). For the ring this is exact when the section falls in
//! contact ($s = s^*(r)$) or in free flight with the ring relaxed to its centre (exactly 0 in
//! double precision on the paper's orbits); otherwise the map on $z$ is not closed, and
//! [`Linearization::openness`] says by how much (the ring's distance from its centre).
//!
//! Its Jacobian comes from the variational equations integrated with the state through every
//! event (`stability::augmented`), not from differences: the run that gives $P^n(z)$ gives
//! $DP^n(z)$, on the same steps.
//!
//! # Periodic orbits
//!
//! Periodic orbits by shooting: Newton's method on $P^n(z) - z$ with the Jacobian of the
//! variational equations, the Floquet multipliers, and the orbit's grazing margins.
//!
//! **Margins.** A periodic orbit of a contact model can lose or gain a contact without any
//! multiplier reaching the unit circle (a grazing bifurcation), and near one the map is not
//! smooth. [`OrbitMargins`] measures how far the orbit is from that: the number of contact
//! phases per orbit, the smallest penetration depth of a contact, the closest approach to
//! contact in free flight (both from the model's [`Variational::contact_depth`](crate::hybrid::Variational::contact_depth), sampled 64
//! times on each smooth piece between events and refined by a parabola through the largest
//! sample and its neighbours), and the smallest crossing margin of the events' saltation
//! matrices. An orbit with an event crossed at a margin below [`GRAZING_MARGIN`] is flagged
//! ([`PeriodicOrbit::grazing`]): its multipliers are those of a map that is not
//! differentiable there.
//!
//! # Floquet multipliers
//!
//! Floquet multipliers: the eigenvalues of a monodromy matrix, sorted, and how a multiplier
//! leaves the unit circle.
//!
//! For a periodic point $z^{\ast} = P^n(z^{\ast})$ of a stroboscopic map the multipliers are the
//! eigenvalues of the monodromy matrix $DP^n(z^{\ast})$. The point is asymptotically stable when
//! every multiplier has modulus below 1; it loses stability when one crosses the unit circle:
//! a real multiplier through $-1$ (**flip**, period doubling), through $+1$ (**fold**, saddle
//! node), or a complex pair (**Neimark–Sacker**, a torus).
//!
//! Eigenvalues come from nalgebra's real Schur decomposition (pure Rust, backward stable:
//! their error is about $\varepsilon\thinspace\lVert A\rVert$ times the eigenvalue's condition
//! number).
//!
//! # Lyapunov exponents
//!
//! Lyapunov exponents of the stroboscopic map.
//!
//! * **Spectrum, QR (Benettin) method.** Along a trajectory $y_{k+1} = P(y_k)$ the variational
//!   equations carry an orthonormal frame $Q_k$ ($d\times d$, $d$ the number of non-algebraic
//!   components) through one forcing period, $DP(z_k)\thinspace Q_k = Q_{k+1}R_k$, and
//!   $\lambda_i = \langle\ln R_{k,ii}\rangle$ per forcing period (divide by $2\pi/\eta$ for per
//!   unit $\tau$). The first periods align the frame and are not recorded.
//! * **Statistical error.** Batch means over the recorded periods (`statistics`), with the
//!   batch length stated in the result; the running estimate after each batch shows the
//!   convergence.
//! * **Largest exponent, two-trajectory method** (independent of the variational equations):
//!   a second trajectory $d_0$ away along $u_k$ is run one period with the model's own
//!   simulation, its distance $d_{k+1}$ recorded as $\ln(d_{k+1}/d_0)$, and it is renormalised
//!   back to $d_0$ along the new separation (distances in units of the model's
//!   [`RotorModel::state_scale`](crate::hybrid::RotorModel::state_scale), so that they mean
//!   the same in any units).
//! * **Sum of the exponents.** With the whole spectrum, $\sum_i\lambda_i$ is the mean of
//!   $\ln|\det DP(z_k)|$ by construction (the product of the QR's diagonal), so it is no check
//!   of $DP$. The check is Liouville's formula along the trajectory, independent of the
//!   variational code: $\ln|\det DP| = \int\operatorname{tr}(\partial f/\partial y)\thinspace d\tau +
//!   \sum_e\ln|\det S_e|$ over the period (`tests/suite/stability/stability_lyapunov.rs`,
//!   docs/stability.md).
//!
//! Every event of the fiducial trajectory is crossed through its saltation matrix; the result
//! counts those crossed at a margin below [`GRAZING_MARGIN`] (the exponents stay meaningful:
//! the saltations of the ring's onset and preload crossings are bounded at grazing), and the
//! sections at which the map on $z$ was not closed (a ring that has not relaxed in free flight).
//!
//! # Batch means and QR
//!
//! Time averages with a statistical error: batch means, and the QR (Benettin) bookkeeping of
//! Lyapunov exponents.
//!
//! ## Batch means
//!
//! A time average $\bar x = \frac1n\sum_k x_k$ of a correlated series (one value per forcing
//! period) has a standard error that the sample variance underestimates. Split the series into
//! $m$ consecutive batches of length $b$; when $b$ is long against the correlation time the
//! batch means $\bar x_j$ are nearly independent, and
//!
//! $$\operatorname{se}(\bar x) \approx \frac{s_b}{\sqrt m},\qquad
//! s_b^2 = \frac{1}{m - 1}\sum_j (\bar x_j - \bar x_b)^2 .$$
//!
//! The estimate is honest only if $b$ exceeds the correlation time: check it by doubling $b$
//! (the error must not grow). The batch means are kept with the running estimate
//! (the mean after each complete batch).
//!
//! ## QR re-orthonormalisation
//!
//! With $Q_k$ orthonormal ($d\times p$) and $Y = DP(z_k)\thinspace Q_k = Q_{k+1}R_k$ (thin QR, $R_k$
//! upper triangular with a positive diagonal), the $i$-th Lyapunov exponent per iteration of
//! the map is the time average of $\ln R_{k,ii}$. Summed over $i = 1..d$ the
//! samples are $\ln|\det DP(z_k)|$ by construction (an identity of the factorisation, not a
//! check of $DP$; the check of the exponents' sum is Liouville's formula, `lyapunov`).
//!
//! # Newton
//!
//! Newton's method: the one Newton of the crate, for a fixed point of a map with a known
//! Jacobian, $F(z) = P(z) - z = 0$ ([`newton_fixed_point`]), and for the bordered systems of
//! the continuation ([below](#continuation)).
//!
//! Each iteration solves $J\thinspace\delta = -G(u_k)$ by LU with partial pivoting ($J = DP -
//! I$ for a fixed point) and takes the full step if it lowers the residual; otherwise it halves
//! the step (up to [`NewtonOptions::max_halvings`] times), which keeps an iterate that would
//! leave the basin of the orbit from jumping to another one. It stops when every component of
//! the residual is within its tolerance, **relative plus absolute**:
//! $|G_i| \le$ [`atol`](NewtonOptions::atol)$\cdot s_i +$ [`rtol`](NewtonOptions::rtol)$\cdot
//! |u_i|$, $s_i$ the scale of component $i$ (the model's
//! [`state_scale`](crate::hybrid::RotorModel::state_scale); 1 by default), and returns the
//! point with the map's value and Jacobian there (the monodromy matrix). A run that does not
//! converge returns its last iterate and residual inside the error.
//!
//! # Continuation
//!
//! Following periodic orbits along a parameter: one continuation core, one Newton, one locator
//! of special points.
//!
//! The parameter enters through a closure that builds the model at each value (any parameter,
//! any model). A period-$n$ orbit is a zero of $F(z, p) = P^n_p(z) - z$, $z$ the
//! non-algebraic components at the section.
//!
//! * [`continue_orbit`] follows the branch in its **pseudo-arclength** (through folds), with
//!   its stability, and locates every special point on the way; [`switch_at_flip`] starts the
//!   period-$2n$ branch at a flip. The method is [below](#pseudo-arclength-continuation).
//! * [`locate_loss`] is its **natural-parameter** case, for the question "where does this
//!   stable orbit stop being stable?": steps in the parameter itself (the constraint row of
//!   the corrector is $e_p$), each orbit found by [`periodic_orbit`],
//!   until the first loss of stability, which it brackets and reports with the orbit there, or
//!   a [`BranchFailure`] with its error. The method is [below](#loss-of-stability).
//!
//! Both use the one Newton ([Newton](#newton)) with its relative-plus-absolute
//! stopping rule on the model's [`state_scale`](crate::hybrid::RotorModel::state_scale), and
//! the one locator: a special point is bracketed between two orbits and the bracket bisected
//! (by the crate's one bisection, [`crate::numeric::bisect`]) until it is narrower than the options' `bracket_width` (a width, in the
//! parameter's units; the residual tolerances are `atol`/`rtol`).
//!
//! **The special points, one definition.** The multipliers outside the unit circle are
//! counted in three classes: a change of the count of real positive ones is a
//! [**fold**](SpecialKind::Fold) (a real multiplier through $+1$), of real negative ones a
//! [**flip**](SpecialKind::Flip) (through $-1$), of complex ones a
//! [**Neimark–Sacker**](SpecialKind::NeimarkSacker) bifurcation. A change of the orbit's
//! **event structure** (the guards crossed over one orbit, compared up to a rotation; for an
//! orbit without events the mode it stays in, so that a permanent contact differs from free
//! flight) is a
//! [**grazing**](SpecialKind::Grazing): the margin of a contact onset (or of a regime boundary
//! in contact) going to zero, a contact gained or lost; the multipliers do not announce it.
//! The contacts per orbit are the events on guards the model calls contact onsets
//! ([`RotorModel::is_contact_onset`](crate::hybrid::RotorModel::is_contact_onset)).
//!
//! # Pseudo-arclength continuation
//!
//! Continuation of periodic orbits in any scalar parameter: pseudo-arclength through folds,
//! stability along the branch, bifurcations located, branch switching at a flip, and grazing
//! (a contact gained or lost) detected, located and passed.
//!
//! ## The method
//!
//! A period-$n$ orbit is a zero of $F(z, p) = P^n_p(z) - z$, $z$ the non-algebraic components at
//! the section $\tau = 0$ (the rotor's $(x, y, x^\prime, y^\prime)$ for the paper's model) and
//! $p$ the parameter, the model being built at each $p$ by a closure. The branch is followed in
//! the **scaled** coordinates $w = (z_i/s_i,\ p/s_p)$, $s_i$ the model's
//! [`error_scale`](crate::hybrid::RotorModel::error_scale) where it gives one (a
//! finite-element rotor's: each velocity weighed by its coordinate's own frequency, so that
//! the high modes a contact excites do not dominate the step), else its
//! [`state_scale`](crate::hybrid::RotorModel::state_scale), and $s_p$
//! [`ContinuationOptions::param_scale`] (so that the arclength does not mix units), in its
//! arclength $s$ (pseudo-arclength): from a point $w_k$ with unit tangent $t_k$ (the null
//! vector of $[F_w\ F_p]$, oriented along the last one), the predictor $w_k + \Delta s\thinspace
//! t_k$ is corrected by the one Newton ([Newton](#newton), full steps) on
//!
//! $$F(w) = 0,\qquad t_k\cdot(w - w_k - \Delta s\thinspace t_k) = 0,$$
//!
//! which stays regular at a fold, where $p$ turns back. $F_z = DP^n - I$ is the Jacobian of the
//! variational equations through every event ([`StroboscopicMap`]); $F_p$ is a central
//! difference in $p$ (step $h = $ [`ContinuationOptions::param_step`] $\cdot(1 + |p|)$). The
//! corrector stops when $|F_i| \le$ `atol`$\cdot s_i +$ `rtol`$\cdot|z_i|$ (and the constraint
//! is within $10^3$ `atol`). The step grows by 1.5 after an easy correction (at most 3
//! iterations) up to [`ContinuationOptions::ds_max`] and halves after a failed one (a
//! correction that does not converge, or one larger than the step: Newton jumped to another
//! branch). Below [`ContinuationOptions::ds_min`] the corrector gets one more chance, a
//! **leap**: where a contact starts the map is only once differentiable (and where a
//! permanent contact starts, a full annular rub, its Jacobian jumps), and Newton, its
//! Jacobian taken on one side, can fail at every step across it. The leap steps the parameter
//! alone, by a quarter, a half and then all of `ds_max`, runs 200 periods there from the last
//! orbit and corrects at that parameter from where the run ended: past a grazing into a stable
//! contact the run lands next to the orbit. If no leap converges the branch ends
//! ([`BranchEnd::Stalled`]); after one, the step starts again from
//! [`ContinuationOptions::ds`], and the grazing between is located as any special point.
//!
//! ## Special points
//!
//! At every point the multipliers (eigenvalues of $DP^n$) are counted outside the unit circle
//! and the event structure recorded ([`super`]'s one definition). Between two points a change
//! of a count is a fold, flip or Neimark–Sacker bifurcation, a change of the event structure a
//! grazing, which the continuation goes on through.
//!
//! Each is located by the one bisection ([`crate::numeric::bisect`]) along the secant between the two
//! points (a corrected point on the hyperplane through the midpoint, normal to the secant)
//! until the bracket is narrower than [`ContinuationOptions::bracket_width`] (in the parameter,
//! and in every component of $z$ relative to its scale); the value reported is the bracket's
//! midpoint, with the multipliers at its near end. If the bisection stops short (no corrected
//! point or no orbit at a midpoint), the point is returned as detected but not located:
//! [`SpecialPoint::converged`] is `false`, with the error and the bracket reached.
//!
//! **Branch switching** ([`switch_at_flip`]): at a flip of the period-$n$ orbit the period-$2n$
//! orbit branches off along the eigenvector $v$ of the multiplier $-1$. Its first point is
//! corrected on the hyperplane $v\cdot(w - w^{\ast}) = a$ (with $p$ free, $v$ in the scaled
//! coordinates) for amplitudes $a$ from $10^{-3}$ up, until a point of minimal period $2n$ is
//! found; its branch is then continued as any other.
//!
//! # Loss of stability
//!
//! Following a periodic orbit along a parameter and locating where it loses stability.
//!
//! The parameter enters through a closure that builds the model at each value (any parameter,
//! any model). From the orbit found at `from`, natural-parameter continuation steps towards
//! `to`, each orbit found by Newton ([`periodic_orbit`]) from a secant prediction of the last
//! two, until one of these happens between two steps:
//!
//! * a multiplier leaves the unit circle (the spectral radius passes 1): **flip** (real,
//!   through $-1$), **fold** (real, through $+1$) or **Neimark–Sacker** (a complex pair);
//! * the orbit's **event structure** changes (a contact appears or disappears: a grazing
//!   bifurcation, which the multipliers do not announce; compared up to a rotation, so that
//!   an event moving across the section does not count);
//! * no orbit is found, and none as the step is halved down to the tolerance.
//!
//! The bracket is then bisected by the one bisection ([`crate::numeric::bisect`]; Newton at each
//! midpoint, warm-started from the stable end)
//! until it is narrower than [`LossOptions::bracket_width`]; for a multiplier crossing the
//! value reported is the linear interpolation of the spectral radius to 1 inside the final
//! bracket, for the others its midpoint. The bisection has no other exit: a located
//! [`StabilityLoss`] always has a bracket of at most the width (or two adjacent floats). The
//! kinds are the one definition of the continuation above ([`SpecialKind`]).
//!
//! **One core, two correctors.** [`locate_loss`] and [`continue_orbit`] run the same
//! stepping loop (its step control, budget and stop rules) and the same locator; they differ
//! in the corrector. With the parameter held fixed (the constraint row $e_p$) the bordered
//! corrector is Newton on $P^n(z) - z$, which is what [`periodic_orbit`] runs (the one Newton,
//! with its step halvings), so the natural mode's corrector calls that: through the bordered
//! corrector each solve would also evaluate $F_p$ (two more runs of the map per iteration,
//! unused at a fixed parameter) and return a branch point without what this question needs at
//! every step: the orbit's margins, minimal period and monodromy. The step control has the
//! natural mode's settings: a failed step is halved while it is wider than
//! [`LossOptions::bracket_width`] (then the failure itself is bisected, a fold or grazing end
//! located from it), a successful one goes back to [`LossOptions::step`].
//!
//! **A failure is not a bifurcation.** Where no orbit is found at the far end of the final
//! bracket, the branch ends there; that is called a bifurcation only on positive evidence at
//! the last orbit found, and only when what failed is Newton itself (no convergence, a
//! singular $DP^n - I$, or an orbit of the wrong branch):
//!
//! * a **fold** if a real multiplier has come near $+1$ (above 0.95, and not farther from 1
//!   than where the bracket started): a branch of period-$n$ orbits ends by turning back;
//! * a **grazing** if an event of the last orbit is crossed tangentially
//!   ([`PeriodicOrbit::grazing`]: its margin has gone to 0): a contact or a regime boundary
//!   met tangentially, where the map is not differentiable.
//!
//! Any other end (a model that cannot be built, a failed simulation, Newton failing with no
//! such evidence, the step budget exhausted) is reported as a [`BranchFailure`] with its
//! error, where it happened and the last orbit found, never as a located point.
//!
//! # The rub map
//!
//! What a design engineer asks of a rotor that may touch its ring: where contact starts over
//! the speed range, how far the rub branch reaches, where it jumps (its folds) and whether it
//! is stable. These are properties of the steady periodic orbits, not of one run-up (whose
//! jump depends on its ramp rate). [`rub_map`] continues the branch of period-$n$ orbits with
//! [`continue_orbit_with_progress`] (every special point located) and measures each orbit at
//! the ring by one run over its period from its point, with dense samples and its events: the
//! station's **largest radius** (located between the knots on the Hermite interpolant, as
//! [`per_revolution`](crate::analysis::per_revolution) does), the **fraction of the period in
//! contact** (from the events' times: 1 for a full annular rub, whose orbit has no onset), and
//! the **largest normal force** over the samples and the events' states (sampled). A model
//! says what the ring sees through the reader it is given ([`RingReading`]: for a rotor on the
//! ring, its station and [`RingedRotor::normal_force`](crate::rotor::RingedRotor::normal_force)).
//! From below the first contact the start is the linear steady orbit
//! ([`LinearRotor::steady_state`](crate::rotor::LinearRotor::steady_state)), where Newton
//! converges at once. The first grazing is the speed where that linear orbit's ellipse reaches
//! the gap; the test `stability::stability_rub_map` checks it against the closed form to
//! $10^{-8}$, a rub orbit against a long run to its attractor and its multipliers against a
//! perturbation's growth.
//!
//! The Jacobian is the dense monodromy matrix of the variational equations: $n$ columns per
//! step, so a reduced or modal model (tens of modes) is the size it suits; the matrix-free
//! path for hundreds of coordinates (Newton-Krylov, Arnoldi) is not built yet.

mod augmented;
mod continuation;
mod dominant;
mod error;
mod floquet;
mod lyapunov;
mod map;
mod newton;
mod orbit;
mod rub_map;
mod saltation;
mod statistics;

pub use augmented::LinearEvent;
pub use continuation::{
    continue_orbit, continue_orbit_with_progress, locate_loss, switch_at_flip, Branch, BranchEnd,
    BranchFailure, BranchPoint, Continuation, ContinuationOptions, ContinuationPoint, LossOptions,
    SpecialKind, SpecialPoint, StabilityLoss,
};
pub use dominant::{dominant_multipliers, DominantMultipliers};
pub use error::StabilityError;
pub use floquet::{multipliers, CrossingKind, FloquetError, Multiplier};
pub use lyapunov::{
    lyapunov_exponents, lyapunov_exponents_with_progress, LyapunovOptions, LyapunovSpectrum,
    TwoTrajectory,
};
pub use map::{Advanced, Linearization, StroboscopicMap};
pub use newton::{newton_fixed_point, FixedPoint, MapValue, NewtonError, NewtonOptions};
pub use orbit::{periodic_orbit, OrbitMargins, OrbitOptions, PeriodicOrbit};
pub use rub_map::{rub_map, RingReading, RubMap, RubMapOptions, RubPoint};
pub use saltation::{saltation, EventLinearization, Saltation, SaltationError, GRAZING_MARGIN};

pub use statistics::BatchEstimate;
