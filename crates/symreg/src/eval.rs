//! Batched evaluation of postfix programs, and the Jacobian for constant fitting.
//!
//! Rows are processed in batches of [`BATCH`]: every node owns one batch buffer, filled in
//! postfix order by a tight loop per operator (Operon's design), so the per-node dispatch
//! cost is paid once per batch, not once per row. The Jacobian with respect to every
//! parameter comes from one reverse (adjoint) sweep over the same buffers: parameters sit
//! only at the leaves and the output, so the adjoint of a leaf times its input value is the
//! derivative with respect to its scale.
use crate::ops::Op;
use crate::program::{Node, Program};
use crate::vmath;

/// Rows per batch.
pub const BATCH: usize = 128;

/// Reusable evaluation state for one program.
#[derive(Debug, Clone)]
pub struct Evaluator {
    offsets: Vec<usize>,
    children: Vec<[usize; 2]>,
    vals: Vec<f64>,
    adj: Vec<f64>,
    jac: Vec<f64>,
    res: Vec<f64>,
    avx2: bool,
}

#[inline(always)]
fn unary(dst: &mut [f64], a: &[f64], f: impl Fn(f64) -> f64) {
    for (d, &x) in dst.iter_mut().zip(a) {
        *d = f(x);
    }
}

#[inline(always)]
fn binary(dst: &mut [f64], a: &[f64], b: &[f64], f: impl Fn(f64, f64) -> f64) {
    for ((d, &x), &y) in dst.iter_mut().zip(a).zip(b) {
        *d = f(x, y);
    }
}

#[inline(always)]
fn adjoint1(da: &mut [f64], ak: &[f64], va: &[f64], out: &[f64], d: impl Fn(f64, f64) -> f64) {
    for (((g, &a), &v), &o) in da.iter_mut().zip(ak).zip(va).zip(out) {
        *g = a * d(v, o);
    }
}

/// What a sweep reads: the program, its parameters (the output's scale and offset first)
/// and the input columns.
#[derive(Clone, Copy, Debug)]
pub struct Inputs<'a> {
    /// The program.
    pub prog: &'a Program,
    /// Its parameters, as [`Program::param_offsets`] lays them out.
    pub params: &'a [f64],
    /// The input columns, in the program's variable order.
    pub cols: &'a [&'a [f64]],
}

/// The normal equations of a least-squares problem: what the sweep reads, the parameters
/// that are free (indices into `inp.params`) and the target, and the system's buffers
/// (`jtj`: `free.len()` squared; `jtr`: `free.len()`).
struct NormalEquations<'a> {
    inp: Inputs<'a>,
    free: &'a [usize],
    y: &'a [f64],
    jtj: &'a mut [f64],
    jtr: &'a mut [f64],
}

/// The rows `0..n_rows` as batches `(start, len)` of at most [`BATCH`] rows.
fn batches(n_rows: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..n_rows)
        .step_by(BATCH)
        .map(move |start| (start, BATCH.min(n_rows - start)))
}

/// Whether the running CPU has AVX2 (always false off x86-64).
fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    // Eight accumulators in a fixed association order, so the result depends on the inputs
    // only (the compiler keeps them scalar; `dot4_avx2` computes the same sums in lanes).
    let mut s = [0.0f64; 8];
    let (ca, cb) = (a.chunks_exact(8), b.chunks_exact(8));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..8 {
            s[k] += x[k] * y[k];
        }
    }
    let mut t = ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
    for (x, y) in ra.iter().zip(rb) {
        t += x * y;
    }
    t
}

