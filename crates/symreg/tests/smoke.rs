#![allow(clippy::unwrap_used, clippy::print_stdout)]
use hxai_symreg::*;
#[test]
fn smoke() {
    let n = 400;
    let x1: Vec<f64> = (0..n).map(|i| 1.0 + (i * 37 % 101) as f64 / 25.0).collect();
    let x2: Vec<f64> = (0..n).map(|i| 1.0 + (i * 53 % 97) as f64 / 30.0).collect();
    let y: Vec<f64> = x1.iter().zip(&x2).map(|(a, b)| a * b / (b * b)).collect();
    let data = Dataset::new(vec!["x1".into(), "x2".into()], vec![x1, x2]).unwrap();
    let t = std::time::Instant::now();
    let res = search(&data, &y, &SearchConfig::default(), &mut |p| {
        println!("{p:?}")
    })
    .unwrap();
    println!("{:?}", t.elapsed());
    println!(
        "best {} | {} | c={} mse={}",
        res.best.equation(),
        res.best.sympy(),
        res.best.complexity(),
        res.best.train_mse
    );
    for m in &res.pareto {
        println!(
            "  c={} mse={:.3e} {}",
            m.complexity,
            m.train_mse,
            m.equation()
        );
    }
}
