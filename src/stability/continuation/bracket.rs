//! The one bracketing loop of the special-point locator.

/// What a bisection step found at the midpoint.
pub(crate) enum Verdict<A, B, E> {
    /// Like the near end: the midpoint becomes the near end.
    Near(A),
    /// Like the far end: the midpoint becomes the far end.
    Far(B),
    /// No verdict (a failure at the midpoint): the bisection stops.
    Stop(E),
}

/// A bisection's final bracket.
pub(crate) struct Bracket<A, B, E> {
    /// The near end.
    pub(crate) near: A,
    /// The far end.
    pub(crate) far: B,
    /// Why it stopped before `step` said the bracket was narrow enough (`None`: it did, or
    /// the budget ran out).
    pub(crate) stopped: Option<E>,
}

/// Bisects the bracket `(near, far)`: `step(near, far)` returns `None` when the bracket is
/// narrow enough (or cannot be halved any more), otherwise the verdict at its midpoint; at
/// most `budget` steps.
pub(crate) fn bisect<A, B, E>(
    mut near: A,
    mut far: B,
    budget: usize,
    mut step: impl FnMut(&A, &B) -> Option<Verdict<A, B, E>>,
) -> Bracket<A, B, E> {
    for _ in 0..budget {
        match step(&near, &far) {
            None => {
                return Bracket {
                    near,
                    far,
                    stopped: None,
                }
            }
            Some(Verdict::Near(a)) => near = a,
            Some(Verdict::Far(b)) => far = b,
            Some(Verdict::Stop(e)) => {
                return Bracket {
                    near,
                    far,
                    stopped: Some(e),
                }
            }
        }
    }
    Bracket {
        near,
        far,
        stopped: None,
    }
}
