use zenosim::models::*;
use zenosim::{Simulation, SimulationOptions, Tolerances, Method};
fn main() {
    for method in [Method::Dop853, Method::Dopri5] {
    for tol in [1e-8, 1e-9, 1e-10, 1e-11, 1e-12] {
        let s = SphericalPendulum::demo();
        let options = SimulationOptions { t_end: s.t_end, tolerances: Tolerances { rtol: tol, atol: tol }, method, ..Default::default() };
        let run = Simulation::new(&s.model, &s.q0, &s.q_dot0, options).unwrap().run(&mut ());
        let want = s.q0[0].sin().powi(2)*s.q_dot0[1];
        // p_phi just before the switch
        let z = run.events.iter().find(|e| e.kind == zenosim::EventKind::Zeno).unwrap();
        let pb = s.model.momentum_phi(&z.before.q, &z.before.q_dot) / 100.0;
        let i1 = &run.events[0];
        let p1 = s.model.momentum_phi(&i1.before.q, &i1.before.q_dot) / 100.0;
        let c = CartPendulum::demo();
        let options = SimulationOptions { t_end: c.t_end, tolerances: Tolerances { rtol: tol, atol: tol }, method, ..Default::default() };
        let runc = Simulation::new(&c.model, &c.q0, &c.q_dot0, options).unwrap().run(&mut ());
        let px = c.model.momentum_x(&c.q0, &c.q_dot0);
        println!("{method:?} tol {tol:e}: sph final {:+.2e} at-switch {:+.2e} first-impact {:+.2e} evals {} | cart {:+.2e} evals {}", run.final_state.q_dot[1]-want, pb-want, p1-want, run.stats.rhs_evals, runc.final_state.q_dot[1]-px/15.0, runc.stats.rhs_evals);
    }}
}
