//! What flows through the loop: proposed [`Candidate`]s, their [`Fitted`] results, and the
//! [`Archive`] of the best fit at each complexity that every strategy reads.
use crate::program::Program;

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
    /// At each complexity, the next best distinct programs by loss after the one in
    /// `by_complexity` (at most `runners_up_kept`), so that selection can choose among
    /// structures that fit alike ([`SearchConfig::runners_up`](crate::SearchConfig::runners_up)).
    pub runners_up: Vec<Vec<Fitted>>,
    /// How many runners-up are kept at each complexity (0: none).
    pub runners_up_kept: usize,
}

impl Archive {
    /// An empty archive that keeps `runners_up` programs at each complexity besides the best.
    pub(crate) fn with_runners_up(runners_up: usize) -> Self {
        Self {
            runners_up_kept: runners_up,
            ..Self::default()
        }
    }

    /// Keeps `f` if it has the lowest loss at its complexity or the lowest score overall,
    /// or among the runners-up at its complexity; rejected fits (non-finite score) are
    /// ignored.
    pub(crate) fn offer(&mut self, f: &Fitted) {
        if !f.score.is_finite() {
            return;
        }
        if self.by_complexity.len() <= f.complexity {
            self.by_complexity.resize(f.complexity + 1, None);
            self.runners_up.resize(f.complexity + 1, Vec::new());
        }
        let slot = &mut self.by_complexity[f.complexity];
        let displaced = match slot {
            Some(s) if s.program == f.program => None,
            Some(s) if f.mse < s.mse => slot.replace(f.clone()),
            Some(_) => Some(f.clone()),
            None => {
                *slot = Some(f.clone());
                None
            }
        };
        if let Some(r) = displaced
            && self.runners_up_kept > 0
        {
            let list = &mut self.runners_up[r.complexity];
            if !list.iter().any(|x| x.program == r.program) {
                let at = list.partition_point(|x| x.mse <= r.mse);
                if at < self.runners_up_kept {
                    list.insert(at, r);
                    list.truncate(self.runners_up_kept);
                }
            }
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

    /// The runners-up at the complexities of the front (see [`Archive::runners_up`]).
    pub(crate) fn front_runners_up(&self) -> Vec<Fitted> {
        self.front()
            .iter()
            .flat_map(|f| self.runners_up.get(f.complexity).into_iter().flatten())
            .cloned()
            .collect()
    }

    /// Lowest training loss on the front (infinite while the archive is empty).
    pub(crate) fn best_loss(&self) -> f64 {
        self.front()
            .iter()
            .map(|f| f.mse)
            .fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::Node;

    fn fit(var: u16, mse: f64) -> Fitted {
        Fitted {
            program: Program {
                nodes: vec![Node::Var(var)],
                affine: true,
            },
            params: vec![1.0; 4],
            mse,
            score: mse,
            complexity: 1,
            source: 0,
            tag: 0,
        }
    }

    #[test]
    fn the_runners_up_are_the_next_best_distinct_programs() {
        let mut a = Archive::with_runners_up(2);
        for f in [
            fit(0, 1.0),
            fit(1, 2.0),
            fit(0, 1.0),
            fit(2, 0.5),
            fit(3, 3.0),
        ] {
            a.offer(&f);
        }
        let best = a.by_complexity[1].as_ref().map(|f| f.program.nodes.clone());
        assert_eq!(best, Some(vec![Node::Var(2)]));
        let runners: Vec<_> = a.front_runners_up().iter().map(|f| f.mse).collect();
        assert_eq!(runners, vec![1.0, 2.0], "x0 once, x3 beyond the two kept");
        let mut none = Archive::default();
        for f in [fit(0, 1.0), fit(1, 2.0)] {
            none.offer(&f);
        }
        assert!(none.front_runners_up().is_empty());
    }
}
