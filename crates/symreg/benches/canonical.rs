//! Cost of a structure key (`hxai_symreg::canonical`): one call over each of the seeded
//! random programs of complexity up to 10 (inputs plus operators) from `bench_programs`,
//! with affine inputs as in a search and without, under each `Effort`. Criterion reports the
//! time of the whole set; divide by the program count printed in the benchmark id for the
//! mean per call.
#![allow(missing_docs)]
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use hxai_symreg::ComplexityMeasure;
use hxai_symreg::canonical::{Effort, structure_with};

fn bench(c: &mut Criterion) {
    let names: Vec<String> = vec!["x0".into(), "x1".into(), "x2".into()];
    let mut g = c.benchmark_group("structure_key");
    g.sample_size(10);
    for affine in [true, false] {
        let progs: Vec<_> = if affine {
            hxai_symreg::bench_programs::affine_programs(400, 11)
        } else {
            hxai_symreg::bench_programs::programs(400, 11)
        };
        let progs: Vec<_> = progs
            .into_iter()
            .map(|(p, _)| p)
            .filter(|p| p.complexity(ComplexityMeasure::FeaturesPlusOperators) <= 10)
            .collect();
        for effort in [Effort::Full, Effort::Fast] {
            let id = format!(
                "{}/{effort:?}/{} programs",
                if affine { "affine" } else { "plain" },
                progs.len()
            );
            g.bench_with_input(BenchmarkId::from_parameter(id), &progs, |b, progs| {
                b.iter(|| {
                    progs
                        .iter()
                        .map(|p| structure_with(p, &names, effort).nodes)
                        .sum::<usize>()
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
