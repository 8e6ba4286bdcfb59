//! `cargo bench --bench steps` (a few minutes, run on every change): kernel evaluation (and the
//! shell-averaged kernel of spherical scenes),
//! neighbour search (cell-grid build alone, and build plus the query of every particle; 10⁴
//! and 10⁵ particles, 2D and 3D, jittered lattice, h = 1.2 Δx) and one full SPH step of 10⁵
//! particles in 2D and in 3D. Throughput is reported in elements per second: kernel
//! evaluations, particles searched, particle updates. Whole problems are timed by the
//! `problems` bench.

use blastsph_benchmarks::{gas_box, jittered_lattice};
use blastsph_solver::neighbours::{find_neighbours, CellGrid, PairReach};
use blastsph_solver::radial::RadialKernel;
use blastsph_solver::{Geometry, Kernel, KernelShape};
use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::time::Duration;

fn kernels(c: &mut Criterion) {
    let mut group = c.benchmark_group("kernel");
    let q: Vec<f64> = (0..1000).map(|k| 2.0 * k as f64 / 1000.0).collect();
    group.throughput(Throughput::Elements(q.len() as u64));
    for shape in [
        KernelShape::CubicSpline,
        KernelShape::WendlandC2,
        KernelShape::QuinticSpline,
    ] {
        let kernel = Kernel::<3>::new(shape);
        group.bench_function(BenchmarkId::new("value+derivative 3D", shape.name()), |b| {
            b.iter(|| {
                q.iter()
                    .map(|&r| kernel.value(black_box(r), 1.0) + kernel.derivative(r, 1.0))
                    .sum::<f64>()
            })
        });
    }
    group.finish();
}

/// The shell-averaged kernel of 1D spherical scenes, W̃(r_i, r_j; h) with both derivatives, for
/// pairs as a shell lattice has them: gaps of 0–2h at radii of 1–100 h.
fn shell_kernels(c: &mut Criterion) {
    let mut group = c.benchmark_group("shell kernel");
    let pairs: Vec<(f64, f64)> = (0..1000)
        .map(|k| {
            let radius = 10f64.powf(2.0 * (k % 100) as f64 / 100.0);
            (radius, radius + 2.0 * (k / 100) as f64 / 10.0)
        })
        .collect();
    group.throughput(Throughput::Elements(pairs.len() as u64));
    for shape in [KernelShape::CubicSpline, KernelShape::WendlandC2] {
        let kernel = RadialKernel::new(Geometry::Spherical, shape);
        group.bench_function(BenchmarkId::new("value+derivatives", shape.name()), |b| {
            b.iter(|| {
                pairs
                    .iter()
                    .map(|&(r_i, r_j)| {
                        let (w, d1, d2) = kernel.value_and_derivatives(black_box(r_i), r_j, 1.0);
                        w + d1 + d2
                    })
                    .sum::<f64>()
            })
        });
    }
    group.finish();
}

fn neighbour_search<const D: usize>(c: &mut Criterion, n: usize) {
    let dx = 0.01;
    let x = jittered_lattice::<D>(n, dx);
    let h = vec![1.2 * dx; x.len()];
    let mut group = c.benchmark_group(format!("neighbours {D}D"));
    group.throughput(Throughput::Elements(x.len() as u64));
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(5));
    group.bench_function(BenchmarkId::new("build", x.len()), |b| {
        b.iter(|| CellGrid::build(&x, 2.0 * 1.2 * dx))
    });
    group.bench_function(BenchmarkId::new("build+query", x.len()), |b| {
        b.iter(|| find_neighbours(&x, &h, 2.0, PairReach::MeanH, x.len()))
    });
    group.finish();
}

fn neighbours(c: &mut Criterion) {
    neighbour_search::<2>(c, 10_000);
    neighbour_search::<2>(c, 100_000);
    neighbour_search::<3>(c, 10_000);
    neighbour_search::<3>(c, 100_000);
}

/// One step of the gas box at 10⁵ particles, taking the stable step as a run would.
fn full_step<const D: usize>(c: &mut Criterion) {
    let mut sim = gas_box::<D>(100_000);
    let n = sim.particles().n_real();
    let mut group = c.benchmark_group(format!("sph step {D}D"));
    group.throughput(Throughput::Elements(n as u64));
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    group.bench_function(BenchmarkId::new("density+forces+integration", n), |b| {
        b.iter(|| {
            let dt = sim.stable_time_step().unwrap();
            sim.step(dt).unwrap()
        })
    });
    group.finish();
}

fn full_steps(c: &mut Criterion) {
    full_step::<2>(c);
    full_step::<3>(c);
}

criterion_group!(benches, kernels, shell_kernels, neighbours, full_steps);
criterion_main!(benches);
