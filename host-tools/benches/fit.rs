//! `cargo bench -p host-tools --bench fit`: the full GSA fit at N = T = 100
//! (moment-form objective vs sample-by-sample), and least squares, on the
//! bundled MTS data (6 branches), on the simulated drop campaign
//! `data/drop-none` (the paper's 5 currents × 2 branches, 7819 samples: the
//! data set of the two-box benchmark) and on a 10-branch synthetic set (the
//! paper's Table 4 loops, 2000 samples each).
use criterion::{criterion_group, criterion_main, Criterion};
use mre_algorithm::model::Branch;
use mre_host::dataset::{BranchSamples, Dataset};
use mre_host::fit::bounds::data_bounds;
use mre_host::fit::gsa::{minimize, GsaParams};
use mre_host::fit::objective::rmse_by_samples;
use mre_host::fit::problems::{branch_problems, BranchProblem};
use mre_host::fit::{branch_rng, branch_stream, fit_branches, FitOptions, Method};
use rayon::prelude::*;
use std::hint::black_box;

fn bundled(name: &str) -> Vec<BranchProblem> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(name);
    branch_problems(&Dataset::load(&dir).expect("bundled data loads")).expect("bundled data has fit branches")
}

/// The paper's Table 4 loops, 2000 samples per branch over 0..0.88 mm.
fn paper_ten_branches() -> Vec<BranchProblem> {
    let table = mre_algorithm::table::Table::paper().expect("paper table");
    let mut out = Vec::new();
    for e in table.entries() {
        for branch in [Branch::Compression, Branch::Extension] {
            let x_mm: Vec<f64> = (0..2000).map(|i| 0.88 * i as f64 / 1999.0).collect();
            let force_n = x_mm
                .iter()
                .enumerate()
                .map(|(i, &x)| e.force_n(x as f32, branch).force_n as f64 + 30.0 * ((i * 7919) as f64).sin())
                .collect();
            out.push(BranchProblem {
                current_a: e.current_a as f64,
                branch,
                samples: BranchSamples { x_mm, force_n },
            });
        }
    }
    out
}

/// GSA with the sample-by-sample objective, same RNG streams as `fit_branches`.
fn gsa_by_samples(problems: &[BranchProblem], params: &GsaParams) -> f64 {
    problems
        .par_iter()
        .map(|p| {
            let (x, f) = (&p.samples.x_mm, &p.samples.force_n);
            let b = data_bounds(x, f).expect("bounds");
            minimize(
                |c| rmse_by_samples(x, f, c),
                &b,
                params,
                &mut branch_rng(params.seed, branch_stream(p.current_a, p.branch)),
                || {},
            )
            .best_value
        })
        .sum()
}

fn bench(c: &mut Criterion) {
    let gsa = FitOptions {
        method: Method::Gsa,
        ..Default::default()
    };
    let lsq = FitOptions {
        method: Method::Lsq,
        ..Default::default()
    };
    for (name, problems) in [
        ("mts_6_branches", bundled("mr-damper-mts")),
        ("drop_none_10_branches", bundled("drop-none")),
        ("paper_10_branches", paper_ten_branches()),
    ] {
        let mut g = c.benchmark_group(name);
        g.sample_size(10);
        g.bench_function("gsa_moment_form", |b| {
            b.iter(|| black_box(fit_branches(&problems, &gsa).expect("fit")))
        });
        g.bench_function("gsa_sample_by_sample", |b| {
            b.iter(|| black_box(gsa_by_samples(&problems, &gsa.gsa)))
        });
        g.bench_function("lsq", |b| {
            b.iter(|| black_box(fit_branches(&problems, &lsq).expect("fit")))
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
