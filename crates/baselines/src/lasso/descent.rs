//! The coordinate-descent solvers of scikit-learn's `_cd_fast.pyx` (formulation A,
//! `beta = 0`): the plain solver on the residual and the Gram-matrix solver on `X^T X`, one
//! loop with gap-safe screening shared by both. [`Lasso`](super::Lasso) calls the first,
//! [`LassoCv`](super::LassoCv) the second on each fold's alpha path.

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn abs_max(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Duality gap of formulation A (`beta = 0`, `alpha > 0`).
fn gap_a(alpha: f64, w_l1: f64, r_norm2: f64, ry: f64, dual_norm: f64) -> f64 {
    let primal = 0.5 * r_norm2 + alpha * w_l1;
    let scale = if dual_norm > alpha {
        alpha / dual_norm
    } else {
        1.0
    };
    let dual = -0.5 * scale * scale * r_norm2 + scale * ry;
    primal - dual
}

/// What the two solvers of `_cd_fast.pyx` keep between coordinate updates: the residual
/// `r = y - X w` ([`Plain`]) or `Q w` with the Gram matrix `Q = X^T X` ([`Gram`]). The loop
/// around them, [`descend`], is the same for both.
trait CdState {
    /// The Gram solver takes the duality gap's absolute value for the screening radius and
    /// does not stop early on a negative gap (scikit-learn's two solvers differ there).
    const GAP_ABS: bool;
    /// `||x_j||^2`.
    fn norm2(&self, j: usize) -> f64;
    /// `x_j^T r`.
    fn xr(&self, j: usize) -> f64;
    /// Applies `w_j += d` to the kept state.
    fn shift(&mut self, j: usize, d: f64);
    /// Duality gap and dual norm at `w`; fills `xta` with `X^T r`.
    fn gap(&self, w: &[f64], alpha: f64, xta: &mut [f64]) -> (f64, f64);
}

/// Residual state of `enet_coordinate_descent`: centred columns, centred target.
struct Plain<'a> {
    cols: &'a [Vec<f64>],
    y: &'a [f64],
    norm2: Vec<f64>,
    r: Vec<f64>,
}

impl CdState for Plain<'_> {
    const GAP_ABS: bool = false;
    fn norm2(&self, j: usize) -> f64 {
        self.norm2[j]
    }
    fn xr(&self, j: usize) -> f64 {
        dot(&self.cols[j], &self.r)
    }
    fn shift(&mut self, j: usize, d: f64) {
        self.r
            .iter_mut()
            .zip(&self.cols[j])
            .for_each(|(ri, xi)| *ri -= d * xi);
    }
    fn gap(&self, w: &[f64], alpha: f64, xta: &mut [f64]) -> (f64, f64) {
        for (j, c) in self.cols.iter().enumerate() {
            xta[j] = dot(c, &self.r);
        }
        let dual_norm = abs_max(xta);
        let w_l1: f64 = w.iter().map(|v| v.abs()).sum();
        let r = &self.r;
        (
            gap_a(alpha, w_l1, dot(r, r), dot(r, self.y), dual_norm),
            dual_norm,
        )
    }
}

/// Gram state of `enet_coordinate_descent_gram`: `Q` (`p x p`, row-major), `q = X^T y`,
/// `y^T y`, and `Q w`.
struct Gram<'a> {
    q_mat: &'a [f64],
    q: &'a [f64],
    y_norm2: f64,
    qw: Vec<f64>,
}

impl Gram<'_> {
    fn row(&self, j: usize) -> &[f64] {
        let p = self.q.len();
        &self.q_mat[j * p..(j + 1) * p]
    }
}

impl CdState for Gram<'_> {
    const GAP_ABS: bool = true;
    fn norm2(&self, j: usize) -> f64 {
        self.q_mat[j * self.q.len() + j]
    }
    fn xr(&self, j: usize) -> f64 {
        self.q[j] - self.qw[j]
    }
    fn shift(&mut self, j: usize, d: f64) {
        let p = self.q.len();
        let row = &self.q_mat[j * p..(j + 1) * p];
        self.qw.iter_mut().zip(row).for_each(|(a, b)| *a += d * b);
    }
    fn gap(&self, w: &[f64], alpha: f64, xta: &mut [f64]) -> (f64, f64) {
        let q_dot_w = dot(w, self.q);
        let wqw = dot(w, &self.qw);
        let r_norm2 = self.y_norm2 + wqw - 2.0 * q_dot_w;
        let ry = self.y_norm2 - q_dot_w;
        for (j, x) in xta.iter_mut().enumerate() {
            *x = self.q[j] - self.qw[j];
        }
        let dual_norm = abs_max(xta);
        let w_l1: f64 = w.iter().map(|v| v.abs()).sum();
        (gap_a(alpha, w_l1, r_norm2, ry, dual_norm), dual_norm)
    }
}

/// The coordinates gap-safe screening keeps (`active`, in order) and those it has ruled out.
struct Screening {
    active: Vec<usize>,
    excluded: Vec<bool>,
}

