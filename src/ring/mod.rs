//! The preloaded snubber ring as a reusable contact element.
//!
//! All quantities are non-dimensional (lengths in units of the physical gap, forces in units of
//! $k_r \gamma$, time $\tau = \omega_n t$), but the constraint radius [`SnubberRing::gap`] is kept
//! as a field so the element can be used with any scaling (it is 1 in the paper's).
//!
//! # Model
//!
//! Per axis $i \in \lbrace x, y \rbrace$ the ring is held by two preloaded spring-damper units of
//! unit stiffness $K_i > 0$ and preload $D_i \ge 0$ (see [`RingAxis`]). With $s$ the ring centre
//! (the axis index dropped where one axis is meant):
//!
//! * elastic energy
//!   $$e_i(s) = \begin{cases} K s^2 & |s| \le D,\\\\ \tfrac{K}{2}\left((|s| + D)^2 - 2 D^2\right) & |s| \ge D \end{cases}$$
//!   (both give $K D^2$ at $|s| = D$); total $E(s) = e_x(s_x) + e_y(s_y)$;
//! * elastic force $g_i(s) = e_i^\prime(s)$: $2 K s$ inside the preload and
//!   $\operatorname{sign}(s)\thinspace K (|s| + D)$ beyond it (continuous at $|s| = D$, slope
//!   $2K \to K$);
//! * damping $c_i\thinspace s_i^\prime$ with $c_i = 4 \nu_2$ inside (both units act) and
//!   $2 \nu_2$ beyond (one unit has lifted off);
//! * total force of the ring $f = g(s) + C s^\prime$, $C = \operatorname{diag}(c_x, c_y)$.
//!
//! An axis is *inside* its preload when $D > 0$ and $|s| \le D$, and *beyond* it otherwise: an
//! axis with zero preload is always beyond (then $g = K s$, $c = 2 \nu_2$). The same predicate
//! decides the energy branch, the force branch, the damping coefficient, the Jacobian and the
//! regime, so they never disagree (the paper's strict $|s| < D$ for the damping only differs on
//! the set $|s| = D$).
//!
//! In contact ($|r| > \mathrm{gap}$) the ring sits at the energy minimiser $s^{\ast}(r)$ on the
//! circle $|r - s| = \mathrm{gap}$ ([`SnubberRing::locate`], see [below](#where-the-ring-sits-in-contact) and
//! [ring.md](https://docs.rs/crate/jeffcott/latest/source/docs/ring.md) for the solver); out of
//! contact the massless ring relaxes exactly ([`SnubberRing::relax`]).
//!
//! # The ring as a contact element
//!
//! The ring as a contact element: its modes, guards and transitions.
//!
//! A rotor model composes the ring with the displacement $r$ and velocity $r^\prime$ of the rotor
//! at the ring's station ([`Kinematics`], relative to the ring's rest centre) and gets from here
//! every rule that makes the ring a contact element, so that no model re-derives them:
//!
//! * **modes** ([`RingMode`]): free flight, where the massless ring relaxes in closed form from
//!   the state it was left in ([`Relaxation`]), or contact on given force-law branches
//!   ([`Branches`]: the regimes II..V, each continued smoothly past its boundaries);
//! * **guards** ([`RingGuard`], [`SnubberRing::guard`], [`SnubberRing::guard_value`],
//!   [`SnubberRing::guard_rate`]): contact onset $h = |r - s(t)|^2 - \gamma^2$ rising through 0
//!   in free flight; in contact, loss (the loss force, below, falling through 0), the rotor back
//!   at the gap circle ($|r|^2 - \gamma^2$ falling through 0) and one preload crossing per
//!   preloaded axis ($|s_i| - D_i$ through 0), which switches that axis' branch;
//! * **the ring's position, velocity and force** in each mode ([`SnubberRing::ring_state`]);
//! * **transitions** ([`SnubberRing::transition`]): the next mode and where the ring is placed,
//!   with the acceptance rule of a touch, the no-pull test and the corner rule built in;
//! * **consistent initial states** ([`SnubberRing::consistent_position`],
//!   [`SnubberRing::initial_mode`], and [`SnubberRing::start_mode`] for an integrated free
//!   flight: a start touching the ring and moving into it begins with the touch).
//!
//! ## The rules
//!
//! **Loss force.** In contact the paper's normal force is $N = n\cdot f$ with
//! $f = g(s) + C J r^\prime$. After a loss the free ring relaxes, $C s^\prime = -g(s)$, and the
//! contact distance starts to change at the rate $h^\prime = 2\gamma\thinspace G$ with
//! $G = n\cdot r^\prime + n\cdot C^{-1} g(s)$. Write
//! $\lambda = G/(n\cdot C^{-1} n) = 2\mu\gamma + n\cdot r^\prime/(n\cdot C^{-1}n)$: the normal
//! force that the massless ring's own balance $C s^\prime = \lambda n - g$ needs to keep
//! $n\cdot(r^\prime - s^\prime) = 0$. For an isotropic damping ($C = cI$: regimes II and V, and
//! $\nu_2 = 0$) $\lambda = N$. In regimes III and IV, $C = \operatorname{diag}(c_x, c_y)$ with
//! $c_x \ne c_y$ and $\lambda \ne N$: at $N = 0$,
//! $h^\prime = 2\gamma\thinspace n_x f_x (1/c_x - 1/c_y)$, which can be positive, i.e. the freed ring
//! would move straight back into the rotor. Contact therefore ends when **both** forces have
//! fallen to zero: the loss guard is $\max(N, \lambda)$ falling through 0
//! ([`RingContact::loss_force`]). After a loss $\lambda \le 0$, so $h^\prime \le 0$ in every
//! regime: the rotor and the ring part. Where the two agree (II, V) this is the paper's
//! criterion unchanged.
//!
//! **A touch** (the onset guard fires at $(t, r, r^\prime)$). The ring is placed at the minimiser
//! of its energy over the disk $|r - s| \le \gamma$: its centre if $|r| < \gamma$ (beyond the
//! touch tolerance, [`ONSET_TOUCH`]), else $s^*(r)$ on the branches it lies on (an axis within
//! $10^{-10} D_i$ of its preload takes the branch its ring velocity moves into). Contact starts
//! if the loss force there is positive, or if it vanishes because the ring is relaxed and the
//! rotor on the circle ($\mu$ zero to the rounding of the touch) while the rotor moves outward
//! ($n\cdot r^\prime > 0$: then $\mu$, hence the force, grows from zero). Otherwise free flight goes on from the placed ring,
//! *separating*: $h = 0$ and $h^\prime = 2\gamma G \le 0$ there, so the touch cannot fire again
//! at once and time advances. A rotor inside the gap circle leaves the ring at its centre (the
//! minimum is within reach: no force can arise).
//!
//! **A free flight that starts touching** (after a loss, a touch without contact, or a start
//! on the circle) has its onset guard offset by a margin $m$ ([`SnubberRing::onset_margin`]):
//! the guard is $h - m$, which starts below zero by more than the rounding of $h$ and than an
//! event detector's start-of-segment window. A guard on zero at a mode's start that leaves it
//! rising is taken for the zero at the start time ([`ode`, Events](crate::ode#events), rule 3): without
//! the margin a rotor that curves back into the ring (the zero-force slide) or was released a
//! hair inside it passed through the ring in free flight, silently. With it, such a rotor
//! touches the ring again after penetrating at most $m$ (about $10^{-14}\gamma^2$, more late in
//! long runs for a rotor moving in), and the touch decides.
//!
//! **Preload crossings.** The crossing axis switches branch (inner to outer on the side of
//! $s_i$, outer to inner). The other axis takes the branch it is on within the time resolution
//! of the event: at a corner of the regime map, within
//! $10^{-10} D_i$ of its preload, the branch its ring velocity moves into; elsewhere the branch
//! of the position it reaches within $\tau = 64\varepsilon\max(|t|, 1)$, so that a preload
//! it reaches (or passes, through the centre, to the opposite one) sooner than the event is
//! located is crossed now, rather than left to a guard that would start within the
//! start-of-segment window and be dropped. If the ring, located on the new branches, is then
//! on the wrong side of a preload beyond the rounding of its position (the crossing axis
//! itself passed through its inner region within $\tau$), the branches are taken afresh from
//! the minimum-energy position, as at a touch. These matter only where a preload is smaller
//! than the ring moves in $\tau$ ($10^{-8}$ at $t = 10^6$ for a unit ring speed); elsewhere
//! the rule is the paper's. Where a preloaded axis' whole inner region $2D_i$ is narrower than
//! the resolution of the decision, $64\varepsilon(|r| + \gamma) + |s_i^\prime|\tau$ (the
//! rounding of the located position and the ring's motion in $\tau$), with the ring within that
//! resolution of it, at a touch or a preload crossing, no rule can tell the side: the
//! transition fails with [`RingError::PreloadBelowResolution`] rather than run a contact on a
//! branch that may be wrong (the ring hovered at such a preload, its guard crossing back and
//! forth within rounding, until a crossing was lost and the contact ran with the ring up to
//! 0.3 gaps from $s^*(r)$).
//!
//! **No ring damping** ($\nu_2 = 0$): the ring relaxes instantly, so every free flight starts
//! with the ring at its centre.
//!
//! # Where the ring sits in contact
//!
//! Where the ring sits in contact: $s^*(r) = \arg\min E(s)$ subject to $|r - s| = \gamma$.
//!
//! ## One solver for every regime
//! With $d = r - s$, a minimiser satisfies the Lagrange conditions $g(s) = 2\mu d$, $\mu > 0$,
//! $|d| = \gamma$. On fixed branches of the two axes' force laws ([`Branches`]) each axis is
//! linear in $s_i$, so
//!
//! $$d_i(\mu) = \frac{\alpha_i}{\beta_i + \mu},\qquad (\alpha_i, \beta_i) = \begin{cases}
//! (K_i r_i,\ K_i) & \text{inner: } g_i = 2K_i s_i\\\\
//! (\tfrac12 K_i (r_i + \sigma_i D_i),\ \tfrac12 K_i) & \text{outer: } g_i = K_i (s_i + \sigma_i D_i)
//! \end{cases}$$
//!
//! and $\mu$ solves $|d(\mu)| = \gamma$ on $\mu > -\beta_{\min}$ (negative $\mu$ is the smooth
//! extension of a contact regime slightly inside $|r| = \gamma$, which event location needs).
//! The function $\varphi(\mu) = |d(\mu)|^{-1} - 1/\gamma$ is a weighted power mean of exponent
//! $-2$ of the affine functions $\beta_i + \mu$ minus a constant, hence **increasing and
//! concave**, and the root lies in
//! $[\thinspace|\alpha|/\gamma - \beta_{\max},\ |\alpha|/\gamma - \beta_{\min}\thinspace]$.
//!
//! **Next to the pole.** The solver works in $u = \beta_{\min} + \mu > 0$, the distance from the
//! soft axis' pole, and computes $\beta_i + \mu = (\beta_i - \beta_{\min}) + u$ and $d$ from it:
//! where the stiff axis alone cannot reach the ring ($d_t = |\alpha_t|/(\beta_{\max} -
//! \beta_{\min}) < \gamma$ at the pole; on a branch on the far side of the centre, or inside
//! $|r| = \gamma$) the root is at $u \approx |\alpha_s|/\sqrt{\gamma^2 - d_t^2}$, which for
//! $r_s \sim 10^{-17}$ is far below one ulp of $\mu$ but well resolved in $u$. The bracket
//! $|\alpha_s|/\gamma \le u \le |\alpha_s|/\sqrt{\gamma^2 - d_t^2}$ holds it. For $\alpha_s = 0$
//! the root is the pole's limit: $d_s = \pm\sqrt{\gamma^2 - d_t^2}$ with the sign of $\alpha_s$
//! (of $r_s = \pm 0$), the limit of $r_s \to 0^\pm$, so that the answer is continuous in $r$
//! from either side. No float equality picks a formula: equal betas give a bracket of one point,
//! $u = |\alpha|/\gamma$ (regimes II and V of an isotropic ring, paper eq. 22 and Table 3),
//! and the pole's limit replaces $d_s = \alpha_s/u$ only where that is $0/0$. Otherwise a
//! safeguarded Newton iteration on $\varphi$ converges monotonically from the left (a step that
//! leaves the bracket is replaced by bisection, geometric while the bracket spans orders of
//! magnitude; after 8 Newton steps, lost in the rounding of the residual, only bisection).
//!
//! **Stopping rule and tolerance.** The iteration stops after a Newton step
//! $|\delta| \le 10^{-10} u$ (on a fixed branch the error left after such a step is
//! $\lesssim \delta^2/u$, below rounding), or once a Newton step or the bracket moves the ring
//! by less than its rounding, $|\delta|\thinspace|d^\prime(u)| \le 4\varepsilon\gamma$, or
//! when the bracket is at adjacent floats. The tolerance is relative to the soft axis because
//! the ring's position moves by about $|d|\thinspace du/u$ there: relative to $\beta_{\max}$
//! it left errors up to $10^{-20}(\beta_{\max}/\beta_{\min})^2$ in $s$ ($5\times10^{-7}$ for
//! $K_y/K_x = 10^7$, depending on the warm start), and iterating on $\mu$ could not resolve a
//! root next to the pole at all. Warm and cold starts agree to rounding ($1.5\times10^{-15}$
//! relative to $\gamma + |r|$ over $10^6$ random placements with one coordinate of $r$ at or
//! near 0, $K$ from $10^{-3}$ to $10^4$ per axis, any branches and hints). About 1.6
//! iterations on average there, at most 60; it never returns an unconverged iterate: after
//! 100 steps it returns [`RingError::NotConverged`] (the bisection reaches
//! adjacent floats well before, so this cannot happen for finite input; the error keeps the
//! promise checkable).
//!
//! ## Choosing the branches
//! [`SnubberRing::locate`] also finds the branches the minimiser lies on. For a given $\mu$
//! each axis solves the monotone piecewise-linear equation $g_i(s_i) + 2\mu s_i = 2\mu r_i$; the
//! axis passes its preload at the breakpoint $\mu_i^* = K_i D_i/(|r_i| - D_i)$ (if
//! $|r_i| > D_i > 0$; $0$ if $D_i = 0$). $|d(\mu)|$ falls strictly from $|r|$ at $\mu = 0$, so
//! comparing $|d|^2$ with $\gamma^2$ at the (at most two) breakpoints finds the piece, hence the
//! branches, that hold the root; the branch solver then runs inside that piece.
//!
//! The Jacobian $J = \partial s^*/\partial r$ follows from implicit differentiation: with
//! $A = \operatorname{diag}(g_i^\prime + 2\mu)$ and $w = A^{-1}d$,
//! $J = 2\mu A^{-1} + w\thinspace(d - 2\mu w)^{\mathsf T}/(d\cdot w)$ (see `docs/ring.md`). With
//! $A_{ii} = a_i = 2(\beta_i + \mu)$ and $a_i - 2\mu = 2\beta_i$ this is
//! $J = I - \frac{2}{P}\begin{pmatrix}\beta_x d_y^2 & -\beta_y d_x d_y\\\\ -\beta_x d_x d_y &
//! \beta_y d_x^2\end{pmatrix}$ with $P = a_y d_x^2 + a_x d_y^2$: no cancellation of
//! $\mu/(\beta_i + \mu)$ terms, and finite at a pole ($a_i = 0$), which is how it is computed.
//!
//! # Branches: a regime continued past its boundaries
//!
//! The ring's location on a prescribed branch: the smooth extension of one contact regime.
//!
//! [`SnubberRing::locate`](SnubberRing::locate) picks, for each axis, the branch of the
//! piecewise-linear force law the minimiser actually lies on, so $s^*(r)$ is continuous but its
//! derivative jumps at the regime boundaries. An integrator must not step across such a
//! kink: inside one contact regime the driver uses the *same* branch formulas extended beyond
//! the boundary, which are analytic, and an event moves it to the neighbouring branch when
//! $|s_i| = D_i$ is crossed.
//!
//! On a fixed branch each axis of the Lagrange condition $g_i(s) = 2\mu(r_i - s_i)$ is linear,
//! and [`SnubberRing::locate_on`](SnubberRing::locate_on) solves it (see [below](#where-the-ring-sits-in-contact)).
//!
//! # Regimes
//!
//! Contact regimes I..V and the analytic region boundaries (paper section 4, eqs. 23-27).
//!
//! # Free relaxation
//!
//! Free relaxation of the massless ring out of contact.
//!
//! Out of contact the ring's force is zero, `g(s) + C(s) s' = 0`, i.e. per axis with the time
//! constant `T = 2 nu2/K` (the same inside and beyond the preload):
//!
//! * inside (`|s| <= D`): `2 K s + 4 nu2 s' = 0`, so `s' = -s/T` and `s(t) = s0 e^{-t/T}`;
//! * beyond (`|s| > D`, or `D = 0`): `K (s + sign(s) D) + 2 nu2 s' = 0`, so
//!   `s' = -(s + sign(s) D)/T` and `s(t) = sign(s0) [ (|s0| + D) e^{-t/T} - D ]` until `|s| = D`
//!   at `t1 = T ln((|s0| + D)/(2 D))`, then `s(t) = sign(s0) D e^{-(t - t1)/T}`.
//!
//! The solution never changes sign, `|s(t)|` is non-increasing and so is `|s'(t)|`: it decays
//! exponentially on each piece and drops by the factor 2 at `t1` (from `2D/T` to `D/T`).
//! With `nu2 = 0` the relaxation is instantaneous: `s(t) = 0` for every `t > 0`.
//!
//! # Derivatives of the element
//!
//! Derivatives of the ring element: what the variational equations of a rotor on the ring need.
//!
//! Linearising a hybrid trajectory (Floquet multipliers, Lyapunov exponents, Newton on a
//! stroboscopic map) needs, besides the vector field and the guards, their derivatives with
//! respect to the rotor's kinematics $(r, v)$, $v = r^\prime$, at the ring's station. This module
//! gives them for every mode of the ring, analytically:
//!
//! * **in contact** on fixed branches, the second derivatives of the located ring
//!   ([`SnubberRing::contact_hessian`]: $\partial\mu/\partial r$ and $\partial J/\partial r$) and
//!   the Jacobian of the contact force $F(r, v) = g(s^*(r)) + C J(r) v$
//!   ([`SnubberRing::force_jacobian`]);
//! * **the guards' gradients** ([`SnubberRing::guard_gradient`]): onset, loss (the loss force
//!   $\max(N, \lambda)$), the gap and the preload crossings;
//! * **out of contact**, the sensitivity of the relaxing ring to its start
//!   ([`Relaxation::sensitivity`], [`Relaxation::start_time_sensitivity`]).
//!
//! ## The located ring's second derivatives
//!
//! On fixed branches the Lagrange system $g(s) = 2\mu d$, $|d| = \gamma$, $d = r - s$ is smooth.
//! With $A = \operatorname{diag}(g_i^\prime + 2\mu)$ (constant $g_i^\prime$ on a branch: $2K_i$
//! inner, $K_i$ outer) and the bordered matrix
//!
//! $$\mathcal M = \begin{pmatrix} A & -2d\\\\ d^{\mathsf T} & 0\end{pmatrix},$$
//!
//! the first derivatives along $e$ solve $\mathcal M\thinspace (Je;\ \mu_e) = (2\mu e;\ d\cdot e)$. Differentiating
//! once more along $e^\prime$ ($\partial A = 2\mu_{e^\prime} I$, $\partial d = e^\prime - Je^\prime$):
//!
//! $$\mathcal M\begin{pmatrix} H(e, e^\prime)\\\\ \mu_{ee^\prime}\end{pmatrix} =
//! \begin{pmatrix} 2\mu_{e^\prime}(e - Je) + 2\mu_e(e^\prime - Je^\prime)\\\\
//! (e^\prime - Je^\prime)\cdot(e - Je)\end{pmatrix},$$
//!
//! $H(e, e^\prime) = \partial^2 s^*/\partial r^2[e, e^\prime]$, symmetric. $\mathcal M$ is
//! solved by elimination through the diagonal $A$: with $w = A^{-1} d$, the multiplier part is
//! $(b_2 - d\cdot A^{-1}b_1)/(2\thinspace d\cdot w)$ and the position part
//! $A^{-1}(b_1 + 2d\thinspace\mu)$.
//!
//! ## The contact force
//!
//! $$\frac{\partial F}{\partial v} = CJ,\qquad
//! \frac{\partial F}{\partial r}\thinspace e_k = G^\prime J e_k + C\thinspace \frac{\partial J}{\partial r_k}\thinspace v,$$
//!
//! $G^\prime = \operatorname{diag}(g_i^\prime)$, $C = \operatorname{diag}(c_i)$ on the branches.
//!
//! ## The guards
//!
//! With $n = d/\gamma$, $\partial n/\partial r = (I - J)/\gamma$:
//!
//! * onset $h = |r - s(t)|^2 - \gamma^2$: $\nabla_r h = 2q$, $\partial h/\partial s = -2q$
//!   ($q = r - s$), $\partial_t h = -2q\cdot s^\prime(t)$ at a fixed relaxation;
//! * loss, normal force $N = n\cdot F$: $\nabla_r N = \big(\tfrac{I - J}{\gamma}\big)^{\mathsf T}F +
//!   \big(\tfrac{\partial F}{\partial r}\big)^{\mathsf T} n$, $\nabla_v N = (CJ)^{\mathsf T}n$;
//!   where the separation force $\lambda$ is the larger (regimes III/IV,
//!   [`RingContact::loss_force`]), $\lambda = a/b$ with $a = c_xc_y\thinspace n\cdot v +
//!   c_y n_x g_x + c_x n_y g_y$, $b = c_y n_x^2 + c_x n_y^2$, and
//!   $\nabla\lambda = (\nabla a - \lambda\nabla b)/b$ ($\partial g/\partial r = G^\prime J$);
//! * gap $|r|^2 - \gamma^2$: $\nabla_r = 2r$;
//! * preload of axis $i$, $\pm s_i - D_i$ on the mode's branch: $\nabla_r = \pm J^{\mathsf T}e_i$
//!   (the sign of $s_i$ on the inner branch, $\sigma_i$ on the outer one).
//!
//! ## The relaxing ring
//!
//! Out of contact, per axis, $s(t) = $ [`SnubberRing::relax`]$(s_0, t - t_0)$ and
//!
//! $$\frac{\partial s(t)}{\partial s_0} = e^{-(t - t_0)/T}\times\begin{cases}\tfrac12 &
//! \text{after the crossing of the preload of a ring started beyond it } (|s_0| > D > 0)\\\\
//! 1 & \text{otherwise,}\end{cases}\qquad \frac{\partial s(t)}{\partial t_0} = -s^\prime(t).$$
//!
//! The factor $\tfrac12$ is the saltation of the scalar relaxation at $|s| = D$: its velocity
//! drops from $2D/T$ to $D/T$ there. A ring started exactly on its preload takes the inner
//! (one-sided) value 1. With $\nu_2 = 0$ both are 0 for $t > t_0$ (instant relaxation). The
//! velocity is transported by the same factor, $s^\prime(t) = \rho(t)\thinspace s^\prime(t_0^+)$.

