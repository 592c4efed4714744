use std::time::Instant;
use zenosim::models::BallOnSine;
use zenosim::{Derived, Simulation, SimulationOptions};
fn main() {
    let ex = BallOnSine::paper();
    let d = Derived::new(&ex.model).unwrap();
    let n = 1_000_000;
    let t = Instant::now();
    let mut s = 0.0;
    for i in 0..n { let q = [0.1, 1.0 + i as f64 * 1e-9, 2.0]; s += d.acceleration(&q, &[0.5, 0.1, 0.2]).unwrap()[2]; }
    println!("free acceleration: {:.0} ns ({s})", t.elapsed().as_nanos() as f64 / n as f64);
    let t = Instant::now();
    for i in 0..n { let q = [0.1, 1.0 + i as f64 * 1e-9, 2.0]; s += d.multiplier(0, &q, &[0.5, 0.1, 0.2]).unwrap(); }
    println!("multiplier: {:.0} ns", t.elapsed().as_nanos() as f64 / n as f64);
    let t = Instant::now();
    for i in 0..n { let mut q = [0.1, 1.0 + i as f64 * 1e-9, 0.84]; let mut v = [0.5, 0.1, 0.2]; s += d.project(0, &mut q, &mut v).unwrap().0; }
    println!("project: {:.0} ns", t.elapsed().as_nanos() as f64 / n as f64);
    for t_end in [2.0, 2.0456, 6.0] {
        let sim = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, SimulationOptions { t_end, ..Default::default() }).unwrap();
        let reps = 200;
        let t = Instant::now();
        let mut evals = 0;
        for _ in 0..reps { evals = sim.run(&mut ()).stats.rhs_evals; }
        println!("run to {t_end}: {:.0} us, {evals} evals", t.elapsed().as_micros() as f64 / reps as f64);
    }
}
