use zenosim::models::BallOnSine;
use zenosim::{Simulation, SimulationOptions, EventKind};
fn main() {
    let ex = BallOnSine::paper();
    let options = SimulationOptions { t_end: ex.t_end, ..Default::default() };
    let run = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, options).unwrap().run(&mut ());
    let mut last = 0.0;
    for (k, e) in run.events.iter().enumerate().take(80) {
        let q = &e.before.q; let v = &e.before.q_dot; let va = &e.after.q_dot;
        let an = v[2] - q[1].cos()*v[1]; let ana = va[2] - q[1].cos()*va[1];
        println!("{k:4} {:?} t={:.15} dt={:.3e} h={:.2e} Aq-={:.4e} Aq+={:.4e} x2={:.6}", e.kind, e.t, e.t-last, q[2]-q[1].sin(), an, ana, q[1]);
        last = e.t;
    }
}