use nalgebra::Vector2;
use thiserror::Error;

mod branch;
mod element;
pub mod friction;
mod locate;
pub mod onset;
mod regime;
mod relax;
mod sensitivity;
pub(crate) mod station;

pub use branch::{Branch, Branches};
pub(crate) use element::{loss_force_rate, preload_sign, LossMotion};
pub use element::{
    AccelOfForce, Axis, Kinematics, RingCache, RingGuard, RingMode, RingState, RingTransition,
    ONSET_TOUCH,
};
pub use friction::{ContactStart, FrictionRing, RollContact, Slip, SlipContact};
pub use locate::{regime_ii_position, regime_v_position, RingContact};
pub use regime::{boundaries, Regime};
pub use relax::Relaxation;
pub use sensitivity::{ContactHessian, ForceJacobian, GuardGradient};

/// Errors of the snubber-ring element: every variant names the offending field and its value.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum RingError {
    /// A parameter or input is NaN or infinite.
    #[error("{field} must be finite, got {value}")]
    NonFinite {
        /// Name of the field or argument (e.g. `"x.stiffness"`, `"r.y"`).
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The offending value.
        value: f64,
    },
    /// A parameter that must be `>= 0` is negative.
    #[error("{field} must be >= 0, got {value}")]
    Negative {
        /// Name of the field.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The offending value.
        value: f64,
    },
    /// A parameter that must be `> 0` is zero or negative.
    #[error("{field} must be > 0, got {value}")]
    NotPositive {
        /// Name of the field.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The offending value.
        value: f64,
    },
    /// A routine that assumes equal stiffness on both axes got an anisotropic ring.
    #[error("x.stiffness = {x} and y.stiffness = {y} differ; an isotropic stiffness is required")]
    AnisotropicStiffness {
        /// `K_x`.
        x: f64,
        /// `K_y`.
        y: f64,
    },
    /// The rotor is not in contact: `|r| <= gap`, so there is no contact position.
    #[error("rotor at distance |r| = {distance} is inside the gap {gap}: no contact")]
    InsideGap {
        /// `|r|`, the distance of the rotor centre from the ring's rest position.
        distance: f64,
        /// The gap (constraint radius).
        gap: f64,
    },
    /// The branch formulas of a contact mode have no solution at the rotor position
    /// `(x, y)` (both axes exactly at their branch centre $r_i = -\sigma_i D_i$, or a
    /// non-finite position): the contact mode cannot continue there.
    #[error("no ring placement on the contact branches at r = ({x}, {y})")]
    NoPlacement {
        /// `r.x`.
        x: f64,
        /// `r.y`.
        y: f64,
    },
    /// The multiplier solver did not converge (not expected for finite input: bisection halves
    /// the bracket every step).
    #[error("ring location did not converge in {iterations} iterations (bracket width {bracket})")]
    NotConverged {
        /// Iterations made.
        iterations: u32,
        /// Width of the remaining bracket of the multiplier.
        bracket: f64,
    },
    /// The rotor is beyond the ring: `|r - s| > gap` (more than the tolerance), an impossible
    /// state.
    #[error("rotor beyond the ring: |r - s| = {distance} > gap {gap}; place the ring with SnubberRing::consistent_position")]
    BeyondRing {
        /// `|r - s|`.
        distance: f64,
        /// The gap.
        gap: f64,
    },
    /// At a contact transition at time `t`, a preloaded axis' whole inner region ($2D_i$
    /// wide) is narrower than the resolution at which the ring's branch is decided there (the
    /// rounding of the located position plus the distance the ring moves in the time
    /// resolution of an event), with the ring within that resolution of it: which side of the
    /// preload the ring is on cannot be decided, and a contact run on the wrong branch would
    /// be a silent wrong answer (docs/reliability.md, "Preloads below the resolution of the
    /// run"). Set such a preload to 0, or make it larger than the resolution (shorter runs,
    /// a rest position nearer the ring, slower motion).
    #[error("{field} = {preload:e} is below the resolution {resolution:e} of the ring's position at t = {t}: the side of the preload cannot be decided; set it to 0 or above the resolution")]
    PreloadBelowResolution {
        /// `"x.preload"` or `"y.preload"`.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The preload $D_i$.
        preload: f64,
        /// The resolution: $64\varepsilon(|r| + \gamma) + |s_i^\prime|\tau$, with
        /// $\tau = 64\varepsilon\max(|t|, 1)$.
        resolution: f64,
        /// Time of the transition.
        t: f64,
    },
    /// A friction coefficient at or above the bound below which every slipping location of
    /// the ring is unique ([`FrictionRing::limit`]): beyond it the ring may have several
    /// locations for one rotor position, and none would be picked silently.
    #[error("friction = {friction} is at or above {limit}, the bound below which the slipping ring's location is unique for this ring's stiffnesses")]
    FrictionBeyondUniqueness {
        /// The friction coefficient $\mu_f$.
        friction: f64,
        /// [`FrictionRing::limit`] of the ring.
        limit: f64,
    },
    /// At a contact start both slip senses are consistent (slipping forward has $v_+ > 0$ and
    /// slipping backward $v_- < 0$): the start cannot be decided. Not expected for a rotor
    /// moving into the ring (then $v_+ < v_-$).
    #[error("contact start is ambiguous: forward slip velocity {forward} > 0 and backward {backward} < 0")]
    SlipAmbiguous {
        /// $v_+$, the slip velocity of the forward-slipping location.
        forward: f64,
        /// $v_-$, that of the backward-slipping location.
        backward: f64,
    },
    /// In contact, the ring is not at its minimum-energy position $s^*(r)$.
    #[error("rotor in contact but the ring is {offset} away from its minimum-energy position; place it with SnubberRing::consistent_position")]
    RingOffMinimum {
        /// `|s - s*(r)|`.
        offset: f64,
    },
}

