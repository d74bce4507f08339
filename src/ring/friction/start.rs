//! How a contact with friction starts.

use nalgebra::Vector2;

use super::slip::violation;
use super::{FrictionRing, RollContact, Slip, SlipContact};
use crate::ring::element::CORNER_TOL;
use crate::ring::{check_finite, Branches, RingError};

/// Checks the rotor's velocity and the surface speed.
fn check_motion(r_dot: &Vector2<f64>, surface_speed: f64) -> Result<(), RingError> {
    check_finite("r_dot.x", r_dot.x)?;
    check_finite("r_dot.y", r_dot.y)?;
    check_finite("surface_speed", surface_speed)?;
    Ok(())
}

/// The mode a contact with friction starts in ([`FrictionRing::start`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactStart {
    /// Slipping, in the sense of the record's [`SlipContact::friction`].
    Slipping(SlipContact),
    /// Rolling, at the frictionless location's contact direction (where $F_t = 0$).
    Rolling(RollContact),
}

impl FrictionRing {
    /// The mode a contact starts in with the rotor at `r` (`|r| > gap`), moving at `r_dot`,
    /// for the shaft's surface speed `surface_speed` $= \eta a$ (MODEL.md's onset rule): with
    /// $v_\pm$ the slip velocities of the locations slipping forward and backward, it slips
    /// forward if $v_+ > 0$, backward if $v_- < 0$, and rolls otherwise, at the frictionless
    /// location's direction (inside the friction cone: $F_t = 0$ there).
    ///
    /// # Errors
    /// Those of [`FrictionRing::locate_slipping`]; [`RingError::SlipAmbiguous`] when both
    /// $v_+ > 0$ and $v_- < 0$; [`RingError::NonFinite`] (`"r_dot.x"`, `"r_dot.y"`,
    /// `"surface_speed"`).
    pub fn start(
        &self,
        r: &Vector2<f64>,
        r_dot: &Vector2<f64>,
        surface_speed: f64,
    ) -> Result<ContactStart, RingError> {
        check_motion(r_dot, surface_speed)?;
        let forward = self.locate_slipping(r, Slip::Forward)?;
        let backward = self.locate_slipping(r, Slip::Backward)?;
        let plain = self.ring.locate(r)?;
        self.decide(r, (forward, backward), plain.normal, r_dot, surface_speed)
    }

    /// As [`FrictionRing::start`] on given branches (their smooth extension): for a touch of
    /// the gap circle within its rounding, where [`FrictionRing::start`] has no location
    /// (`|r| <= gap`), with the branches the frictionless touch starts on. Beyond the gap
    /// circle, a slipping start that does not lie on `branches` (beyond the resolution at which
    /// the frictionless contact decides a branch on a preload) is [`FrictionRing::start`]'s:
    /// e.g. a touch of a ring that has not relaxed, whose frictionless location lies on other
    /// branches than the slipping one.
    ///
    /// # Errors
    /// As [`FrictionRing::start`], with [`RingError::NoPlacement`] where the branches have no
    /// location at `r`.
    pub fn start_on(
        &self,
        r: &Vector2<f64>,
        r_dot: &Vector2<f64>,
        surface_speed: f64,
        branches: Branches,
    ) -> Result<ContactStart, RingError> {
        check_motion(r_dot, surface_speed)?;
        let forward = self.locate_slipping_on(r, Slip::Forward, branches, f64::NAN)?;
        let backward = self.locate_slipping_on(r, Slip::Backward, branches, f64::NAN)?;
        let plain = self.ring.locate_on(r, branches, f64::NAN)?;
        let start = self.decide(r, (forward, backward), plain.normal, r_dot, surface_speed)?;
        let (ring, gap) = (&self.ring, self.ring.gap);
        let resolution =
            CORNER_TOL * (ring.x.preload + ring.y.preload) + 64.0 * f64::EPSILON * (r.norm() + gap);
        match start {
            ContactStart::Slipping(c)
                if r.norm() > gap && violation(ring, branches, &c.s) > resolution =>
            {
                self.start(r, r_dot, surface_speed)
            }
            _ => Ok(start),
        }
    }

    /// The onset rule on the two slipping locations; rolling at the frictionless normal.
    fn decide(
        &self,
        r: &Vector2<f64>,
        (forward, backward): (SlipContact, SlipContact),
        normal: Vector2<f64>,
        r_dot: &Vector2<f64>,
        surface_speed: f64,
    ) -> Result<ContactStart, RingError> {
        let v_plus = forward.slip_velocity(r_dot, surface_speed);
        let v_minus = backward.slip_velocity(r_dot, surface_speed);
        match (v_plus > 0.0, v_minus < 0.0) {
            (true, true) => Err(RingError::SlipAmbiguous {
                forward: v_plus,
                backward: v_minus,
            }),
            (true, false) => Ok(ContactStart::Slipping(forward)),
            (false, true) => Ok(ContactStart::Slipping(backward)),
            (false, false) => Ok(ContactStart::Rolling(
                self.rolling(r, normal.y.atan2(normal.x))?,
            )),
        }
    }
}
