use super::attractor::{Attractor, MatchOptions};

/// What a point of a scan is labelled with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum PointLabel {
    /// The point reached attractor `k` of [`Catalogue::entries`].
    Attractor(usize),
    /// The point's run failed.
    Failed,
    /// The point has not been run (a partial run).
    NotRun,
}

/// One distinct attractor of a [`Catalogue`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CatalogueEntry {
    /// The attractor as reached from the first point that found it: its representative.
    pub attractor: Attractor,
    /// Index of that point.
    pub first: usize,
    /// Number of points that reached it.
    pub count: usize,
}

/// The distinct attractors of a scan and each point's label.
///
/// Built by [`Catalogue::new`] in point order: each point's attractor is compared with the
/// representatives found so far ([`Attractor::matches`]) and takes the first that matches, or
/// becomes a new entry. The result depends only on the outcomes and their order, never on
/// how they were computed (threads, ranks, restarts).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Catalogue {
    /// The distinct attractors, in order of first appearance.
    pub entries: Vec<CatalogueEntry>,
    /// One label per point.
    pub labels: Vec<PointLabel>,
    /// The tolerance used.
    pub tolerance: MatchOptions,
}

impl Catalogue {
    /// Matches the attractors of `results` (one slot per point; `None` = not run) at `tol`.
    pub fn new<E>(results: &[Option<Result<Attractor, E>>], tol: &MatchOptions) -> Self {
        let mut entries: Vec<CatalogueEntry> = Vec::new();
        let labels = results
            .iter()
            .enumerate()
            .map(|(i, r)| match r {
                None => PointLabel::NotRun,
                Some(Err(_)) => PointLabel::Failed,
                Some(Ok(a)) => {
                    let k = match entries.iter().position(|e| e.attractor.matches(a, tol)) {
                        Some(k) => k,
                        None => {
                            entries.push(CatalogueEntry {
                                attractor: a.clone(),
                                first: i,
                                count: 0,
                            });
                            entries.len() - 1
                        }
                    };
                    entries[k].count += 1;
                    PointLabel::Attractor(k)
                }
            })
            .collect();
        Catalogue {
            entries,
            labels,
            tolerance: *tol,
        }
    }

    /// Number of points whose run failed.
    pub fn failed(&self) -> usize {
        self.labels
            .iter()
            .filter(|l| **l == PointLabel::Failed)
            .count()
    }

    /// The entries' indices ordered by decreasing basin size (ties: first appearance).
    pub fn by_size(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.entries.len()).collect();
        order.sort_by_key(|&k| (std::cmp::Reverse(self.entries[k].count), k));
        order
    }
}
