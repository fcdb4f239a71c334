//! What a search reports after every epoch, read by the loop (`run`), the consensus runs
//! (`vote`) and every caller's progress bar.

/// Reported after every epoch.
#[derive(Clone, Debug, PartialEq)]
pub struct Progress {
    /// Epochs done (1-based).
    pub epoch: usize,
    /// Epochs planned.
    pub epochs: usize,
    /// Models fitted so far.
    pub evaluations: u64,
    /// Lowest training mean squared error so far.
    pub best_loss: f64,
}
