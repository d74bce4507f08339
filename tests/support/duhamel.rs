//! The response of the linear Jeffcott rotor without contact by the Duhamel integral,
//! evaluated by composite 5-point Gauss-Legendre quadrature written here: a truth for run-ups
//! independent of the crate's integrators (issue 21 item 4).

/// Composite 5-point Gauss-Legendre quadrature of `f` over `[a, b]` on `panels` panels (exact
/// for polynomials of degree 9 on each panel; nodes and weights in closed form).
pub fn gauss_legendre(f: impl Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
    let r = (10.0f64 / 7.0).sqrt();
    let (x1, x2) = ((5.0 - 2.0 * r).sqrt() / 3.0, (5.0 + 2.0 * r).sqrt() / 3.0);
    let s70 = 70.0f64.sqrt();
    let (w1, w2) = ((322.0 + 13.0 * s70) / 900.0, (322.0 - 13.0 * s70) / 900.0);
    let nodes = [
        (0.0, 128.0 / 225.0),
        (x1, w1),
        (-x1, w1),
        (x2, w2),
        (-x2, w2),
    ];
    let h = (b - a) / panels as f64;
    (0..panels)
        .map(|i| {
            let mid = a + (i as f64 + 0.5) * h;
            let sum: f64 = nodes.iter().map(|(x, w)| w * f(mid + 0.5 * h * x)).sum();
            0.5 * h * sum
        })
        .sum()
}

/// The response at $\tau$ of $u^{\prime\prime} + 2\nu u^\prime + u = F(\tau)$ from rest,
/// $u(\tau) = \int_0^\tau h(\tau - s) F(s)\thinspace ds$ with the impulse response
/// $h(t) = e^{-\nu t}\sin(\omega_d t)/\omega_d$, $\omega_d = \sqrt{1 - \nu^2}$.
pub fn duhamel(nu: f64, force: impl Fn(f64) -> f64, tau: f64, panels: usize) -> f64 {
    let wd = (1.0 - nu * nu).sqrt();
    let h = |t: f64| (-nu * t).exp() * (wd * t).sin() / wd;
    gauss_legendre(|s| h(tau - s) * force(s), 0.0, tau, panels)
}

/// The out-of-balance force on a ramp $\eta = \eta_0 + R s$, written from the formula:
/// $\beta(\eta^2\cos\varphi + \eta^\prime\sin\varphi, \eta^2\sin\varphi - \eta^\prime\cos\varphi)$,
/// $\varphi = \varphi_0 + \eta_0 s + R s^2/2$; with `tangential` false, without the
/// $\eta^\prime$ terms.
pub fn ramp_force(
    beta: f64,
    phi0: f64,
    eta0: f64,
    rate: f64,
    s: f64,
    tangential: bool,
) -> [f64; 2] {
    let eta = eta0 + rate * s;
    let (sin, cos) = (phi0 + eta0 * s + 0.5 * rate * s * s).sin_cos();
    let a = beta * eta * eta;
    let b = if tangential { beta * rate } else { 0.0 };
    [a * cos + b * sin, a * sin - b * cos]
}
