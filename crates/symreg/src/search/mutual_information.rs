//! Prior weights of the inputs: how strongly each column, on its own, tells about the
//! target. The generators draw inputs in proportion to them before the strategies have
//! learnt anything (QLattice's mutual-information prior).

/// Equal-count bins per variable. With the default 2,000 fitting rows the 16 x 16 joint
/// histogram holds about 8 rows per cell: enough to rank inputs, which is all the prior
/// needs, before the estimate's small-sample upward bias swamps the differences.
const MI_BINS: usize = 16;

/// Floor added to every input's normalised mutual information. An input that tells nothing
/// on its own may still matter in a product or a difference (the `v` and `c` of
/// `sqrt(1 - v^2/c^2)`), so it keeps about a tenth of the best input's chance to be drawn
/// (QLattice's rank rule `max(0.1, 1 - rank/100)` uses the same floor).
const INPUT_PRIOR_FLOOR: f64 = 0.1;

/// Sampling weight of each input: `INPUT_PRIOR_FLOOR + mi / max_mi`, so the most
/// informative input weighs `1.1` and none weighs less than `0.1`; all `1.0` when no input
/// carries information (or the target is binned into one class).
pub(crate) fn input_priors(cols: &[&[f64]], y: &[f64]) -> Vec<f64> {
    let mi = mutual_information(cols, y);
    let max_mi = mi.iter().cloned().fold(0.0, f64::max);
    mi.iter()
        .map(|&m| {
            if max_mi > 0.0 {
                INPUT_PRIOR_FLOOR + m / max_mi
            } else {
                1.0
            }
        })
        .collect()
}

/// Mutual information (nats) between each column and the target, from [`MI_BINS`]
/// equal-count bins (ties share a bin, so the estimate does not depend on row order).
pub(crate) fn mutual_information(cols: &[&[f64]], y: &[f64]) -> Vec<f64> {
    const B: usize = MI_BINS;
    let bins = |v: &[f64]| -> Vec<usize> {
        let mut idx: Vec<usize> = (0..v.len()).collect();
        idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
        let mut out = vec![0; v.len()];
        let mut rank = 0;
        let mut i = 0;
        while i < idx.len() {
            let mut j = i;
            while j + 1 < idx.len() && v[idx[j + 1]] == v[idx[i]] {
                j += 1;
            }
            for &k in &idx[i..=j] {
                out[k] = (rank * B / v.len()).min(B - 1);
            }
            rank += j - i + 1;
            i = j + 1;
        }
        out
    };
    let by = bins(y);
    let n = y.len() as f64;
    cols.iter()
        .map(|c| {
            let bx = bins(c);
            let mut joint = [[0.0f64; B]; B];
            let mut px = [0.0f64; B];
            let mut py = [0.0f64; B];
            for (&a, &b) in bx.iter().zip(&by) {
                joint[a][b] += 1.0;
                px[a] += 1.0;
                py[b] += 1.0;
            }
            let mut mi = 0.0;
            for a in 0..B {
                for b in 0..B {
                    if joint[a][b] > 0.0 {
                        mi += joint[a][b] / n * (joint[a][b] * n / (px[a] * py[b])).ln();
                    }
                }
            }
            mi
        })
        .collect()
}
