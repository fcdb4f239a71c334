//! Which fitted constants the data determine: the null directions of `J^T J` (issue 63: a
//! level of a per-class constant without training rows dropped every parameter's standard
//! error, where only its own is undetermined).
use crate::uncertainty::{SINGULAR_RCOND, jacobi_eigen};

/// How much of a null direction of `J^T J` (after scaling to unit diagonal) an unknown
/// may carry and still count as determined: a direction's eigenvector is a unit vector, so
/// a loading of 1e-3 is a millionth of its weight, far above rounding (1e-16) and far below
/// the loadings of unknowns that really trade off (1/sqrt(2) for a product `a*b`).
const NULL_LOADING: f64 = 1e-3;

/// Which unknowns the data determine, from `jtj` (`J^T J`, `k x k`, row-major): an unknown
/// is undetermined when it does not change the prediction (a zero or non-finite diagonal)
/// or when it carries weight in a direction `J^T J` does not see (an eigenvalue at most
/// `1e-12` of the largest after scaling to unit diagonal, as the pseudo-inverse of the
/// delta method cuts). `a*b*x` leaves both `a` and `b` undetermined; a level of a
/// per-class constant without rows leaves that one alone undetermined, and the others'
/// standard errors can still be given.
pub fn determined(jtj: &[f64], k: usize) -> Vec<bool> {
    let d: Vec<f64> = (0..k)
        .map(|i| {
            let v = jtj[i * k + i];
            if v > 0.0 && v.is_finite() {
                1.0 / v.sqrt()
            } else {
                0.0
            }
        })
        .collect();
    let mut out: Vec<bool> = d.iter().map(|&v| v > 0.0).collect();
    let live: Vec<usize> = (0..k).filter(|&i| out[i]).collect();
    let m = live.len();
    if m == 0 {
        return out;
    }
    let mut s: Vec<f64> = (0..m * m)
        .map(|ij| {
            let (a, b) = (live[ij / m], live[ij % m]);
            jtj[a * k + b] * d[a] * d[b]
        })
        .collect();
    if s.iter().any(|v| !v.is_finite()) {
        return vec![false; k];
    }
    let mut v = vec![0.0; m * m];
    for i in 0..m {
        v[i * m + i] = 1.0;
    }
    jacobi_eigen(&mut s, &mut v, m);
    let lambda: Vec<f64> = (0..m).map(|i| s[i * m + i]).collect();
    let cut = lambda.iter().copied().fold(0.0, f64::max) * SINGULAR_RCOND;
    for (e, &l) in lambda.iter().enumerate() {
        if l > cut {
            continue;
        }
        for (i, &u) in live.iter().enumerate() {
            if v[i * m + e].abs() > NULL_LOADING {
                out[u] = false;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::determined;

    /// `J^T J` of `J`'s columns (rows of `j`, `k` unknowns).
    fn jtj(j: &[Vec<f64>], k: usize) -> Vec<f64> {
        let mut a = vec![0.0; k * k];
        for row in j {
            for p in 0..k {
                for q in 0..k {
                    a[p * k + q] += row[p] * row[q];
                }
            }
        }
        a
    }

    /// A product `a*b*x` at a = b = 1: the columns of `J` are both `x`, so neither is
    /// determined; a third unknown `c` (an offset) is; an unknown that moves nothing is not.
    #[test]
    fn a_product_and_a_dead_unknown_are_undetermined_the_rest_are() {
        let x = [1.0, 2.0, 3.0, 4.5];
        let j: Vec<Vec<f64>> = x.iter().map(|&v| vec![v, v, 1.0, 0.0]).collect();
        assert_eq!(determined(&jtj(&j, 4), 4), [false, false, true, false]);
        // a line a + b*x is fully determined, however different the scales
        let j: Vec<Vec<f64>> = x.iter().map(|&v| vec![1.0, 1e6 * v]).collect();
        assert_eq!(determined(&jtj(&j, 2), 2), [true, true]);
    }
}