/// Checks that `value` is finite.
pub(crate) fn check_finite(field: &'static str, value: f64) -> Result<f64, RingError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(RingError::NonFinite { field, value })
    }
}

/// Checks that `value` is finite and `>= 0`.
pub(crate) fn check_non_negative(field: &'static str, value: f64) -> Result<f64, RingError> {
    check_finite(field, value)?;
    if value >= 0.0 {
        Ok(value)
    } else {
        Err(RingError::Negative { field, value })
    }
}

/// Checks that `value` is finite and `> 0`.
pub(crate) fn check_positive(field: &'static str, value: f64) -> Result<f64, RingError> {
    check_finite(field, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(RingError::NotPositive { field, value })
    }
}

/// One axis of the ring: the two opposing spring-damper units along `x` or `y`.
///
/// * `stiffness` `K > 0`: stiffness of one unit (`k_s / k_r`). `K = 0` is rejected: with no
///   stiffness on an axis the ring can slide freely along it and the contact position is not
///   unique (any point of a chord of the circle has the same energy).
/// * `preload` `D >= 0`: the preload displacement (`Delta / gamma`); `D = 0` means no preload.
///
/// ```
/// use jeffcott::ring::RingAxis;
///
/// // Both branches of the energy give K D^2 at the preload |s| = D; the force's slope
/// // halves there (2K inside, K beyond: one unit lifts off).
/// let axis = RingAxis::new(2.0, 0.25);
/// let kd2 = 2.0 * 0.25 * 0.25;
/// assert!((axis.energy(0.25) - kd2).abs() < 1e-15);
/// assert!((axis.energy(0.25 + 1e-9) - kd2).abs() < 1e-8);
/// assert!(axis.is_inside(0.25) && !axis.is_inside(0.2500001));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingAxis {
    /// Unit stiffness `K > 0` of this axis.
    pub stiffness: f64,
    /// Preload `D >= 0` of this axis.
    pub preload: f64,
}

