//! The paper's Example 6: a ball bouncing on x3 = sin(x2), carried past its Zeno point.
use zenosim::models::BallOnSine;
use zenosim::{Simulation, SimulationOptions, ZenoStrategy};

fn main() {
    let zeno = match std::env::args().nth(1).as_deref() {
        Some("off") => ZenoStrategy::Off,
        Some(eps) if eps.parse::<f64>().is_ok() => ZenoStrategy::Epsilon(eps.parse().unwrap()),
        _ => ZenoStrategy::Auto,
    };
    let ex = BallOnSine::paper();
    let options = SimulationOptions { t_end: ex.t_end, zeno, ..Default::default() };
    let sim = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, options).expect("valid setup");
    let run = sim.run(&mut ());
    println!("outcome: {:?}", run.outcome);
    println!("impacts: {}, events: {}", run.stats.impacts, run.events.len());
    for z in &run.zeno {
        println!(
            "zeno: {} at t_switch = {:.12}, t_zeno = {:.12}, impacts = {}, ratio = {:?}",
            z.kind.name(), z.t_switch, z.t_zeno, z.impacts, z.ratio
        );
    }
    println!("final t = {}, q = {:?}, q_dot = {:?}", run.t_final, run.final_state.q, run.final_state.q_dot);
    println!("stats: {:?}", run.stats);
}