/// Adds one batch's share of the normal equations: `jtr[a] += dot(J_a, res)` and, for
/// `b <= a`, `jtj[a * m + b] += dot(J_a, J_b)`, where `J_p` is parameter `p`'s row of `jac`
/// (rows of [`BATCH`]) over the batch's `res.len()` rows. This is where a search spends most
/// of its time (`m (m + 3) / 2` dot products per batch for `m` free parameters), so with
/// AVX2 four dot products share each load of `J_a` ([`dot4_avx2`]); every dot product keeps
/// [`dot`]'s association order, so both paths give the same bits.
#[inline(always)]
fn gram(jac: &[f64], res: &[f64], free: &[usize], jtj: &mut [f64], jtr: &mut [f64], avx2: bool) {
    let len = res.len();
    let m = free.len();
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // the vectors row `a` meets: the residual (t = 0), then J_free[b] (t = b + 1)
        let vector = |t: usize| -> &[f64] {
            if t == 0 {
                res
            } else {
                let q = free[t - 1] * BATCH;
                &jac[q..q + len]
            }
        };
        for (a, &p) in free.iter().enumerate() {
            let jp = &jac[p * BATCH..p * BATCH + len];
            let last = a + 1;
            let mut t0 = 0;
            while t0 <= last {
                // a short last group repeats its last vector; the repeats are dropped
                let d = dot4_avx2(
                    jp,
                    vector(t0),
                    vector((t0 + 1).min(last)),
                    vector((t0 + 2).min(last)),
                    vector((t0 + 3).min(last)),
                );
                for (t, v) in (t0..=last).zip(d) {
                    if t == 0 {
                        jtr[a] += v;
                    } else {
                        jtj[a * m + t - 1] += v;
                    }
                }
                t0 += 4;
            }
        }
        return;
    }
    let _ = avx2;
    for (a, &p) in free.iter().enumerate() {
        let jp = &jac[p * BATCH..p * BATCH + len];
        jtr[a] += dot(jp, res);
        for (b, &q) in free[..=a].iter().enumerate() {
            jtj[a * m + b] += dot(jp, &jac[q * BATCH..q * BATCH + len]);
        }
    }
}

/// Four dot products of `a` with `b0..b3` (each at least as long as `a`), each
/// bit-identical to [`dot`]: lane `k` of a pair of 4-wide accumulators is `dot`'s
/// accumulator `s[k]`, updated by the same IEEE multiply and add (never fused), and the
/// lanes are summed in `dot`'s order. Call only when the CPU has AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn dot4_avx2(a: &[f64], b0: &[f64], b1: &[f64], b2: &[f64], b3: &[f64]) -> [f64; 4] {
    // SAFETY: the caller runs on a CPU with AVX2 (see `gram`).
    #[allow(unsafe_code)]
    unsafe {
        dot4_avx2_kernel(a, b0, b1, b2, b3)
    }
}

/// The body of [`dot4_avx2`]. Whole chunks of 8 (`as_chunks`) and value transmutes keep
/// the loop free of the checks that the dev profile (debug assertions on) adds to indexing
/// and to the load intrinsics' pointer copies.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
#[allow(unsafe_code)]
fn dot4_avx2_kernel(a: &[f64], b0: &[f64], b1: &[f64], b2: &[f64], b3: &[f64]) -> [f64; 4] {
    use std::arch::x86_64::{__m256d, _mm256_add_pd, _mm256_mul_pd, _mm256_setzero_pd};
    let n = a.len();
    let b = [&b0[..n], &b1[..n], &b2[..n], &b3[..n]];
    let (ac, ar) = a.as_chunks::<8>();
    let [c0, c1, c2, c3] = b.map(|v| v.as_chunks::<8>().0);
    // one chunk as two 4-lane vectors: lanes 0-3 and 4-7
    let lanes = |x: &[f64; 8]| -> [__m256d; 2] {
        // SAFETY: same size (64 bytes), and every bit pattern is a valid f64.
        unsafe { std::mem::transmute::<[f64; 8], [__m256d; 2]>(*x) }
    };
    // accumulators: lanes 0-3 and 4-7 of the chunks, one pair per `b`
    let mut acc = [[_mm256_setzero_pd(); 2]; 4];
    for ((((x, y0), y1), y2), y3) in ac.iter().zip(c0).zip(c1).zip(c2).zip(c3) {
        let [x0, x1] = lanes(x);
        for (a, y) in acc.iter_mut().zip([y0, y1, y2, y3]) {
            let [y_lo, y_hi] = lanes(y);
            a[0] = _mm256_add_pd(a[0], _mm256_mul_pd(x0, y_lo));
            a[1] = _mm256_add_pd(a[1], _mm256_mul_pd(x1, y_hi));
        }
    }
    // SAFETY: same size (4 x 64 bytes), and every bit pattern is a valid f64.
    let sums = unsafe { std::mem::transmute::<[[__m256d; 2]; 4], [[f64; 8]; 4]>(acc) };
    let n8 = n - ar.len();
    let mut out = [0.0; 4];
    for ((o, s), bj) in out.iter_mut().zip(&sums).zip(b) {
        let mut t = ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
        for (x, y) in ar.iter().zip(&bj[n8..]) {
            t += x * y;
        }
        *o = t;
    }
    out
}