impl RingAxis {
    /// An axis with stiffness `K` and preload `D` (validated when the ring is built).
    pub fn new(stiffness: f64, preload: f64) -> Self {
        Self { stiffness, preload }
    }

    /// `true` when `s` is inside the preload on this axis: `D > 0` and `|s| <= D`.
    #[inline]
    pub fn is_inside(&self, s: f64) -> bool {
        self.preload > 0.0 && s.abs() <= self.preload
    }

    /// Elastic energy of the axis,
    /// `e(s) = K s^2` inside the preload, `(K/2)((|s| + D)^2 - 2 D^2)` beyond it.
    #[inline]
    pub fn energy(&self, s: f64) -> f64 {
        let (k, d) = (self.stiffness, self.preload);
        if self.is_inside(s) {
            k * s * s
        } else {
            let a = s.abs() + d;
            0.5 * k * (a * a - 2.0 * d * d)
        }
    }

    /// Elastic force `g(s) = e'(s)`: `2 K s` inside the preload, `sign(s) K (|s| + D)` beyond it.
    #[inline]
    pub fn elastic_force(&self, s: f64) -> f64 {
        let (k, d) = (self.stiffness, self.preload);
        if self.is_inside(s) {
            2.0 * k * s
        } else if s == 0.0 {
            0.0
        } else {
            k * (s + d.copysign(s))
        }
    }

