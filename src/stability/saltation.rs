use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector};
use thiserror::Error;

/// Default grazing threshold of [`saltation`]: an event crossed at a margin (module docs) below
/// $10^{-3}$ is grazing.
pub const GRAZING_MARGIN: f64 = 1e-3;

/// The linearisation of one event: what [`saltation`] needs.
#[derive(Debug, Clone, Copy)]
pub struct EventLinearization<'a, D: Dim>
where
    DefaultAllocator: Allocator<D> + Allocator<D, D>,
{
    /// Vector field before the event, $f^-$, at the state before it.
    pub field_before: &'a OVector<f64, D>,
    /// Vector field after the event, $f^+$, at the state after it (after the reset).
    pub field_after: &'a OVector<f64, D>,
    /// Gradient of the guard with respect to the state, $\nabla g$.
    pub guard_gradient: &'a OVector<f64, D>,
    /// Explicit time derivative of the guard, $g_t$ (0 for an autonomous guard).
    pub guard_time_derivative: f64,
    /// Jacobian of the reset, $R_x$; `None` for no reset (the identity).
    pub reset_jacobian: Option<&'a OMatrix<f64, D, D>>,
    /// Explicit time derivative of the reset, $R_t$; `None` for zero.
    pub reset_time_derivative: Option<&'a OVector<f64, D>>,
    /// The state's scale $s$ ([`RotorModel::state_scale`](crate::hybrid::RotorModel::state_scale)):
    /// the margin is measured in the scaled coordinates $x_c/s_c$ (module docs); `None` for 1
    /// in every component.
    pub state_scale: Option<&'a OVector<f64, D>>,
}

/// A saltation matrix with what it was computed from.
#[derive(Debug, Clone, PartialEq)]
pub struct Saltation<D: Dim>
where
    DefaultAllocator: Allocator<D> + Allocator<D, D>,
{
    /// $S$: $\delta x^+ = S\thinspace \delta x^-$.
    pub matrix: OMatrix<f64, D, D>,
    /// $-\nabla g/(\nabla g\cdot f^- + g_t)$: the event time moves by
    /// $\delta t_e = $ `time_gradient` $\cdot\thinspace \delta x^-$.
    pub time_gradient: OVector<f64, D>,
    /// The denominator $\nabla g\cdot f^- + g_t$, the guard's crossing rate.
    pub denominator: f64,
    /// Its scale $|\nabla g|\thinspace|f^-|_{\nabla g} + |g_t|$ (module docs).
    pub scale: f64,
}

impl<D: Dim> Saltation<D>
where
    DefaultAllocator: Allocator<D> + Allocator<D, D>,
{
    /// The crossing margin $|\text{denominator}|/\text{scale}$ in $[0, 1]$: 1 for a crossing
    /// along the guard's normal, 0 at grazing.
    pub fn margin(&self) -> f64 {
        margin(self.denominator, self.scale)
    }

    /// Whether the margin is below `threshold`.
    pub fn is_grazing(&self, threshold: f64) -> bool {
        self.margin() < threshold
    }
}

/// The checks of [`saltation`]'s inputs: the threshold, the dimensions, finite values and a
/// positive scale.
fn validate<D: Dim>(event: &EventLinearization<'_, D>, threshold: f64) -> Result<(), SaltationError>
where
    DefaultAllocator: Allocator<D> + Allocator<D, D>,
{
    if !(0.0..=1.0).contains(&threshold) {
        return Err(SaltationError::InvalidThreshold { value: threshold });
    }
    let n = event.field_before.nrows();
    let check = |field: &'static str, found: usize, finite: bool| {
        if found != n {
            Err(SaltationError::DimensionMismatch {
                field,
                expected: n,
                found,
            })
        } else if !finite {
            Err(SaltationError::NonFinite { field })
        } else {
            Ok(())
        }
    };
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    check("field_before", n, finite(event.field_before.as_slice()))?;
    check(
        "field_after",
        event.field_after.nrows(),
        finite(event.field_after.as_slice()),
    )?;
    check(
        "guard_gradient",
        event.guard_gradient.nrows(),
        finite(event.guard_gradient.as_slice()),
    )?;
    if !event.guard_time_derivative.is_finite() {
        return Err(SaltationError::NonFinite {
            field: "guard_time_derivative",
        });
    }
    if let Some(r) = event.reset_jacobian {
        check("reset_jacobian", r.nrows(), finite(r.as_slice()))?;
        check("reset_jacobian", r.ncols(), true)?;
    }
    if let Some(r) = event.reset_time_derivative {
        check("reset_time_derivative", r.nrows(), finite(r.as_slice()))?;
    }

    if let Some(s) = event.state_scale {
        check("state_scale", s.nrows(), true)?;
        if let Some((component, &value)) = s
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v > 0.0))
        {
            return Err(SaltationError::InvalidScale { component, value });
        }
    }
    Ok(())
}

