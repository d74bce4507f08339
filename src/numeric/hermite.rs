//! The cubic Hermite interpolant of one interval, from the values and slopes at its ends.

/// The weights of the cubic Hermite interpolant at $\theta \in [0, 1]$ of an interval of
/// length $h$ from $x_0, x_0^\prime$ to $x_1, x_1^\prime$:
/// $p(\theta) = w_0 x_0 + w_1 h x_0^\prime + w_2 x_1 + w_3 h x_1^\prime$ with
/// $w_0 = (1 + 2\theta)(1 - \theta)^2$, $w_1 = \theta(1 - \theta)^2$,
/// $w_2 = \theta^2(3 - 2\theta)$, $w_3 = \theta^2(\theta - 1)$. Its error for a smooth $x$ is
/// at most $h^4 \max|x^{(4)}| / 384$.
///
/// ```
/// use jeffcott::numeric::hermite_weights;
/// // A cubic is reproduced: x = t^3 on [1, 3] (h = 2) at its midpoint, 8.
/// let w = hermite_weights(0.5);
/// let p = w[0] * 1.0 + w[1] * 2.0 * 3.0 + w[2] * 27.0 + w[3] * 2.0 * 27.0;
/// assert!((p - 8.0).abs() < 1e-12);
/// ```
pub fn hermite_weights(theta: f64) -> [f64; 4] {
    let s = theta;
    [
        (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s),
        s * (1.0 - s) * (1.0 - s),
        s * s * (3.0 - 2.0 * s),
        s * s * (s - 1.0),
    ]
}

/// The derivatives of [`hermite_weights`] with respect to $\theta$:
/// $p^\prime(\theta) = dp/d\theta$ (divide by $h$ for the slope in time) is
/// $w_0^\prime x_0 + w_1^\prime h x_0^\prime + w_2^\prime x_1 + w_3^\prime h x_1^\prime$ with
/// $w_0^\prime = -w_2^\prime = 6\theta(\theta - 1)$, $w_1^\prime = (1 - \theta)(1 - 3\theta)$,
/// $w_3^\prime = \theta(3\theta - 2)$.
///
/// ```
/// use jeffcott::numeric::hermite_slope_weights;
/// // At the ends the slope is the given one: dp/dθ = h x'.
/// assert_eq!(hermite_slope_weights(0.0), [0.0, 1.0, 0.0, 0.0]);
/// assert_eq!(hermite_slope_weights(1.0), [0.0, 0.0, 0.0, 1.0]);
/// ```
pub fn hermite_slope_weights(theta: f64) -> [f64; 4] {
    let s = theta;
    let w0 = 6.0 * s * (s - 1.0);
    [w0, (1.0 - s) * (1.0 - 3.0 * s), -w0, s * (3.0 * s - 2.0)]
}
