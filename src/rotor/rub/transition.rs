//! The transitions between the contact modes of a [`RubbingRotor`](super::RubbingRotor): the
//! release, the slip's stop, the slide off the friction cone's edge and the preload crossing.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, OVector};

use super::{transition_error, RubCache, RubMode, RubbingRotor, FRICTION};
use crate::hybrid::ModelError;
use crate::ring::{Axis, Branch, Branches, Slip};
use crate::rotor::SmoothRotor;

impl<R: SmoothRotor> RubbingRotor<R>
where
    DefaultAllocator: Allocator<R::Dim>,
{
    /// A contact that ends (loss, or the rotor back at the gap circle): the ring relaxes from
    /// where it is.
    pub(super) fn release(
        &self,
        mode: RubMode,
        t: f64,
        y: &mut OVector<f64, R::Dim>,
    ) -> Result<RubMode, ModelError> {
        let cache = RubCache::default();
        let c = self
            .contact(mode, t, y, &cache)
            .map_err(|e| transition_error(t, e))?;
        let next = self.rub.ring().release(t, &self.station(y), c.s);
        self.write_slots(y, next.s);
        Ok(RubMode::Ring(next.mode))
    }

    /// The slip velocity reached zero: the contact rolls, unless the slip velocity turns back
    /// to its sense (a touch: the slip goes on). The slip velocity's rate decides, not the
    /// stick margin's: where $v = 0$ the contact direction turns at $-\eta a/\gamma$ slipping
    /// and rolling alike, so the margin's rate in rolling is zero there (to rounding) and the
    /// margin grows at second order, $\tfrac12\partial_\theta(\mu_f N - |F_t|)\thinspace
    /// \lvert v^\prime\rvert(t - t_0)^2/\gamma$, as the slipping location falls behind.
    pub(super) fn stop(
        &self,
        sense: Slip,
        branches: Branches,
        t: f64,
        y: &OVector<f64, R::Dim>,
    ) -> Result<RubMode, ModelError> {
        let cache = RubCache::default();
        let k = self.station(y);
        let slip = RubMode::Slip { sense, branches };
        let rate = self
            .friction_rate(slip, t, y, &cache)
            .map_err(|e| transition_error(t, e))?;
        if rate > 0.0 {
            return Ok(slip);
        }
        let c = self
            .rub
            .locate_slipping_on(&k.r, sense, branches, f64::NAN)
            .map_err(|e| transition_error(t, e))?;
        Ok(RubMode::Roll {
            angle: c.normal.y.atan2(c.normal.x),
            shaft: self.spin(t, y).angle,
            branches,
        })
    }

    /// The friction cone's edge while rolling: the contact slips in the sense of $F_t$.
    pub(super) fn slide(
        &self,
        mode: RubMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
    ) -> Result<RubMode, ModelError> {
        let cache = RubCache::default();
        let RubMode::Roll {
            angle,
            shaft,
            branches,
        } = mode
        else {
            return Ok(mode);
        };
        let k = self.station(y);
        let theta = angle - self.radius / self.rub.ring().gap * (self.spin(t, y).angle - shaft);
        let c = self
            .rub
            .rolling_on(&k.r, theta, branches)
            .map_err(|e| transition_error(t, e))?;
        let sense = c.release().unwrap_or(Slip::Forward);
        let next = RubMode::Slip { sense, branches };
        // The ring's velocity jumps (it is massless), and with it the slip velocity: slipping
        // in the sense of F_t holds if that slip velocity has this sense, or is zero and gains it.
        let c = self
            .contact(next, t, y, &cache)
            .map_err(|e| transition_error(t, e))?;
        let rate = self
            .friction_rate(next, t, y, &cache)
            .map_err(|e| transition_error(t, e))?;
        if c.guards[FRICTION] <= 0.0 && rate < 0.0 {
            return Err(ModelError::Transition {
                t,
                reason: "rolling ends at the friction cone's edge but slipping in the sense of the friction force would reverse at once".into(),
            });
        }
        Ok(next)
    }

    /// A preload crossing (guard `i`): the fired axis changes branch, the other takes the
    /// branch it is on within the time resolution (a corner of the regime map), as in the
    /// frictionless contact; the ring's position is continuous through it. Its velocity is
    /// not (the slopes and dampers change), and with it the slip velocity: where that turns
    /// against the slip, the contact rolls (the friction force cannot jump to the other side).
    pub(super) fn cross(
        &self,
        mode: RubMode,
        i: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
    ) -> Result<RubMode, ModelError> {
        let c = self
            .contact(mode, t, y, &RubCache::default())
            .map_err(|e| transition_error(t, e))?;
        let Some((axis, _)) = self.preload_guard(c.branches, i) else {
            return Ok(mode);
        };
        let ring = self.rub.ring();
        // A preload narrower than the time resolution cannot be resolved (as without friction).
        ring.check_preload_resolution(t, &self.station(y).r, &c.s, &c.s_dot)
            .map_err(|e| transition_error(t, e))?;
        let mut next = c.branches;
        let fired = axis.index();
        let flipped = match branch_on(&next, fired) {
            Branch::Inner => Branch::Outer(if c.s[fired] >= 0.0 { 1 } else { -1 }),
            Branch::Outer(_) => Branch::Inner,
        };
        set_branch(&mut next, fired, flipped);
        let other = [Axis::Y, Axis::X][fired];
        let j = other.index();
        if let Some(b) = ring.branch_at(other, t, c.s[j], c.s_dot[j]) {
            set_branch(&mut next, j, b);
        }
        match mode {
            RubMode::Slip { sense, .. } => {
                let slip = RubMode::Slip {
                    sense,
                    branches: next,
                };
                let cache = RubCache::default();
                let v = self
                    .contact(slip, t, y, &cache)
                    .map_err(|e| transition_error(t, e))?
                    .guards[FRICTION];
                if v >= 0.0 {
                    return Ok(slip);
                }
                let n = self.station(y).r - c.s;
                let roll = RubMode::Roll {
                    angle: n.y.atan2(n.x),
                    shaft: self.spin(t, y).angle,
                    branches: next,
                };
                let rate = self
                    .friction_rate(roll, t, y, &cache)
                    .map_err(|e| transition_error(t, e))?;
                if rate < 0.0 {
                    return Err(ModelError::Transition {
                        t,
                        reason: "at a preload crossing the slip velocity turns against the slip and rolling would leave the friction cone at once".into(),
                    });
                }
                Ok(roll)
            }
            RubMode::Roll { angle, shaft, .. } => {
                // The same roll, referred to this event (the linearisation reads the
                // contact's direction at the mode's start there).
                let spin = self.spin(t, y).angle;
                Ok(RubMode::Roll {
                    angle: angle - self.radius / ring.gap * (spin - shaft),
                    shaft: spin,
                    branches: next,
                })
            }
            RubMode::Ring(_) => Ok(mode),
        }
    }
}

fn branch_on(b: &Branches, i: usize) -> Branch {
    if i == 0 {
        b.x
    } else {
        b.y
    }
}

fn set_branch(b: &mut Branches, i: usize, branch: Branch) {
    if i == 0 {
        b.x = branch;
    } else {
        b.y = branch;
    }
}