    /// Elastic stiffness `g'(s)`: `2 K` inside the preload, `K` beyond it (one-sided at `|s| = D`,
    /// where the inside value is returned).
    #[inline]
    pub fn elastic_slope(&self, s: f64) -> f64 {
        if self.is_inside(s) {
            2.0 * self.stiffness
        } else {
            self.stiffness
        }
    }

    /// Damping coefficient: `4 nu2` inside the preload, `2 nu2` beyond it.
    #[inline]
    pub fn damping_coefficient(&self, s: f64, damping: f64) -> f64 {
        if self.is_inside(s) {
            4.0 * damping
        } else {
            2.0 * damping
        }
    }
}

/// The preloaded snubber ring: two [`RingAxis`], the damping ratio `nu2` and the gap.
///
/// Build it with [`SnubberRing::new`] or [`SnubberRing::isotropic`], which validate the parameters.
/// The fields are public for reading; every fallible method re-validates, so a ring edited into
/// an invalid state yields a [`RingError`] (never a panic).
///
/// ```
/// use jeffcott::nalgebra::Vector2;
/// use jeffcott::ring::{regime_ii_position, Regime, SnubberRing};
///
/// // The paper's isotropic ring: K = 1.5, preload D = 0.1, nu2 = 0.05, gap 1.
/// let ring = SnubberRing::isotropic(1.5, 0.1, 0.05)?;
/// // A rotor 0.05 into the ring along x: the ring is pushed 0.05, inside its preload, so
/// // regime II, where the ring sits on the ray through r at |r| - 1 (paper eq. 22).
/// let r = Vector2::new(1.05, 0.0);
/// let contact = ring.locate(&r)?;
/// assert_eq!(contact.regime(), Regime::II);
/// assert!((contact.s - regime_ii_position(&r, 1.0)?).norm() < 1e-14);
/// assert!(((r - contact.s).norm() - 1.0).abs() < 1e-14); // on the contact circle
///
/// // Out of contact, inside the preload, the ring relaxes as s0 exp(-t/T), T = 2 nu2/K
/// // (both units act: 2K s + 4 nu2 s' = 0).
/// let (s0, t) = (Vector2::new(0.05, -0.02), 0.3);
/// let tau = 2.0 * 0.05 / 1.5;
/// assert!((ring.relax(&s0, t) - s0 * (-t / tau).exp()).norm() < 1e-15);
/// # Ok::<(), jeffcott::ring::RingError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnubberRing {
    /// The horizontal axis.
    pub x: RingAxis,
    /// The vertical axis.
    pub y: RingAxis,
    /// Damping ratio `nu2 >= 0` of one unit (`c_s / (2 sqrt(k_r M))`); a unit's damping force is
    /// `2 nu2 s'`.
    pub damping: f64,
    /// Constraint radius (radial clearance) `gap > 0`; 1 in the paper's scaling.
    pub gap: f64,
}