/// The forward sweep over one batch: `vals[k * BATCH..][..len]` receives node `k`'s values.
#[inline(always)]
fn forward_impl(ev: &mut Evaluator, inp: Inputs, start: usize, len: usize) {
    let Inputs { prog, params, cols } = inp;
    let (offsets, children, vals) = (&ev.offsets, &ev.children, &mut ev.vals);
    for (k, node) in prog.nodes.iter().enumerate() {
        let (before, rest) = vals.split_at_mut(k * BATCH);
        let dst = &mut rest[..len];
        match *node {
            Node::Var(j) => {
                let x = &cols[j as usize][start..start + len];
                if prog.affine {
                    let w = params[offsets[k]];
                    let b = params[offsets[k] + 1];
                    unary(dst, x, |v| w * v + b);
                } else {
                    dst.copy_from_slice(x);
                }
            }
            Node::Const => dst.fill(params[offsets[k]]),
            Node::Op(op) => {
                let [c0, c1] = children[k];
                let a = &before[c0 * BATCH..c0 * BATCH + len];
                if op.arity() == 1 {
                    match op {
                        Op::Exp => unary(dst, a, vmath::exp),
                        Op::Log => unary(dst, a, |v| if v > 0.0 { vmath::ln(v) } else { f64::NAN }),
                        Op::Sqrt => unary(dst, a, f64::sqrt),
                        Op::Square => unary(dst, a, |v| v * v),
                        Op::Inverse => unary(dst, a, |v| 1.0 / v),
                        Op::Sin => {
                            unary(dst, a, vmath::sin_kernel);
                            vmath::trig_fixup(dst, a, |_, x| vmath::sin(x));
                        }
                        Op::Cos => {
                            unary(dst, a, vmath::cos_kernel);
                            vmath::trig_fixup(dst, a, |_, x| vmath::cos(x));
                        }
                        Op::Tanh => {
                            // a loop of its own: passed to `unary`, `tanh` (larger than the
                            // other kernels) was called per row, unvectorised
                            for (d, &x) in dst.iter_mut().zip(a) {
                                *d = vmath::tanh(x);
                            }
                        }
                        Op::Abs => unary(dst, a, f64::abs),
                        Op::Gaussian => unary(dst, a, |v| vmath::exp(-v * v)),
                        Op::Tan => unary(dst, a, f64::tan),
                        _ => dst.fill(f64::NAN),
                    }
                } else {
                    let b = &before[c1 * BATCH..c1 * BATCH + len];
                    match op {
                        Op::Add => binary(dst, a, b, |x, y| x + y),
                        Op::Sub => binary(dst, a, b, |x, y| x - y),
                        Op::Mul => binary(dst, a, b, |x, y| x * y),
                        Op::Div => binary(dst, a, b, |x, y| x / y),
                        Op::Gaussian2 => binary(dst, a, b, |x, y| vmath::exp(-(x * x + y * y))),
                        Op::Pow => binary(dst, a, b, f64::powf),
                        _ => dst.fill(f64::NAN),
                    }
                }
            }
        }
    }
}

/// [`forward_impl`] compiled for AVX2 (4 rows per instruction); chosen at run time.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn forward_avx2(ev: &mut Evaluator, inp: Inputs, start: usize, len: usize) {
    forward_impl(ev, inp, start, len);
}

impl Evaluator {
    /// Prepares evaluation of `prog`.
    pub fn new(prog: &Program) -> Self {
        let n = prog.nodes.len();
        Self {
            offsets: prog.param_offsets(),
            children: prog.children(),
            vals: vec![0.0; n * BATCH],
            adj: Vec::new(),
            jac: Vec::new(),
            res: vec![0.0; BATCH],
            avx2: has_avx2(),
        }
    }

    /// The same evaluator restricted to the portable (SSE2) code path, for tests that
    /// check that both code paths give the same bits.
    #[doc(hidden)]
    pub fn portable(mut self) -> Self {
        self.avx2 = false;
        self
    }

