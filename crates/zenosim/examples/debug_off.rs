use zenosim::models::BouncingBall;
use zenosim::{Simulation, SimulationOptions, ZenoStrategy};
fn main() {
    let ball = BouncingBall::new(1.0, 9.81, 0.5);
    let run = Simulation::new(&ball, &[1.0], &[0.0], SimulationOptions { t_end: 10.0, zeno: ZenoStrategy::Off, ..Default::default() }).unwrap().run(&mut ());
    println!("{:?} t_final={:.17} tau={:.17} impacts={}", run.outcome, run.t_final, ball.zeno_time(1.0), run.stats.impacts);
    let n = run.events.len();
    for e in &run.events[n-5..] { println!("{:.17} x-={:e} v-={:e} v+={:e}", e.t, e.before.q[0], e.before.q_dot[0], e.after.q_dot[0]); }
}