impl SnubberRing {
    /// A ring with axes `x`, `y`, damping ratio `nu2 = damping` and constraint radius `gap`.
    ///
    /// # Errors
    /// [`RingError::NonFinite`] for NaN/inf, [`RingError::NotPositive`] for `K <= 0` or
    /// `gap <= 0`, [`RingError::Negative`] for `D < 0` or `nu2 < 0`; the field is named as
    /// `"x.stiffness"`, `"y.preload"`, `"damping"`, `"gap"`.
    pub fn new(x: RingAxis, y: RingAxis, damping: f64, gap: f64) -> Result<Self, RingError> {
        let ring = Self { x, y, damping, gap };
        ring.validate()?;
        Ok(ring)
    }

    /// An isotropic ring (`K_x = K_y = stiffness`, `D_x = D_y = preload`) with gap 1.
    ///
    /// # Errors
    /// As [`SnubberRing::new`].
    pub fn isotropic(stiffness: f64, preload: f64, damping: f64) -> Result<Self, RingError> {
        let axis = RingAxis::new(stiffness, preload);
        Self::new(axis, axis, damping, 1.0)
    }

    /// The ring from its physical parameters, in any consistent units (SI: N/m, N s/m, m):
    /// unit stiffness `unit_stiffness` $k_s$, unit damping `unit_damping` $c_s$ (a unit's
    /// damping force is $c_s s^\prime$), preloads `preload` $[\Delta_x, \Delta_y]$ and radial
    /// gap `gap` $\gamma$. The fields are then $K = k_s$, $D = \Delta$, $\nu_2 = c_s/2$ and
    /// gap $\gamma$, and per axis the ring's force is $f = 2k_s s + 2c_s s^\prime$ inside the
    /// preload and $\operatorname{sign}(s)\thinspace k_s(|s| + \Delta) + c_s s^\prime$ beyond
    /// it, in the units of $k_s$ times those of $\gamma$ (N for SI). The element's tolerances
    /// are relative to the gap, so it runs in metres as it does in gaps. The paper's
    /// non-dimensional ring is this ring with lengths in $\gamma$, forces in $k_r\gamma$ and
    /// time in $1/\omega_n$: `from_units(k_s / k_r, c_s / sqrt(k_r m), [Δx / γ, Δy / γ], 1)`
    /// (see [`crate::rotor::LinearRotor`] for the rule for any rotor).
    ///
    /// ```
    /// use jeffcott::ring::{RingAxis, SnubberRing};
    /// // ROSS's rub example's ring: k_s = 1.1e6 N/m, c_s = 0.01 N s/m, gap 79.5 µm.
    /// let ring = SnubberRing::from_units(1.1e6, 0.01, [0.0, 0.0], 7.95e-5)?;
    /// assert_eq!(ring, SnubberRing::new(RingAxis::new(1.1e6, 0.0), RingAxis::new(1.1e6, 0.0), 0.005, 7.95e-5)?);
    /// # Ok::<(), jeffcott::ring::RingError>(())
    /// ```
    ///
    /// # Errors
    /// As [`SnubberRing::new`], with the damping named `"unit_damping"` and its value $c_s$.
    pub fn from_units(
        unit_stiffness: f64,
        unit_damping: f64,
        preload: [f64; 2],
        gap: f64,
    ) -> Result<Self, RingError> {
        check_non_negative("unit_damping", unit_damping)?;
        Self::new(
            RingAxis::new(unit_stiffness, preload[0]),
            RingAxis::new(unit_stiffness, preload[1]),
            0.5 * unit_damping,
            gap,
        )
    }