    fn forward(&mut self, inp: Inputs, start: usize, len: usize) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is set only when the running CPU reported AVX2 (see `new`).
            #[allow(unsafe_code)]
            unsafe {
                forward_avx2(self, inp, start, len);
            }
            return;
        }
        forward_impl(self, inp, start, len);
    }

    /// [`Self::forward`] on the batch at `start`, then its residuals
    /// `scale * root + offset - y` into `self.res[..len]`; returns their sum of squares.
    fn forward_residuals(&mut self, inp: Inputs, y: &[f64], start: usize, len: usize) -> f64 {
        self.forward(inp, start, len);
        let root = inp.prog.nodes.len() - 1;
        let (scale, offset) = (inp.params[0], inp.params[1]);
        let v = &self.vals[root * BATCH..root * BATCH + len];
        for i in 0..len {
            self.res[i] = scale * v[i] + offset - y[start + i];
        }
        dot(&self.res[..len], &self.res[..len])
    }

    /// Writes the program's output for all `n_rows` rows into `out`.
    pub fn predict(
        &mut self,
        prog: &Program,
        params: &[f64],
        cols: &[&[f64]],
        n_rows: usize,
        out: &mut Vec<f64>,
    ) {
        out.clear();
        out.reserve(n_rows);
        let root = prog.nodes.len() - 1;
        let (scale, offset) = (params[0], params[1]);
        for (start, len) in batches(n_rows) {
            self.forward(Inputs { prog, params, cols }, start, len);
            out.extend(
                self.vals[root * BATCH..root * BATCH + len]
                    .iter()
                    .map(|&v| scale * v + offset),
            );
        }
    }

    /// The root value (before the output map) on all `n_rows` rows.
    pub(crate) fn root_values(&mut self, inp: Inputs, n_rows: usize) -> Vec<f64> {
        let root = inp.prog.nodes.len() - 1;
        let mut out = Vec::with_capacity(n_rows);
        for (start, len) in batches(n_rows) {
            self.forward(inp, start, len);
            out.extend_from_slice(&self.vals[root * BATCH..root * BATCH + len]);
        }
        out
    }

    /// Mean squared error against `y`; `f64::INFINITY` if any prediction is not finite.
    pub fn mse(&mut self, prog: &Program, params: &[f64], cols: &[&[f64]], y: &[f64]) -> f64 {
        let n_rows = y.len();
        let mut sse = 0.0;
        for (start, len) in batches(n_rows) {
            sse += self.forward_residuals(Inputs { prog, params, cols }, y, start, len);
        }
        let m = sse / n_rows as f64;
        if m.is_finite() { m } else { f64::INFINITY }
    }

    /// Accumulates the Gauss-Newton normal equations `J^T J` (lower triangle, row-major,
    /// `free.len()` squared) and `J^T r` for the parameters listed in `free`, with
    /// residual `r = prediction - y`. Returns the mean squared error (`INFINITY` if not finite).
    pub fn normal_equations(
        &mut self,
        inp: Inputs<'_>,
        free: &[usize],
        y: &[f64],
        jtj: &mut [f64],
        jtr: &mut [f64],
    ) -> f64 {
        let ne = NormalEquations {
            inp,
            free,
            y,
            jtj,
            jtr,
        };
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is set only when the running CPU reported AVX2 (see `new`).
            #[allow(unsafe_code)]
            return unsafe { self.normal_equations_avx2(ne) };
        }
        self.normal_equations_impl(ne)
    }

    /// [`Self::normal_equations_impl`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn normal_equations_avx2(&mut self, ne: NormalEquations) -> f64 {
        self.normal_equations_impl(ne)
    }

    #[inline(always)]
    fn normal_equations_impl(&mut self, ne: NormalEquations) -> f64 {
        let NormalEquations {
            inp,
            free,
            y,
            jtj,
            jtr,
        } = ne;
        jtj.fill(0.0);
        jtr.fill(0.0);
        self.adj.resize(inp.prog.nodes.len() * BATCH, 0.0);
        self.jac.resize(inp.params.len() * BATCH, 0.0);
        let n_rows = y.len();
        let mut sse = 0.0;
        for (start, len) in batches(n_rows) {
            sse += self.forward_residuals(inp, y, start, len);
            self.backward(inp, start, len);
            gram(&self.jac, &self.res[..len], free, jtj, jtr, self.avx2);
        }
        let mse = sse / n_rows as f64;
        if mse.is_finite() && jtj.iter().all(|v| v.is_finite()) && jtr.iter().all(|v| v.is_finite())
        {
            mse
        } else {
            f64::INFINITY
        }
    }

    /// The adjoint sweep after [`Self::forward`] on rows `start..start + len`: fills
    /// `self.jac` (`n_params` rows of `BATCH`) with the derivative of the prediction with
    /// respect to every parameter. Inlined into both code paths of the normal equations.
    #[inline(always)]
    fn backward(&mut self, inp: Inputs, start: usize, len: usize) {
        let Inputs { prog, params, cols } = inp;
        let n = prog.nodes.len();
        let root = n - 1;
        let scale = params[0];
        // adjoints
        self.adj[root * BATCH..root * BATCH + len].fill(scale);
        for k in (0..n).rev() {
            let node = prog.nodes[k];
            let (before, rest) = self.adj.split_at_mut(k * BATCH);
            let ak = &rest[..len];
            match node {
                Node::Op(op) => {
                    let [c0, c1] = self.children[k];
                    let out = &self.vals[k * BATCH..k * BATCH + len];
                    let va = &self.vals[c0 * BATCH..c0 * BATCH + len];
                    if op.arity() == 1 {
                        let da = &mut before[c0 * BATCH..c0 * BATCH + len];
                        match op {
                            Op::Exp => adjoint1(da, ak, va, out, |_, o| o),
                            Op::Square => adjoint1(da, ak, va, out, |a, _| 2.0 * a),
                            Op::Gaussian => adjoint1(da, ak, va, out, |a, o| -2.0 * a * o),
                            Op::Sin => {
                                adjoint1(da, ak, va, out, |a, _| vmath::cos_kernel(a));
                                vmath::trig_fixup(da, va, |i, v| ak[i] * vmath::cos(v));
                            }
                            Op::Cos => {
                                adjoint1(da, ak, va, out, |a, _| -vmath::sin_kernel(a));
                                vmath::trig_fixup(da, va, |i, v| ak[i] * -vmath::sin(v));
                            }
                            Op::Tanh => adjoint1(da, ak, va, out, |_, o| 1.0 - o * o),
                            Op::Inverse => adjoint1(da, ak, va, out, |_, o| -o * o),
                            Op::Log => adjoint1(da, ak, va, out, |a, _| 1.0 / a),
                            Op::Sqrt => adjoint1(da, ak, va, out, |_, o| 0.5 / o),
                            _ => adjoint1(da, ak, va, out, |a, o| op.d1(a, o)),
                        }
                    } else {
                        let vb = &self.vals[c1 * BATCH..c1 * BATCH + len];
                        let (lo, hi) = before.split_at_mut(c1 * BATCH);
                        let da = &mut lo[c0 * BATCH..c0 * BATCH + len];
                        let db = &mut hi[..len];
                        match op {
                            Op::Add => {
                                da.copy_from_slice(ak);
                                db.copy_from_slice(ak);
                            }
                            Op::Sub => {
                                da.copy_from_slice(ak);
                                unary(db, ak, |g| -g);
                            }
                            Op::Mul => {
                                binary(da, ak, vb, |g, b| g * b);
                                binary(db, ak, va, |g, a| g * a);
                            }
                            Op::Div => {
                                binary(da, ak, vb, |g, b| g / b);
                                for (((d, &g), &b), &o) in db.iter_mut().zip(ak).zip(vb).zip(out) {
                                    *d = -g * o / b;
                                }
                            }
                            _ => {
                                for i in 0..len {
                                    let (ga, gb) = op.d2(va[i], vb[i], out[i]);
                                    da[i] = ak[i] * ga;
                                    db[i] = ak[i] * gb;
                                }
                            }
                        }
                    }
                }
                Node::Var(j) => {
                    if prog.affine {
                        let p = self.offsets[k];
                        let x = &cols[j as usize][start..start + len];
                        let (jw, jb) = self.jac[p * BATCH..(p + 2) * BATCH].split_at_mut(BATCH);
                        for i in 0..len {
                            jw[i] = ak[i] * x[i];
                            jb[i] = ak[i];
                        }
                    }
                }
                Node::Const => {
                    let p = self.offsets[k];
                    self.jac[p * BATCH..p * BATCH + len].copy_from_slice(ak);
                }
            }
        }
        {
            let (j01, _) = self.jac.split_at_mut(2 * BATCH);
            let (js, jo) = j01.split_at_mut(BATCH);
            js[..len].copy_from_slice(&self.vals[root * BATCH..root * BATCH + len]);
            jo[..len].fill(1.0);
        }
    }

    /// The Jacobian of the prediction with respect to the parameters listed in `free`, on
    /// all `n_rows` rows, row-major (`n_rows x free.len()`) into `out`: the same adjoint
    /// sweep as [`Self::normal_equations`], row by row instead of summed. Used for the
    /// uncertainty of a prediction (the delta method).
    pub fn jacobian(
        &mut self,
        prog: &Program,
        params: &[f64],
        free: &[usize],
        cols: &[&[f64]],
        n_rows: usize,
        out: &mut Vec<f64>,
    ) {
        let n = prog.nodes.len();
        let m = free.len();
        out.clear();
        out.resize(n_rows * m, 0.0);
        self.adj.resize(n * BATCH, 0.0);
        self.jac.resize(params.len() * BATCH, 0.0);
        let inp = Inputs { prog, params, cols };
        for (start, len) in batches(n_rows) {
            self.forward(inp, start, len);
            self.backward(inp, start, len);
            for (a, &p) in free.iter().enumerate() {
                for i in 0..len {
                    out[(start + i) * m + a] = self.jac[p * BATCH + i];
                }
            }
        }
    }
}
