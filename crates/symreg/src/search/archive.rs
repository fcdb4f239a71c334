//! What flows through the loop: proposed [`Candidate`]s, their [`Fitted`] results, and the
//! [`Archive`] of the best fit at each complexity that every strategy reads.
use super::generate::Tables;
use crate::program::Program;
use rand_chacha::ChaCha8Rng;

/// A proposed model structure, optionally with parameters to start from.
#[derive(Clone, Debug)]
pub(crate) struct Candidate {
    /// The structure.
    pub program: Program,
    /// Warm start (used when its length matches the program).
    pub params: Option<Vec<f64>>,
    /// Which strategy proposed it (index into the combined strategy's parts).
    pub source: u8,
    /// Strategy-specific tag (cell or island).
    pub tag: u32,
}

impl Candidate {
    /// A proposal of `program` tagged `tag`, warm-started from `params` if given; the
    /// combined strategy sets `source`.
    pub(crate) fn new(program: Program, params: Option<Vec<f64>>, tag: u32) -> Self {
        Self {
            program,
            params,
            source: 0,
            tag,
        }
    }

    /// A fresh random program of `tables`, tagged `tag`.
    pub(crate) fn random(tables: &Tables, rng: &mut ChaCha8Rng, tag: u32) -> Self {
        Self::new(tables.random_program(rng), None, tag)
    }
}

/// A fitted candidate.
#[derive(Clone, Debug)]
pub(crate) struct Fitted {
    /// The structure.
    pub program: Program,
    /// Fitted parameters.
    pub params: Vec<f64>,
    /// Training MSE (on the fitting rows).
    pub mse: f64,
    /// Criterion value, lower is better (`INFINITY` when rejected).
    pub score: f64,
    /// Complexity.
    pub complexity: usize,
    /// Proposing strategy.
    pub source: u8,
    /// Strategy-specific tag.
    pub tag: u32,
}

impl Fitted {
    /// This fit credited to another proposal of the same structure (a cache hit or a
    /// duplicate within an epoch): the strategy that proposed `c` learns from it.
    pub(crate) fn relabelled(&self, c: &Candidate) -> Fitted {
        let mut f = self.clone();
        f.source = c.source;
        f.tag = c.tag;
        f
    }
}

/// Best fitted model at each complexity so far.
#[derive(Clone, Debug, Default)]
pub(crate) struct Archive {
    /// Indexed by complexity.
    pub by_complexity: Vec<Option<Fitted>>,
    /// Best by score.
    pub best: Option<Fitted>,
}

impl Archive {
    /// Keeps `f` if it has the lowest loss at its complexity or the lowest score overall;
    /// rejected fits (non-finite score) are ignored.
    pub(crate) fn offer(&mut self, f: &Fitted) {
        if !f.score.is_finite() {
            return;
        }
        if self.by_complexity.len() <= f.complexity {
            self.by_complexity.resize(f.complexity + 1, None);
        }
        let slot = &mut self.by_complexity[f.complexity];
        if slot.as_ref().is_none_or(|s| f.mse < s.mse) {
            *slot = Some(f.clone());
        }
        if self.best.as_ref().is_none_or(|b| f.score < b.score) {
            self.best = Some(f.clone());
        }
    }

    /// Models on the Pareto front (each strictly better than every simpler one).
    pub(crate) fn front(&self) -> Vec<Fitted> {
        let mut out: Vec<Fitted> = Vec::new();
        for f in self.by_complexity.iter().flatten() {
            if out.last().is_none_or(|l| f.mse < l.mse) {
                out.push(f.clone());
            }
        }
        out
    }

    /// Lowest training loss on the front (infinite while the archive is empty).
    pub(crate) fn best_loss(&self) -> f64 {
        self.front()
            .iter()
            .map(|f| f.mse)
            .fold(f64::INFINITY, f64::min)
    }
}
