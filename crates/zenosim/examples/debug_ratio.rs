use zenosim::models::BouncingBall;
use zenosim::{Simulation, SimulationOptions};
fn main() {
    let e = 0.8;
    let ball = BouncingBall::new(1.0, 9.81, e);
    let run = Simulation::new(&ball, &[1.0], &[0.0], SimulationOptions { t_end: 10.0, ..Default::default() }).unwrap().run(&mut ());
    let t = run.impact_times(0);
    let n = t.len();
    println!("impacts {n}, zeno {:?}", run.zeno[0]);
    for k in n-12..n { let d = t[k]-t[k-1]; let dp = t[k-1]-t[k-2]; let exact = ball.impact_time(1.0, k as u32 +1); println!("k={k} t={:.17} err={:+.2e} flight={:.3e} ratio={:.6}", t[k], t[k]-exact, d, d/dp); }
}
