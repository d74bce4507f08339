//! Deserialisation helpers of the derives (crate-private): those of the `serde` feature, and
//! of the records of `global` (always compiled).
//!
//! Labels of guards, options and error fields are `&'static str` in the crate's types (the
//! models name them with string literals). A label read back from a file is *interned*: the
//! first time a distinct string is read it is leaked once, for the life of the process, and
//! every later read of the same string returns that copy. Memory therefore grows with the
//! number of distinct labels read (a handful for the crate's models), not with the number of
//! records.

use std::collections::BTreeSet;
use std::sync::Mutex;

use serde::{Deserialize, Deserializer};

/// The interned labels.
static LABELS: Mutex<BTreeSet<&'static str>> = Mutex::new(BTreeSet::new());

/// The `'static` copy of `s`: the interned one if `s` was read before, else a new leaked one.
fn intern(s: String) -> &'static str {
    // A panic while the lock is held cannot leave the set inconsistent (insert is atomic
    // from the outside), so a poisoned lock is still usable.
    let mut labels = LABELS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(&label) = labels.get(s.as_str()) {
        return label;
    }
    let label: &'static str = Box::leak(s.into_boxed_str());
    labels.insert(label);
    label
}

/// Reads a `&'static str` label (interned).
pub(crate) fn label<'de, D: Deserializer<'de>>(d: D) -> Result<&'static str, D::Error> {
    String::deserialize(d).map(intern)
}

/// Reads a list of labels (interned).
pub(crate) fn labels<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<&'static str>, D::Error> {
    Ok(Vec::<String>::deserialize(d)?
        .into_iter()
        .map(intern)
        .collect())
}

/// Reads an optional list of labels (interned).
pub(crate) fn option_labels<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<&'static str>>, D::Error> {
    Ok(Option::<Vec<String>>::deserialize(d)?.map(|v| v.into_iter().map(intern).collect()))
}

/// Two lists of labels (before, after), interned.
type LabelPair = (Vec<&'static str>, Vec<&'static str>);

/// Reads a pair of lists of labels (interned).
pub(crate) fn label_pair<'de, D: Deserializer<'de>>(d: D) -> Result<LabelPair, D::Error> {
    let (a, b) = <(Vec<String>, Vec<String>)>::deserialize(d)?;
    Ok((
        a.into_iter().map(intern).collect(),
        b.into_iter().map(intern).collect(),
    ))
}

/// Reads a count and rejects one above `N` (a length of a fixed array it indexes).
pub(crate) fn count_at_most<'de, D: Deserializer<'de>, const N: usize>(
    d: D,
) -> Result<usize, D::Error> {
    let n = usize::deserialize(d)?;
    if n > N {
        return Err(serde::de::Error::custom(format_args!(
            "count {n} above its bound {N}"
        )));
    }
    Ok(n)
}
