use mass_spring_solvers::*;
fn main() {
    for k in [1e3, 1e6] {
        let sys = scene::thesis_rope(k).unwrap();
        let mut be = backward_euler::BackwardEuler::reference(&sys).unwrap();
        let t = std::time::Instant::now();
        let run = simulate(&mut be, sys.initial_state(), &RunOptions::default()).unwrap();
        println!("k={k} peaks={} T/2 thesis={:?} exact={:?} steps={} first peak {:?} time {:?} limit {}", run.peak_count(), run.half_period_thesis(), run.half_period_exact(), run.steps, run.peaks[0], t.elapsed(), run.hit_time_limit);
        println!("  y4 {:?}", run.final_state.x[4]);
    }
}
