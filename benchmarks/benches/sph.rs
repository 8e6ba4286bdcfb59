//! `cargo bench`: kernel evaluation, neighbour search (cell-grid build alone, and build plus
//! the query of every particle; 10⁴ and 10⁵ particles, 2D and 3D, jittered lattice,
//! h = 1.2 Δx), one full SPH step for 10⁵ particles in 3D, and a whole problem run as the
//! cost target states it: the axisymmetric Taylor bar at its coarse quick resolution
//! (6 rings across; the target is "well under a minute" for the quick level). Throughput is
//! reported in elements per second: kernel evaluations, particles searched, particle updates.

use blastsph_benchmarks::{gas_cube, jittered_lattice};
use blastsph_solver::neighbours::{find_neighbours, CellGrid, PairReach};
use blastsph_solver::{Kernel, KernelShape};
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

fn full_step(c: &mut Criterion) {
    let mut sim = gas_cube(100_000);
    let n = sim.particles().n_real();
    let mut group = c.benchmark_group("sph step 3D");
    group.throughput(Throughput::Elements(n as u64));
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    // each iteration takes the stable step, as a run would
    group.bench_function(BenchmarkId::new("density+forces+integration", n), |b| {
        b.iter(|| {
            let dt = sim.stable_time_step().unwrap();
            sim.step(dt).unwrap()
        })
    });
    group.finish();
}

fn whole_problems(c: &mut Criterion) {
    use blastsph_verification::{problems, Level};
    let mut group = c.benchmark_group("problem");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(60));
    let overrides = vec![("n_radius".to_string(), "6".to_string())];
    group.bench_function("taylor-bar-axisymmetric n_radius=6", |b| {
        b.iter(|| {
            problems::run("taylor-bar-axisymmetric", Level::Quick, &overrides, &|_| {})
                .expect("runs")
        })
    });
    group.finish();
}

/// One full-size biaxial test as the `biaxial` problem runs it: 1700 grains at 10 %
/// saturation and σ3 = 1 kPa, prepared, wetted, wrapped, consolidated and loaded to 10 % axial
/// strain at the problem's quasi-static platen speed (the target: under two minutes on the
/// 2-core machine). Ten samples take over ten minutes.
fn biaxial_test(c: &mut Criterion) {
    use blastsph_verification::problems::biaxial_run;
    let mut group = c.benchmark_group("dem");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(600));
    group.bench_function("biaxial 1700 grains S=10% sigma3=1kPa to 10%", |b| {
        b.iter(|| biaxial_run(1700, 1, 0.1, 1000.0, 0.1).expect("runs"))
    });
    group.finish();
}

criterion_group!(
    benches,
    kernels,
    neighbours,
    full_step,
    whole_problems,
    biaxial_test
);
criterion_main!(benches);