/// The scale of the crossing rate, $|\nabla g|\thinspace|f^-|_{\nabla g} + |g_t|$ (module
/// docs), in the coordinates scaled by the event's `state_scale` if it has one.
fn rate_scale<D: Dim>(event: &EventLinearization<'_, D>) -> f64
where
    DefaultAllocator: Allocator<D> + Allocator<D, D>,
{
    let (f_minus, grad) = (event.field_before, event.guard_gradient);
    let (grad_norm, support) = match event.state_scale {
        None => {
            let support: f64 = grad
                .iter()
                .zip(f_minus.iter())
                .filter(|(g, _)| **g != 0.0)
                .map(|(_, f)| f * f)
                .sum();
            (grad.norm(), support)
        }
        Some(s) => {
            let pairs = || grad.iter().zip(f_minus.iter()).zip(s.iter());
            let grad_sq: f64 = pairs().map(|((g, _), s)| (g * s) * (g * s)).sum();
            let support: f64 = pairs()
                .filter(|((g, _), _)| **g != 0.0)
                .map(|((_, f), s)| (f / s) * (f / s))
                .sum();
            (grad_sq.sqrt(), support)
        }
    };
    grad_norm * support.sqrt() + event.guard_time_derivative.abs()
}

fn margin(denominator: f64, scale: f64) -> f64 {
    if scale > 0.0 {
        (denominator.abs() / scale).min(1.0)
    } else {
        0.0
    }
}

/// Why [`saltation`] gave no matrix.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum SaltationError {
    /// The trajectory crosses the guard at a margin below the threshold: the event is grazing
    /// and the linearisation through it is not to be trusted. Find out whether the model's
    /// saltation stays bounded there (then pass a smaller threshold), or move away from the
    /// grazing (another parameter, another orbit).
    #[error("grazing event: crossing margin {margin:e} below the threshold {threshold:e} (guard rate {denominator:e}, scale {scale:e})")]
    Grazing {
        /// The margin $|\text{denominator}|/\text{scale}$.
        margin: f64,
        /// The threshold it fell below.
        threshold: f64,
        /// The guard's crossing rate $\nabla g\cdot f^- + g_t$.
        denominator: f64,
        /// Its scale.
        scale: f64,
    },
    /// An input holds NaN or infinity.
    #[error("{field} is not finite")]
    NonFinite {
        /// The input (`"field_before"`, `"guard_gradient"`, ...).
        field: &'static str,
    },
    /// An input's dimension differs from the state's (that of `field_before`).
    #[error("{field} has dimension {found}, the state has {expected}")]
    DimensionMismatch {
        /// The input.
        field: &'static str,
        /// The state's dimension.
        expected: usize,
        /// The input's.
        found: usize,
    },
    /// A component of the state's scale is not finite and positive.
    #[error("state_scale[{component}] = {value}: a scale must be finite and > 0")]
    InvalidScale {
        /// The component.
        component: usize,
        /// Its scale.
        value: f64,
    },
    /// The threshold is not a number in $[0, 1]$.
    #[error(
        "grazing threshold {value} must be in [0, 1] (the margin's range); the default is 1e-3"
    )]
    InvalidThreshold {
        /// The offending value.
        value: f64,
    },
}

/// The saltation matrix of an event (module docs), or [`SaltationError::Grazing`] when the
/// event is crossed at a margin below `threshold` (use [`GRAZING_MARGIN`] unless the model's
/// saltation is known to stay bounded; with `threshold = 0` only an exactly zero or non-finite
/// ratio is refused).
///
/// # Errors
/// [`SaltationError::Grazing`] (with the margin), [`SaltationError::NonFinite`],
/// [`SaltationError::DimensionMismatch`], [`SaltationError::InvalidThreshold`].
pub fn saltation<D: Dim>(
    event: &EventLinearization<'_, D>,
    threshold: f64,
) -> Result<Saltation<D>, SaltationError>
where
    DefaultAllocator: Allocator<D> + Allocator<D, D>,
{
    validate(event, threshold)?;
    let (f_minus, grad) = (event.field_before, event.guard_gradient);
    let denominator = grad.dot(f_minus) + event.guard_time_derivative;
    let scale = rate_scale(event);
    let m = margin(denominator, scale);
    if m < threshold || denominator == 0.0 {
        return Err(SaltationError::Grazing {
            margin: m,
            threshold,
            denominator,
            scale,
        });
    }
    // jump = f+ - R_x f- - R_t
    let mut jump = event.field_after.clone_owned();
    match event.reset_jacobian {
        Some(r) => jump -= r * f_minus,
        None => jump -= f_minus,
    }
    if let Some(rt) = event.reset_time_derivative {
        jump -= rt;
    }
    let inv = 1.0 / denominator;
    let mut matrix = match event.reset_jacobian {
        Some(r) => r.clone_owned(),
        None => {
            let d = f_minus.shape_generic().0;
            OMatrix::<f64, D, D>::identity_generic(d, d)
        }
    };
    matrix.ger(inv, &jump, grad, 1.0);
    let time_gradient = grad * -inv;
    if !matrix.iter().all(|x| x.is_finite()) {
        return Err(SaltationError::NonFinite { field: "matrix" });
    }
    Ok(Saltation {
        matrix,
        time_gradient,
        denominator,
        scale,
    })
}