/// Gap-safe screening: keeps in `sc.active` the coordinates the gap cannot rule out and
/// zeroes the others (on the first call, also those with a zero column).
fn screen<S: CdState>(
    s: &mut S,
    w: &mut [f64],
    sc: &mut Screening,
    alpha: f64,
    (gap, dual_norm): (f64, f64),
    xta: &[f64],
    first: bool,
) {
    let Screening { active, excluded } = sc;
    let radius = (2.0 * if S::GAP_ABS { gap.abs() } else { gap }).sqrt() / alpha;
    active.clear();
    for j in 0..w.len() {
        let norm2 = s.norm2(j);
        if first && norm2 == 0.0 {
            w[j] = 0.0;
            excluded[j] = true;
            continue;
        }
        if !first && excluded[j] {
            continue;
        }
        let xj_theta = xta[j] / alpha.max(dual_norm);
        let d_j = (1.0 - xj_theta.abs()) / norm2.sqrt();
        if d_j <= radius {
            active.push(j);
            excluded[j] = false;
        } else {
            if w[j] != 0.0 {
                s.shift(j, -w[j]);
                w[j] = 0.0;
            }
            excluded[j] = true;
        }
    }
}

/// The coordinate-descent loop of `_cd_fast.pyx` (formulation A, `beta = 0`) on either
/// state: `gap_tol` is `tol` times `||y||^2`, `d_w_tol` the relative-update tolerance.
/// Returns whether the gap reached its tolerance.
fn descend<S: CdState>(
    s: &mut S,
    w: &mut [f64],
    alpha: f64,
    max_iter: usize,
    d_w_tol: f64,
    gap_tol: f64,
) -> bool {
    let p = w.len();
    let mut xta = vec![0.0; p];
    let screening = alpha != 0.0;
    let mut gap = s.gap(w, alpha, &mut xta);
    if gap.0 <= gap_tol && (!S::GAP_ABS || gap.0 >= 0.0) {
        return true;
    }
    let mut sc = Screening {
        active: (0..p).collect(),
        excluded: vec![false; p],
    };
    if screening {
        screen(s, w, &mut sc, alpha, gap, &xta, true);
    }
    for n_iter in 0..max_iter {
        let mut w_max = 0.0f64;
        let mut d_w_max = 0.0f64;
        for &j in &sc.active {
            let norm2 = s.norm2(j);
            if norm2 == 0.0 {
                continue;
            }
            let w_j = w[j];
            let tmp = s.xr(j) + w_j * norm2;
            w[j] = if tmp == 0.0 {
                0.0
            } else {
                tmp.signum() * (tmp.abs() - alpha).max(0.0) / norm2
            };
            if w[j] != w_j {
                s.shift(j, w[j] - w_j);
            }
            d_w_max = d_w_max.max((w[j] - w_j).abs());
            w_max = w_max.max(w[j].abs());
        }
        if w_max == 0.0 || d_w_max / w_max <= d_w_tol || n_iter == max_iter - 1 {
            gap = s.gap(w, alpha, &mut xta);
            if gap.0 <= gap_tol {
                return true;
            }
            if screening {
                screen(s, w, &mut sc, alpha, gap, &xta, false);
            }
        }
    }
    false
}

/// `enet_coordinate_descent` with `beta = 0`: columns `cols` (centred), target `y`
/// (centred), penalty `alpha` already multiplied by `n`. Returns whether the gap reached
/// the tolerance.
pub(crate) fn cd_plain(
    w: &mut [f64],
    alpha: f64,
    cols: &[Vec<f64>],
    y: &[f64],
    max_iter: usize,
    tol: f64,
) -> bool {
    let mut r: Vec<f64> = y.to_vec();
    for (c, wj) in cols.iter().zip(w.iter()) {
        if *wj != 0.0 {
            r.iter_mut().zip(c).for_each(|(ri, xi)| *ri -= wj * xi);
        }
    }
    let mut s = Plain {
        cols,
        y,
        norm2: cols.iter().map(|c| dot(c, c)).collect(),
        r,
    };
    descend(&mut s, w, alpha, max_iter, tol, tol * dot(y, y))
}

/// `enet_coordinate_descent_gram` with `beta = 0`: Gram matrix `q_mat` (`p x p`, row-major,
/// of the centred columns), `q = X^T y`, `y_norm2 = y^T y`.
pub(crate) fn cd_gram(
    w: &mut [f64],
    alpha: f64,
    q_mat: &[f64],
    q: &[f64],
    y_norm2: f64,
    max_iter: usize,
    tol: f64,
) -> bool {
    let mut s = Gram {
        q_mat,
        q,
        y_norm2,
        qw: Vec::new(),
    };
    s.qw = (0..q.len()).map(|j| dot(s.row(j), w)).collect();
    descend(&mut s, w, alpha, max_iter, tol, tol * y_norm2)
}
