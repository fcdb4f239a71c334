//! The seam between the loop and the strategies: [`SearchStrategy`], and the combined
//! strategy that runs QLattice-style sampling and genetic programming side by side.
use super::archive::{Archive, Candidate, Fitted};
use super::config::Strategy;
use super::generate::Tables;
use super::genetic::Genetic;
use super::qlattice::QLattice;
use rand_chacha::ChaCha8Rng;

/// A way of proposing candidates and learning from their fits. Two implementations
/// ([`QLattice`], [`Genetic`]) and their combination; internal, since [`super::search`]
/// chooses one by [`Strategy`].
pub(crate) trait SearchStrategy: Send {
    /// Candidates for this epoch, drawn from `rng` only.
    fn propose(
        &mut self,
        epoch: usize,
        rng: &mut ChaCha8Rng,
        archive: &Archive,
        tables: &Tables,
    ) -> Vec<Candidate>;
    /// Learns from the fitted candidates of this epoch (in proposal order).
    fn update(&mut self, fitted: &[Fitted], archive: &Archive, rng: &mut ChaCha8Rng);
}

/// The strategy `which`, proposing `per_epoch` candidates an epoch. The combined strategy
/// gives each part half (QLattice the smaller half when `per_epoch` is odd).
pub(crate) fn build(which: Strategy, per_epoch: usize, tables: &Tables) -> Box<dyn SearchStrategy> {
    match which {
        Strategy::QLattice => Box::new(QLattice::new(per_epoch, tables)),
        Strategy::Genetic => Box::new(Genetic::new(per_epoch)),
        Strategy::Combined => Box::new(Combined {
            parts: vec![
                Box::new(QLattice::new(per_epoch / 2, tables)),
                Box::new(Genetic::new(per_epoch - per_epoch / 2)),
            ],
        }),
    }
}

/// Several strategies sharing one archive: each proposes in turn (its candidates tagged
/// with its index as `source`) and learns only from its own candidates' fits.
struct Combined {
    parts: Vec<Box<dyn SearchStrategy>>,
}

impl SearchStrategy for Combined {
    fn propose(
        &mut self,
        epoch: usize,
        rng: &mut ChaCha8Rng,
        archive: &Archive,
        tables: &Tables,
    ) -> Vec<Candidate> {
        let mut out = Vec::new();
        for (i, p) in self.parts.iter_mut().enumerate() {
            for mut c in p.propose(epoch, rng, archive, tables) {
                c.source = i as u8;
                out.push(c);
            }
        }
        out
    }

    fn update(&mut self, fitted: &[Fitted], archive: &Archive, rng: &mut ChaCha8Rng) {
        for (i, p) in self.parts.iter_mut().enumerate() {
            let mine: Vec<Fitted> = fitted
                .iter()
                .filter(|f| f.source as usize == i)
                .cloned()
                .collect();
            p.update(&mine, archive, rng);
        }
    }
}
