//! A Katz back-off n-gram model with Good-Turing discounts (Katz 1987, "Estimation of
//! probabilities from sparse data for the language model component of a speech
//! recogniser", IEEE Trans. ASSP 35), as Bartlett, Desmond and Ferreira (2023) use it for
//! a prior over equations.
//!
//! For a history `h` of `m` tokens and a token `w` seen `r` times after it,
//! `P(w | h) = d_r r / c(h)`; an unseen `w` gets `alpha(h) P(w | h')` with `h'` the history
//! without its oldest token, and `alpha(h)` spreads the discounted mass `beta(h)` over the
//! unseen tokens in proportion to `P(. | h')`, so every distribution sums to 1. The
//! discount `d_r` is Katz's: counts above [`KATZ_K`] are trusted (`d_r = 1`), smaller ones
//! discounted by Good-Turing, `d_r = (r*/r - (k+1) n_{k+1}/n_1) / (1 - (k+1) n_{k+1}/n_1)`
//! with `r* = (r+1) n_{r+1}/n_r` and `n_r` the number of distinct n-grams of that order
//! seen `r` times.
//!
//! Three guards keep every cost finite and every distribution proper on a small corpus:
//! - The unigram is the Krichevsky-Trofimov estimate `(n(w) + 1/2) / (N + |V|/2)` over the
//!   [`Token::PREDICTED`] vocabulary: this is the floor. A token the corpus never uses
//!   (`gaussian`) costs at least `ln(2N + |V|)` nats below any history (about 9.4 for a
//!   corpus of 6,000 tokens), plus the back-off weights above it.
//! - Where the counts of counts make the Good-Turing discounts leave `(0, 1)` (a gap in
//!   `n_1 .. n_{k+1}`), `k` is lowered until they do not; if no `k >= 1` works, absolute
//!   discounting `d_r = (r - D)/r` with `D = n_1/(n_1 + 2 n_2)` clamped to `[0.1, 0.9]`
//!   (Ney, Essen and Kneser 1994) takes over for that order.
//! - A history whose continuations are all frequent (so Katz discounts nothing) keeps at
//!   least [`MIN_BACKOFF_MASS`]` / (c(h) + 1)` for the unseen tokens; the seen ones are
//!   scaled down to make room. A history that has seen every token needs no back-off and
//!   its discounted probabilities are scaled up to sum to 1.

use super::tokens::Token;
use std::collections::BTreeMap;

/// Largest count Good-Turing discounts (Katz's `k`); counts above it are taken as they are.
pub const KATZ_K: u64 = 5;

/// The back-off mass a history keeps at least, as `MIN_BACKOFF_MASS / (c(h) + 1)`: half a
/// count, the Krichevsky-Trofimov pseudo-count, so a history seen 200 times always leaves
/// about 1/400 to the tokens never seen after it.
pub const MIN_BACKOFF_MASS: f64 = 0.5;

/// The counts seen after one history, and its back-off weight.
#[derive(Clone, Debug, PartialEq)]
struct History {
    total: u64,
    counts: BTreeMap<Token, u64>,
    /// Multiplies the discounted probability of a seen token.
    scale: f64,
    /// Multiplies the lower order's probability of an unseen token.
    alpha: f64,
}

/// How the counts of one order are discounted.
#[derive(Clone, Debug, PartialEq)]
enum Discount {
    /// Katz: `d[r - 1]` for `r <= d.len()`, 1 above.
    GoodTuring(Vec<f64>),
    /// `d_r = (r - D)/r` for every count.
    Absolute(f64),
}

impl Discount {
    fn of(&self, r: u64) -> f64 {
        match self {
            Discount::GoodTuring(d) => usize::try_from(r)
                .ok()
                .and_then(|r| d.get(r.wrapping_sub(1)))
                .copied()
                .unwrap_or(1.0),
            Discount::Absolute(big_d) => (r as f64 - big_d) / r as f64,
        }
    }

