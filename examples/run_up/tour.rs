//! The run without arguments: the paper's Fig. 8a rotor through its critical speed with and
//! without the ring, up and back, at two rates, then the finite-element rotor; each run writes
//! its pictures in its own folder under `target/run_up`.

/// The two acceleration rates of the tour, $R = d\eta/d\tau$.
const RATES: [&str; 2] = ["0.01", "0.002"];

/// The argument lists of the tour's paper-model runs, each with its output folder.
pub fn paper_runs() -> Vec<Vec<String>> {
    let mut runs = Vec::new();
    for rate in RATES {
        for ring in [true, false] {
            let name = format!("{}_rate_{rate}", if ring { "ring" } else { "no_ring" });
            let mut args: Vec<String> = [
                "run_up",
                "--preset",
                "fig8a",
                "--x0",
                "0.9",
                "--eta-from",
                "0.3",
                "--eta-to",
                "3",
                "--rate",
                rate,
                "--samples-per-period",
                "16",
                "--out",
            ]
            .iter()
            .map(|s| s.to_string())
            .collect();
            args.push(format!("target/run_up/{name}"));
            if !ring {
                args.push("--no-ring".into());
            }
            runs.push(args);
        }
    }
    runs
}
