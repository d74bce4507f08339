//! A grazing's cheap probe: where only the orbit's event structure decides a bisection.

use nalgebra::{DMatrix, DVector, DefaultAllocator, OVector};

use super::{bordered, corrector_rule, model, BranchPoint, End, Solver};
use crate::hybrid::{Variational, VariationalAlloc};
use crate::stability::augmented::event_structure;
use crate::stability::newton::{self, System};
use crate::stability::orbit::newton_error;
use crate::stability::{StabilityError, StroboscopicMap, GRAZING_MARGIN};

/// The most steps of a structure probe: a held matrix that has not converged by then is too
/// far from the probe's (the bisection's first probes), and Newton takes over.
const PROBE_STEPS: u32 = 8;

/// What a probe's run reports besides the residual.
struct Seen<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    structure: Vec<&'static str>,
    contacts: usize,
    min_margin: f64,
    state: OVector<f64, D>,
}

impl<B, M, E> Solver<'_, B>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    /// The orbit on the hyperplane through `mid` normal to `normal`, by the simplified Newton
    /// on a bracket end's $[F_w\ F_p]$ `top` held throughout; each step one run of the map
    /// with a single variational column (for its events), never the Jacobian. Its
    /// [`BranchPoint`] has the event structure, contacts and margin, and no multipliers:
    /// enough for a grazing's bisection, which reads the structure alone (the final end is
    /// evaluated in full, [`Solver::completed`]).
    pub(super) fn structure_probe(
        &self,
        mid: &DVector<f64>,
        normal: &DVector<f64>,
        top: &DMatrix<f64>,
        template: &OVector<f64, M::Dim>,
    ) -> Result<End<M::Dim>, StabilityError> {
        let steps = self.opts.max_iterations.min(PROBE_STEPS);
        let (newton, ones) = self.corrector(steps, mid.len());
        let rule = corrector_rule(&newton, &ones);
        let matrix = bordered(top, normal);
        let eval = |w: &DVector<f64>| {
            let (z, p) = self.unscaled(w);
            let at_p = model(self.build, p)?;
            let map = StroboscopicMap::new(&at_p, self.period, self.opts.sim)?;
            let state = map.state(template, &z);
            let column = DMatrix::from_fn(z.len(), 1, |i, _| if i == 0 { 1.0 } else { 0.0 });
            let lin = map.linearize_along(&state, &column)?;
            let f = (&lin.value - &z).component_div(&self.scale);
            Ok::<_, StabilityError>(System {
                residual: f.push(normal.dot(&(w - mid))),
                matrix: matrix.clone(),
                extra: Seen {
                    structure: event_structure(&lin.events, lin.label),
                    contacts: lin.events.iter().filter(|e| e.contact_onset).count(),
                    min_margin: lin.min_margin(),
                    state,
                },
            })
        };
        let zero = newton::solve(mid, eval, &rule).map_err(newton_error)?;
        let seen = zero.system.extra;
        let (z, p) = self.unscaled(&zero.u);
        Ok(End {
            point: BranchPoint {
                parameter: p,
                point: z.iter().copied().collect(),
                state: seen.state.iter().copied().collect(),
                cycle: Vec::new(),
                multipliers: Vec::new(),
                stable: false,
                min_margin: seen.min_margin,
                grazing: seen.min_margin < GRAZING_MARGIN,
                contacts: seen.contacts,
                structure: seen.structure,
                arclength: 0.0,
            },
            w: zero.u,
            jac: DMatrix::zeros(0, 0),
            top: top.clone(),
            state: seen.state,
            complete: false,
        })
    }

    /// `end` with its multipliers and Jacobian: a [`Solver::structure_probe`]'s end corrected
    /// in full on the hyperplane through it normal to `normal` (it is on the branch already:
    /// one evaluation). An end that is complete, or whose correction fails, is returned as
    /// it is.
    pub(super) fn completed(&self, end: End<M::Dim>, normal: &DVector<f64>) -> End<M::Dim> {
        if end.complete {
            return end;
        }
        let full = self
            .correct((&end.w, None), normal, &end.w, &end.state)
            .and_then(|s| self.point(&s, 0.0).map(|p| End::of(&s, &p)));
        full.unwrap_or(end)
    }
}