    /// Checks all parameters (see [`SnubberRing::new`]).
    ///
    /// # Errors
    /// The first invalid field, as a typed [`RingError`].
    pub fn validate(&self) -> Result<(), RingError> {
        check_positive("x.stiffness", self.x.stiffness)?;
        check_non_negative("x.preload", self.x.preload)?;
        check_positive("y.stiffness", self.y.stiffness)?;
        check_non_negative("y.preload", self.y.preload)?;
        check_non_negative("damping", self.damping)?;
        check_positive("gap", self.gap)?;
        Ok(())
    }

    /// `true` when both axes have the same stiffness and the same preload.
    pub fn is_isotropic(&self) -> bool {
        self.x == self.y
    }

    /// Bounds of the stiffness and of the damping coefficient with which the ring in contact
    /// acts on the rotor's station: $2\max(K_x, K_y)$ (both units of the stiffer axis; the ring
    /// is never stiffer than its stiffest branch) and $4\nu_2$ (both dampers of an inner
    /// branch). For [`crate::hybrid::RotorModel::max_rate`]: a unit-mass station with the
    /// ring adds at most $\sqrt{k}$ and $c$ to the rates of its motion.
    pub fn contact_bounds(&self) -> (f64, f64) {
        (
            2.0 * self.x.stiffness.max(self.y.stiffness),
            4.0 * self.damping,
        )
    }

