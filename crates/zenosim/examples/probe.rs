use zenosim::models::BallOnSine;
use zenosim::{Simulation, SimulationOptions};
fn main() {
    let ex = BallOnSine::paper();
    let sim = Simulation::new(
        &ex.model,
        &ex.q0,
        &ex.q_dot0,
        SimulationOptions {
            t_end: 6.0,
            ..Default::default()
        },
    )
    .unwrap();
    let reps: usize = std::env::args().nth(1).map_or(1, |s| s.parse().unwrap());
    let mut evals = 0;
    for _ in 0..reps {
        evals += sim.run(&mut ()).stats.rhs_evals;
    }
    println!("{evals}");
}
