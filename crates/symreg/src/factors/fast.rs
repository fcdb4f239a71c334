//! FAST (Lou, Caruana, Gehrke and Hooker 2013, "Accurate intelligible models with pairwise
//! interactions", the ranking InterpretML's EBM uses): every pair of columns ranked by how
//! much of the main factors' residual a two-by-two piecewise-constant cut of the pair
//! explains, so that only the few best pairs are fitted and cross-validated (issue 68).
//!
//! Each column is cut into at most [`FAST_BINS`] bins of equal counts (a column with fewer
//! distinct values gets one bin per value). For a pair, the residual's sums and counts over
//! the bins' grid are accumulated once; every cut `(a, b)` splits the grid into four
//! quadrants, each predicting its mean, and the cut's gain is `sum_q S_q^2 / N_q` less the
//! overall mean's `S^2 / N` (the fall of the residual sum of squares). A pair's score is its
//! best cut's gain, found in `O(bins^2)` from prefix sums. The arithmetic is serial per pair,
//! so the ranking never depends on the thread count.

/// Most bins per column (the paper's and EBM's order of magnitude for the ranking).
pub(crate) const FAST_BINS: usize = 32;

/// Each row's bin of `x` (equal-count bins over its sorted values, at most `bins`; equal
/// values always share a bin) and the number of bins.
pub(crate) fn bin_of(x: &[f64], bins: usize) -> (Vec<usize>, usize) {
    let n = x.len();
    if n == 0 {
        return (Vec::new(), 0);
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
    let mut out = vec![0usize; n];
    let (mut bin, mut start) = (0usize, 0usize);
    let per = n.div_ceil(bins.max(1));
    for k in 0..n {
        let i = order[k];
        // a new bin once the current one holds its share and the value changes
        if k > start && k - start >= per && x[i] != x[order[k - 1]] {
            bin += 1;
            start = k;
        }
        out[i] = bin;
    }
    (out, bin + 1)
}

/// The FAST gain of the pair with bins `(ba, na)` and `(bb, nb)` on the residual `r`: the
/// largest fall of the residual sum of squares by one cut of each column.
pub(crate) fn pair_gain(ba: &[usize], na: usize, bb: &[usize], nb: usize, r: &[f64]) -> f64 {
    if na < 2 || nb < 2 {
        return 0.0;
    }
    // prefix sums over the grid: p[(a + 1) * (nb + 1) + (b + 1)] = sum over bins <= (a, b)
    let w = nb + 1;
    let mut s = vec![0.0f64; (na + 1) * w];
    let mut c = vec![0.0f64; (na + 1) * w];
    for ((&a, &b), &v) in ba.iter().zip(bb).zip(r) {
        s[(a + 1) * w + b + 1] += v;
        c[(a + 1) * w + b + 1] += 1.0;
    }
    for a in 1..=na {
        for b in 1..=nb {
            let k = a * w + b;
            s[k] += s[k - w] + s[k - 1] - s[k - w - 1];
            c[k] += c[k - w] + c[k - 1] - c[k - w - 1];
        }
    }
    let (st, ct) = (s[na * w + nb], c[na * w + nb]);
    if ct <= 0.0 {
        return 0.0;
    }
    let base = st * st / ct;
    let term = |sum: f64, cnt: f64| if cnt > 0.0 { sum * sum / cnt } else { 0.0 };
    let mut best = 0.0f64;
    for a in 1..na {
        for b in 1..nb {
            let (sll, cll) = (s[a * w + b], c[a * w + b]);
            let (sla, cla) = (s[a * w + nb], c[a * w + nb]);
            let (slb, clb) = (s[na * w + b], c[na * w + b]);
            let g = term(sll, cll)
                + term(sla - sll, cla - cll)
                + term(slb - sll, clb - cll)
                + term(st - sla - slb + sll, ct - cla - clb + cll)
                - base;
            if g > best {
                best = g;
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gain equals the fall of the residual sum of squares of the best four-quadrant
    /// model, found here by brute force over every cut.
    #[test]
    fn the_gain_is_the_best_cuts_fall_of_the_squared_error() {
        let n = 200;
        let x: Vec<f64> = (0..n).map(|i| f64::from((i * 37 % 101) as u32)).collect();
        let z: Vec<f64> = (0..n).map(|i| f64::from((i * 53 % 89) as u32)).collect();
        let r: Vec<f64> = (0..n)
            .map(|i| {
                let hi = x[i] > 60.0 && z[i] > 30.0;
                f64::from(u32::from(hi)) + 0.01 * f64::from((i % 7) as u32)
            })
            .collect();
        let (ba, na) = bin_of(&x, 8);
        let (bb, nb) = bin_of(&z, 8);
        let got = pair_gain(&ba, na, &bb, nb, &r);
        let sse = |rows: &[usize]| -> f64 {
            let m = rows.iter().map(|&i| r[i]).sum::<f64>() / rows.len().max(1) as f64;
            rows.iter().map(|&i| (r[i] - m).powi(2)).sum()
        };
        let all: Vec<usize> = (0..n).collect();
        let mut best = 0.0f64;
        for a in 1..na {
            for b in 1..nb {
                let q = |lo_a: bool, lo_b: bool| -> Vec<usize> {
                    (0..n)
                        .filter(|&i| (ba[i] < a) == lo_a && (bb[i] < b) == lo_b)
                        .collect()
                };
                let split = sse(&q(true, true))
                    + sse(&q(true, false))
                    + sse(&q(false, true))
                    + sse(&q(false, false));
                best = best.max(sse(&all) - split);
            }
        }
        assert!(
            (got - best).abs() <= 1e-9 * best.max(1.0),
            "{got} vs {best}"
        );
        // a residual unrelated to the pair's quadrants gains far less
        let flat: Vec<f64> = (0..n).map(|i| 0.01 * f64::from((i % 7) as u32)).collect();
        assert!(pair_gain(&ba, na, &bb, nb, &flat) < 0.01 * got);
    }

    #[test]
    fn bins_have_equal_counts_and_equal_values_share_one() {
        let x: Vec<f64> = (0..100).map(|i| f64::from(i / 10)).collect();
        let (b, n) = bin_of(&x, 4);
        assert!(n <= 5, "{n}");
        for i in 1..100 {
            if x[i] == x[i - 1] {
                assert_eq!(b[i], b[i - 1]);
            }
        }
        let (b, n) = bin_of(&[3.0, 1.0, 2.0], 32);
        assert_eq!((b, n), (vec![2, 0, 1], 3));
    }
}