    /// Katz's discounts from the counts of counts (`n[r]` = n-grams seen `r` times).
    fn from_counts_of_counts(n: &BTreeMap<u64, u64>) -> Discount {
        let nr = |r: u64| n.get(&r).copied().unwrap_or(0) as f64;
        for k in (1..=KATZ_K).rev() {
            if (1..=k + 1).any(|r| nr(r) == 0.0) {
                continue;
            }
            let common = (k + 1) as f64 * nr(k + 1) / nr(1);
            if common >= 1.0 {
                continue;
            }
            let d: Vec<f64> = (1..=k)
                .map(|r| {
                    let r_star = (r + 1) as f64 * nr(r + 1) / nr(r);
                    (r_star / r as f64 - common) / (1.0 - common)
                })
                .collect();
            if d.iter().all(|&d| d > 0.0 && d < 1.0) {
                return Discount::GoodTuring(d);
            }
        }
        let (n1, n2) = (nr(1), nr(2));
        let big_d = if n1 > 0.0 && n2 > 0.0 {
            n1 / (n1 + 2.0 * n2)
        } else {
            0.5
        };
        Discount::Absolute(big_d.clamp(0.1, 0.9))
    }
}

/// A trained back-off model.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Ngram {
    order: usize,
    /// `P(w)` for every predicted token.
    unigram: BTreeMap<Token, f64>,
    /// `levels[m - 1]`: the histories of `m` tokens, `m = 1 .. order - 1`.
    levels: Vec<BTreeMap<Vec<Token>, History>>,
    discounts: Vec<Discount>,
}

impl Ngram {
    /// Trains on sentences (without start and end marks). `order >= 1`.
    pub(crate) fn train(sentences: &[Vec<Token>], order: usize) -> Ngram {
        let order = order.max(1);
        let mut uni: BTreeMap<Token, u64> = BTreeMap::new();
        let mut levels: Vec<BTreeMap<Vec<Token>, History>> = vec![BTreeMap::new(); order - 1];
        for s in sentences {
            let mut padded = vec![Token::Start; order - 1];
            padded.extend(
                s.iter()
                    .copied()
                    .filter(|t| *t != Token::Start && *t != Token::End),
            );
            padded.push(Token::End);
            for i in order - 1..padded.len() {
                let w = padded[i];
                *uni.entry(w).or_default() += 1;
                for (m, level) in levels.iter_mut().enumerate() {
                    let h = padded[i - m - 1..i].to_vec();
                    let e = level.entry(h).or_insert_with(|| History {
                        total: 0,
                        counts: BTreeMap::new(),
                        scale: 1.0,
                        alpha: 1.0,
                    });
                    e.total += 1;
                    *e.counts.entry(w).or_default() += 1;
                }
            }
        }
        let n: u64 = uni.values().sum();
        let v = Token::PREDICTED.len() as f64;
        let unigram = Token::PREDICTED
            .iter()
            .map(|&w| {
                let c = uni.get(&w).copied().unwrap_or(0) as f64;
                (w, (c + 0.5) / (n as f64 + 0.5 * v))
            })
            .collect();
        let discounts = levels
            .iter()
            .map(|level| {
                let mut nn: BTreeMap<u64, u64> = BTreeMap::new();
                for h in level.values() {
                    for &c in h.counts.values() {
                        *nn.entry(c).or_default() += 1;
                    }
                }
                Discount::from_counts_of_counts(&nn)
            })
            .collect();
        let mut model = Ngram {
            order,
            unigram,
            levels,
            discounts,
        };
        // back-off weights from the lowest order up: each uses the finished order below
        for m in 0..model.levels.len() {
            let weights: Vec<(Vec<Token>, f64, f64)> = model.levels[m]
                .iter()
                .map(|(h, hist)| {
                    let (scale, alpha) = model.weights(m, h, hist);
                    (h.clone(), scale, alpha)
                })
                .collect();
            for (h, scale, alpha) in weights {
                if let Some(hist) = model.levels[m].get_mut(&h) {
                    hist.scale = scale;
                    hist.alpha = alpha;
                }
            }
        }
        model
    }

