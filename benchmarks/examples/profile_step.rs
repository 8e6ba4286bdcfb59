//! Steps the 10⁵-particle gas cube a few times, for profilers (`perf record`).
fn main() {
    let mut sim = blastsph_benchmarks::gas_box::<3>(100_000);
    let start = std::time::Instant::now();
    let steps = 10;
    for _ in 0..steps {
        let dt = sim.stable_time_step().unwrap();
        sim.step(dt).unwrap();
    }
    let per_step = start.elapsed().as_secs_f64() / steps as f64;
    println!("{:?}", sim.phase_times());
    println!(
        "{per_step:.4} s per step, {:.3e} particle updates/s",
        sim.particles().n_real() as f64 / per_step
    );
}
