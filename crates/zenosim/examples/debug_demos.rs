use zenosim::models::*;
use zenosim::{Simulation, SimulationOptions, HybridLagrangian, Execution};
fn show<M: HybridLagrangian>(name: &str, ex: &Example<M>) -> Execution {
    let options = SimulationOptions { t_end: ex.t_end, ..Default::default() };
    let run = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, options).unwrap().run(&mut ());
    let kinds: Vec<_> = run.events.iter().filter(|e| e.kind != zenosim::EventKind::Impact).map(|e| format!("{}@{:.4}", e.kind.name(), e.t)).collect();
    println!("{name}: {:?} impacts={} other={:?} final q={:?} qd={:?} stats={:?}", run.outcome, run.stats.impacts, kinds, run.final_state.q, run.final_state.q_dot, run.stats);
    for z in &run.zeno { println!("   zeno {:?} t_switch={} t_zeno={} n={} r={:?}", z.kind, z.t_switch, z.t_zeno, z.impacts, z.ratio); }
    run
}
fn main() {
    show("paper ball", &BallOnSine::paper());
    show("demo ball", &BallOnSine::demo());
    let c = CartPendulum::demo();
    let run = show("cart", &c);
    let px = c.model.momentum_x(&c.q0, &c.q_dot0);
    println!("   px/(M+m) = {} final xdot = {} diff {:e}", px/15.0, run.final_state.q_dot[1], run.final_state.q_dot[1]-px/15.0);
    let s = SphericalPendulum::demo();
    let run = show("sph", &s);
    let want = s.q0[0].sin().powi(2)*s.q_dot0[1];
    println!("   want phidot {} got {} diff {:e}", want, run.final_state.q_dot[1], run.final_state.q_dot[1]-want);
}
