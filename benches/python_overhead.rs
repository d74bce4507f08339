//! The Rust side of the bindings' overhead benchmark (issue 22: a 1000-period simulation from
//! Python costs at most 5 % more than the same run from Rust). Not a criterion bench: a timer
//! that `python/benches/overhead.py` drives over a pipe, so that the Rust and the Python runs
//! alternate on the same loaded machine instead of being measured minutes apart.
//!
//! Protocol: each line of standard input is `PRESET PERIODS` (e.g. `fig8b 1000`); for each,
//! one run of the preset's model from rest with default options, every stroboscopic state
//! recorded (`JeffcottModel::strobe_range(&State::zeros(), 0, PERIODS, ..)`, what
//! `jeffcott.simulate(p, PERIODS)` computes), and one line on standard output:
//! `WALL CPU STEPS`: the run's wall time and the CPU time of its thread (`clock_gettime`'s
//! thread CPU clock, the clock of Python's `time.thread_time`; NaN off Unix), in seconds, and
//! its integrator steps. Ends at the end of input.
//!
//! Run: `python python/benches/overhead.py` (it starts
//! `cargo bench --bench python_overhead` itself).

use std::hint::black_box;
use std::io::{BufRead, Write};
use std::time::Instant;

use jeffcott::hybrid::SimOptions;
use jeffcott::paper::{JeffcottModel, State};
use jeffcott::params::Preset;

/// The CPU time of this thread, in seconds (NaN where there is no such clock).
fn thread_cpu() -> f64 {
    #[cfg(unix)]
    {
        let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
        t.tv_sec as f64 + 1e-9 * t.tv_nsec as f64
    }
    #[cfg(not(unix))]
    {
        f64::NAN
    }
}

/// One timed run of `line`'s request: `(wall, cpu, steps)`, or why the line is not one.
fn timed(line: &str) -> Result<(f64, f64, u64), String> {
    let mut words = line.split_whitespace();
    let (Some(name), Some(periods), None) = (words.next(), words.next(), words.next()) else {
        return Err(format!("expected `PRESET PERIODS`, got `{line}`"));
    };
    let preset: Preset = name.parse().map_err(|e| format!("{e}"))?;
    let periods: u64 = periods.parse().map_err(|e| format!("periods: {e}"))?;
    let opts = SimOptions::default();
    let (start, cpu) = (Instant::now(), thread_cpu());
    // The model is built inside the timed part, as `jeffcott.simulate` builds it per call.
    let model = JeffcottModel::new(preset.params()).map_err(|e| e.to_string())?;
    let run = model.strobe_range(black_box(&State::zeros()), 0, periods, &opts);
    let (wall, cpu) = (start.elapsed().as_secs_f64(), thread_cpu() - cpu);
    let (traj, stats) = run.map_err(|e| e.to_string())?;
    black_box(&traj);
    Ok((wall, cpu, stats.steps))
}

fn main() {
    let stdout = std::io::stdout();
    for line in std::io::stdin().lock().lines() {
        let Ok(line) = line else { break };
        if line.trim().is_empty() {
            continue;
        }
        let reply = match timed(&line) {
            Ok((wall, cpu, steps)) => format!("{wall:e} {cpu:e} {steps}"),
            Err(e) => format!("error {e}"),
        };
        let mut out = stdout.lock();
        if writeln!(out, "{reply}").and_then(|()| out.flush()).is_err() {
            break;
        }
    }
}
