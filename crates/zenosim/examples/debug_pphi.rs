use zenosim::models::SphericalPendulum;
use zenosim::{Simulation, SimulationOptions, Trajectory, OutputGrid};
fn main() {
    let ex = SphericalPendulum::demo();
    for output in [OutputGrid::Steps, OutputGrid::Uniform(0.1)] {
        let mut tr = Trajectory::default();
        let run = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, SimulationOptions { t_end: ex.t_end, output, ..Default::default() }).unwrap().run(&mut tr);
        let p0 = ex.model.momentum_phi(&ex.q0, &ex.q_dot0);
        let (mut worst, mut at) = (0.0f64, 0.0);
        for p in &tr.points { let d = (ex.model.momentum_phi(&p.q, &p.q_dot) - p0).abs() / p0; if d > worst { worst = d; at = p.t; } }
        println!("{output:?}: max relative p_phi drift {worst:e} at t = {at}; points {}; final {:e}", tr.points.len(), (run.final_state.q_dot[1] - ex.q0[0].sin().powi(2)*ex.q_dot0[1]));
    }
}
