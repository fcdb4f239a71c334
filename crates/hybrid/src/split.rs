//! The train/test split as a model file stores it, one type for both halves.
//!
//! The record half splits records (or their windows) and names them by record id; the table
//! half splits rows and names them by index. The type is generic over the split's kind and
//! what names a member; what only one half has is optional and left out of the JSON when
//! absent, so each model file keeps the keys it has always written.

use serde::{Deserialize, Serialize};

/// A window named by record id and index.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct WindowId {
    /// Record id.
    pub record: String,
    /// Window index within the record.
    pub window: usize,
}

/// Which members were used for fitting and which were held out (JSON `split`).
///
/// - Record models: `kind` a [`SplitKind`](crate::records::SplitKind), members record ids (sorted;
///   a record is on a side when at least one of its windows is), with `seed`,
///   `test_fraction` and `test_windows` (the test windows of a window split, empty for a
///   record split).
/// - Table models: `kind` the split's name (`random`, `grouped`, `extrapolate`, `given`),
///   members row indices (0-based, in the table's order); no seed, fraction or windows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SplitInfo<K, T> {
    /// How the split was made.
    pub kind: K,
    /// Seed of the split (record models).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Fraction of groups (records or windows) held out (record models).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub test_fraction: Option<f64>,
    /// The training members.
    pub train: Vec<T>,
    /// The test members.
    pub test: Vec<T>,
    /// With a window split, the test windows (record models: empty for a record split,
    /// and when read from a file written before it was stored).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub test_windows: Option<Vec<WindowId>>,
}

impl<K> SplitInfo<K, usize> {
    /// The split of a table's rows, `split`, named `kind`.
    pub fn rows(kind: K, split: &hxai_eval::Split) -> Self {
        Self {
            kind,
            seed: None,
            test_fraction: None,
            train: split.train.clone(),
            test: split.test.clone(),
            test_windows: None,
        }
    }
}