    /// `true` when at least one axis is preloaded (`D_x > 0` or `D_y > 0`).
    pub fn has_preload(&self) -> bool {
        self.x.preload > 0.0 || self.y.preload > 0.0
    }

    /// Elastic energy `E(s) = e_x(s_x) + e_y(s_y)` (see [`RingAxis::energy`]).
    pub fn energy(&self, s: &Vector2<f64>) -> f64 {
        self.x.energy(s.x) + self.y.energy(s.y)
    }

    /// Elastic force `g(s) = grad E(s) = (g_x(s_x), g_y(s_y))` (see [`RingAxis::elastic_force`]).
    pub fn elastic_force(&self, s: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(self.x.elastic_force(s.x), self.y.elastic_force(s.y))
    }

    /// Elastic force on given branches, their force law's affine extension wherever `s` lies:
    /// $g_i = 2K_is_i$ on the inner branch, $K_i(s_i + \sigma D_i)$ on the outer branch of side
    /// $\sigma$. Equals [`SnubberRing::elastic_force`] where `branches` are `s`'s own.
    pub fn elastic_force_on(&self, branches: Branches, s: &Vector2<f64>) -> Vector2<f64> {
        let on = |axis: &RingAxis, branch: Branch, s: f64| match branch {
            Branch::Inner => 2.0 * axis.stiffness * s,
            Branch::Outer(side) => axis.stiffness * (s + f64::from(side) * axis.preload),
        };
        Vector2::new(on(&self.x, branches.x, s.x), on(&self.y, branches.y, s.y))
    }

    /// Diagonal of the elastic stiffness matrix on given branches: `2K` inner, `K` outer.
    pub fn branch_slopes(&self, branches: Branches) -> Vector2<f64> {
        sensitivity::branch_slopes(self, branches)
    }

    /// Diagonal of the elastic stiffness matrix `g'(s)`: `2K` inside, `K` beyond the preload.
    pub fn elastic_slopes(&self, s: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(self.x.elastic_slope(s.x), self.y.elastic_slope(s.y))
    }

    /// Diagonal of the damping matrix `C(s)`: `4 nu2` inside, `2 nu2` beyond the preload.
    pub fn damping_coefficients(&self, s: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(
            self.x.damping_coefficient(s.x, self.damping),
            self.y.damping_coefficient(s.y, self.damping),
        )
    }

    /// Total force of the ring `f = g(s) + C(s) s'` at position `s` and velocity `s_dot`.
    pub fn force(&self, s: &Vector2<f64>, s_dot: &Vector2<f64>) -> Vector2<f64> {
        let c = self.damping_coefficients(s);
        self.elastic_force(s) + c.component_mul(s_dot)
    }

    /// The contact regime (II..V) of a ring at `s`, from the preload predicates of its axes:
    /// II both inside, III `x` beyond, IV `y` beyond, V both beyond. (An axis with zero preload
    /// is always beyond.)
    ///
    /// ```
    /// use jeffcott::nalgebra::Vector2;
    /// use jeffcott::ring::{Regime, RingAxis, SnubberRing};
    ///
    /// let ring = SnubberRing::new(RingAxis::new(1.0, 0.1), RingAxis::new(1.0, 0.2), 0.0, 1.0)?;
    /// assert_eq!(ring.regime_of_ring(&Vector2::new(0.05, 0.1)), Regime::II);
    /// assert_eq!(ring.regime_of_ring(&Vector2::new(0.15, 0.1)), Regime::III);
    /// assert_eq!(ring.regime_of_ring(&Vector2::new(0.05, -0.3)), Regime::IV);
    /// assert_eq!(ring.regime_of_ring(&Vector2::new(-0.15, 0.3)), Regime::V);
    /// # Ok::<(), jeffcott::ring::RingError>(())
    /// ```
    pub fn regime_of_ring(&self, s: &Vector2<f64>) -> Regime {
        Regime::from_beyond(!self.x.is_inside(s.x), !self.y.is_inside(s.y))
    }

    /// Relaxation time constants `(T_x, T_y)`, `T_i = 2 nu2 / K_i`, of the free ring.
    pub fn relaxation_time(&self) -> Vector2<f64> {
        Vector2::new(
            2.0 * self.damping / self.x.stiffness,
            2.0 * self.damping / self.y.stiffness,
        )
    }
}