    /// `(scale, alpha)` of history `h` at level `m` (the guards of the module docs).
    fn weights(&self, m: usize, h: &[Token], hist: &History) -> (f64, f64) {
        let total = hist.total as f64;
        let seen: f64 = hist
            .counts
            .values()
            .map(|&r| self.discounts[m].of(r) * r as f64 / total)
            .sum();
        let lower_seen: f64 = hist.counts.keys().map(|&w| self.prob(w, &h[1..])).sum();
        let lower_unseen = 1.0 - lower_seen;
        if lower_unseen <= 1e-12 {
            return (1.0 / seen, 0.0);
        }
        let floor = MIN_BACKOFF_MASS / (total + 1.0);
        let (scale, beta) = if 1.0 - seen < floor {
            ((1.0 - floor) / seen, floor)
        } else {
            (1.0, 1.0 - seen)
        };
        (scale, beta / lower_unseen)
    }

    /// The order `n` of the model.
    pub(crate) fn order(&self) -> usize {
        self.order
    }

    /// `P(w | history)`, using the last `order - 1` tokens of the history (fewer at the
    /// start of a sentence: pad with [`Token::Start`]).
    pub(crate) fn prob(&self, w: Token, history: &[Token]) -> f64 {
        let keep = history.len().min(self.order - 1);
        let mut h = &history[history.len() - keep..];
        let mut weight = 1.0;
        while !h.is_empty() {
            if let Some(hist) = self.levels[h.len() - 1].get(h) {
                if let Some(&r) = hist.counts.get(&w) {
                    let d = self.discounts[h.len() - 1].of(r);
                    return weight * hist.scale * d * r as f64 / hist.total as f64;
                }
                weight *= hist.alpha;
            }
            h = &h[1..];
        }
        weight * self.unigram.get(&w).copied().unwrap_or(0.0)
    }

    /// Every history the model has seen, shortest first, in token order.
    #[cfg(test)]
    pub(crate) fn histories(&self) -> impl Iterator<Item = &[Token]> {
        self.levels.iter().flat_map(|l| l.keys().map(Vec::as_slice))
    }

    /// How many times `w` followed `h` in training (the unigram count for an empty `h`
    /// is not kept: 0).
    #[cfg(test)]
    pub(crate) fn count(&self, h: &[Token], w: Token) -> u64 {
        h.len()
            .checked_sub(1)
            .and_then(|m| self.levels.get(m))
            .and_then(|l| l.get(h))
            .and_then(|hist| hist.counts.get(&w))
            .copied()
            .unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Katz's discounts by hand for n1..n6 = 10, 4, 2, 1, 1, 1: k = 5 and k = 4 give a
    /// discount above 1 (d4 = 1.625, then 1.5), so k = 3 with (k+1) n4/n1 = 0.4:
    /// d1 = (0.8 - 0.4)/0.6, d2 = (0.75 - 0.4)/0.6, d3 = (2/3 - 0.4)/0.6; counts above 3
    /// are not discounted. A gap in the counts of counts falls back to absolute
    /// discounting.
    #[test]
    fn good_turing_discounts_by_hand() {
        let n: BTreeMap<u64, u64> = [(1, 10), (2, 4), (3, 2), (4, 1), (5, 1), (6, 1)].into();
        let d = Discount::from_counts_of_counts(&n);
        let want = [2.0 / 3.0, 7.0 / 12.0, 4.0 / 9.0, 1.0, 1.0];
        for (r, w) in (1..=5).zip(want) {
            assert_relative_eq!(d.of(r), w, max_relative = 1e-12);
        }
        let gap: BTreeMap<u64, u64> = [(1, 6), (3, 2)].into();
        assert_eq!(
            Discount::from_counts_of_counts(&gap),
            Discount::Absolute(0.5)
        );
    }
}
