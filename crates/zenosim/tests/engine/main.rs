//! The engine's integration tests, in one binary (each test binary instantiates the generic
//! engine anew, so one binary builds much faster than many).

mod ball_on_sine;
mod bouncing_ball;
mod conservation;
mod errors;
mod forces_and_time;
mod friction;
mod liftoff;
mod multiple_constraints;
mod pendulum_chain;
mod properties;
mod random_states;
mod review_regressions;
mod zeno_cost;
