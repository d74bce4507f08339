//! Global dynamics on the paper's model: attractors identified against the reference values
//! (docs/global.md), matched across starts, basins at eta = 2.2 with both preloads, and the
//! resumable runner: a run interrupted and restarted equals an uninterrupted one bit for bit,
//! for 1 and 2 threads; failures are recorded with their kind and not lost.

use std::fs;
use std::path::PathBuf;

use jeffcott::global::{
    find_attractor, run_points, scan_grid, Attractor, AttractorOptions, Grid2, GridScan,
    MatchOptions, PointFailure, PointLabel, RunOptions, Shard, SimFailureKind, StoreError,
    SweepStore,
};
use jeffcott::hybrid::{OutputPlan, SimOptions};
use jeffcott::paper::{BasinPlane, ParamPlane, RotorStart, StartPlane, SweepParameter};
use jeffcott::params::Preset;
use jeffcott::JeffcottModel;

fn temp_dir(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let target = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let dir = target.join("global_scan_test").join(name);
    let _ = fs::remove_dir_all(&dir);
    dir
}

/// Every outcome as its record text: equal text is equal bits (numbers round-trip exactly).
fn texts(scan: &GridScan) -> Vec<String> {
    scan.results
        .results
        .iter()
        .map(|r| match r {
            Some(Ok(a)) => serde_json::to_string(a).unwrap(),
            Some(Err(e)) => serde_json::to_string(e).unwrap(),
            None => "missing".into(),
        })
        .collect()
}

fn quick() -> AttractorOptions {
    AttractorOptions::default()
        .with_transient(300)
        .with_record(32)
        .with_max_transient(600)
}

/// A cycle point of `a` within `tol` of `z` (rotor components), and its distance.
fn nearest(a: &Attractor, z: &[f64]) -> f64 {
    a.cycle
        .iter()
        .map(|p| {
            p.iter()
                .zip(z)
                .map(|(u, v)| (u - v).abs())
                .fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn attractors_match_the_reference_orbits() {
    // Period 1 of Fig. 8a at eta = 2 (docs/global.md, reference check value, 1e-10).
    let model = JeffcottModel::new(Preset::Fig8a.params().with_eta(2.0)).unwrap();
    let a = find_attractor(
        &model,
        &model.state_at([0.0; 2], [0.0; 2]).unwrap(),
        &quick(),
    )
    .unwrap();
    assert_eq!(a.period(), Some(1));
    let z = [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533];
    // Converged at rate 0.73 per period for 300 periods: the distance is the check value's
    // rounding (5e-11) plus the integration tolerance.
    assert!(nearest(&a, &z) < 1e-8, "{}", nearest(&a, &z));
    assert_eq!(a.stats.contacts_per_period, 1.0);
    // One contact from tau = 1.20313 to 1.66682 per period 2 pi / 2 (reference).
    let fraction = (1.66682 - 1.20313) / std::f64::consts::PI;
    assert!(
        (a.stats.contact_fraction - fraction).abs() < 1e-4,
        "{}",
        a.stats.contact_fraction
    );
    let regimes: Vec<u8> = a.stats.occupancy.iter().map(|o| o.0).collect();
    assert_eq!(regimes, [1, 5]); // free flight and regime V (no preload)

    // The period-3 orbit of Fig. 8a at eta = 2.17, reached from rest (reference point).
    let model = JeffcottModel::new(Preset::Fig8a.params().with_eta(2.17)).unwrap();
    let config = quick().with_transient(2000).with_max_transient(2000);
    let b = find_attractor(
        &model,
        &model.state_at([0.0; 2], [0.0; 2]).unwrap(),
        &config,
    )
    .unwrap();
    assert_eq!(b.period(), Some(3));
    let z3 = [0.4083372776, -0.0332339640, 0.0200130670, -0.3057623329];
    assert!(nearest(&b, &z3) < 1e-8, "{}", nearest(&b, &z3));
    // The canonical point is the cycle's lexicographic minimum.
    let c = b.canonical().unwrap();
    assert!(b.cycle.iter().all(|p| p[0] >= c[0]));
    // The cycle really is a period-3 orbit: three periods from its canonical point return to it.
    let y0 = model.state_at([c[0], c[1]], [c[2], c[3]]).unwrap();
    let (traj, _) = model
        .run(
            0.0,
            &y0,
            &OutputPlan::strobe(model.params().forcing_period(), 1, 3),
            &SimOptions::default(),
        )
        .unwrap();
    let back = &traj.strobe[2].y;
    let gap = (0..4).map(|i| (back[i] - c[i]).abs()).fold(0.0, f64::max);
    assert!(gap < 1e-7, "{gap:e}");
    let one = &traj.strobe[0].y;
    assert!((one[0] - c[0]).abs() > 0.05); // not a fixed point
}

#[test]
fn the_same_attractor_from_other_starts_matches_and_others_do_not() {
    let model = JeffcottModel::new(Preset::Fig8a.params().with_eta(2.2)).unwrap();
    let run = |x: f64, v: f64| {
        let y0 = model.state_at([x, 0.0], [v, 0.0]).unwrap();
        find_attractor(&model, &y0, &quick()).unwrap()
    };
    // Two starts reaching period 3 and two reaching period 1 (from the basin picture).
    let p3a = run(0.0, 0.0);
    let p3b = run(0.6, 1.3);
    let p1a = run(0.0, -1.5);
    let p1b = run(-0.2, -1.4);
    assert_eq!(
        [p3a.period(), p3b.period(), p1a.period(), p1b.period()],
        [Some(3), Some(3), Some(1), Some(1)]
    );
    let tol = MatchOptions::default();
    assert!(p3a.matches(&p3b, &tol) && p1a.matches(&p1b, &tol));
    assert!(!p3a.matches(&p1a, &tol));
    // Same canonical point from both starts (rotation fixed by the lexicographic minimum).
    let d = nearest(&p3a, p3b.canonical().unwrap());
    assert!(d < 1e-6 && (p3a.canonical().unwrap()[0] - p3b.canonical().unwrap()[0]).abs() < 1e-6);
    // A cycle rotated by one point still matches; a cycle shifted by 2e-3 does not.
    let mut rotated = p3a.clone();
    rotated.cycle.rotate_left(1);
    assert!(rotated.matches(&p3a, &tol));
    let mut shifted = p3a.clone();
    shifted.cycle[1][2] += 2e-3;
    assert!(!shifted.matches(&p3a, &tol));
    // A period-1 orbit recorded as period 2 (two equal points) is compared as period 1.
    let mut doubled = p1a.clone();
    doubled.cycle.push(doubled.cycle[0].clone());
    doubled.periodicity = jeffcott::analysis::Periodicity::Period(2);
    assert!(doubled.matches(&p1b, &tol));
}

#[test]
fn basins_at_eta_2_2_hold_period_1_and_period_3_for_both_preloads() {
    let grid = Grid2::linspace((-1.0, 1.0, 5), (-1.5, 1.5, 4)).unwrap();
    // With D = 0.1 the period-3 orbit attracts slowly (a multiplier of its third iterate near
    // -1 makes it look like period 6 after 600 periods): give it 2000.
    let config = quick().with_transient(1000).with_max_transient(2000);
    for (preset, rest_period) in [(Preset::Fig8a, 3), (Preset::Fig8b, 1)] {
        let plane = BasinPlane::new(preset.params().with_eta(2.2), StartPlane::XVx);
        let scan = scan_grid(
            &grid,
            plane.setup(),
            &config,
            None,
            &RunOptions::default(),
            None,
        )
        .unwrap();
        let cat = scan.catalogue(&MatchOptions::default());
        let mut periods: Vec<Option<usize>> =
            cat.entries.iter().map(|e| e.attractor.period()).collect();
        periods.sort();
        assert_eq!(periods, [Some(1), Some(3)], "{preset}");
        assert_eq!(cat.failed(), 0);
        assert_eq!(
            cat.entries.iter().map(|e| e.count).sum::<usize>(),
            grid.len()
        );
        // From rest: period 3 without preload, period 1 with (the paper's 2.165 / 2.213).
        let setup = plane.setup();
        let (model, y0) = setup(&[0.0, 0.0]).unwrap();
        let rest = find_attractor(&model, &y0, &config).unwrap();
        assert_eq!(rest.period(), Some(rest_period), "{preset}");
        let k = cat
            .entries
            .iter()
            .position(|e| e.attractor.matches(&rest, &cat.tolerance));
        assert!(
            k.is_some(),
            "{preset}: the attractor from rest is one of the grid's"
        );
    }
}

#[test]
fn an_interrupted_scan_restarted_equals_an_uninterrupted_one_bitwise() {
    let grid = Grid2::linspace((-1.0, 1.0, 6), (-1.5, 1.5, 5)).unwrap();
    let plane = BasinPlane::new(Preset::Fig8b.params().with_eta(2.2), StartPlane::XVx);
    let config = quick();
    let description = plane;

    // Uninterrupted, one thread, in memory.
    let whole = scan_grid(
        &grid,
        plane.setup(),
        &config,
        None,
        &RunOptions::default().with_threads(1),
        None,
    )
    .unwrap();
    assert!(whole.results.is_complete());
    assert_eq!(whole.results.computed, grid.len());

    // Interrupted after 7 points (2 threads), then after 9 more (1 thread), then finished (2).
    let dir = temp_dir("restart");
    let store = SweepStore::open_scan(&dir, "basins", &description, &grid, &config).unwrap();
    let two = RunOptions::default().with_threads(2);
    let first = scan_grid(
        &grid,
        plane.setup(),
        &config,
        Some(&store),
        &two.with_max_new_points(7),
        None,
    )
    .unwrap();
    assert_eq!(
        (first.results.computed, first.results.missing()),
        (7, grid.len() - 7)
    );
    // A kill in the middle of a write leaves a partial last line: simulate it.
    let path = store.records_path(0);
    let text = fs::read_to_string(&path).unwrap();
    let last_line = text.lines().last().unwrap().to_string();
    fs::write(
        &path,
        format!("{text}{}", &last_line[..last_line.len() / 2]),
    )
    .unwrap();
    let store = SweepStore::open_scan(&dir, "basins", &description, &grid, &config).unwrap();
    let second = scan_grid(
        &grid,
        plane.setup(),
        &config,
        Some(&store),
        &RunOptions::default().with_threads(1).with_max_new_points(9),
        None,
    )
    .unwrap();
    assert_eq!((second.results.reused, second.results.computed), (7, 9));
    let third = scan_grid(&grid, plane.setup(), &config, Some(&store), &two, None).unwrap();
    assert_eq!(
        (third.results.reused, third.results.computed),
        (16, grid.len() - 16)
    );
    assert!(third.results.is_complete());
    assert_eq!(texts(&third), texts(&whole));
    assert_eq!(third.results.results, whole.results.results);

    // A fourth run has nothing to do and reads back the same.
    let fourth = scan_grid(&grid, plane.setup(), &config, Some(&store), &two, None).unwrap();
    assert_eq!(
        (fourth.results.reused, fourth.results.computed),
        (grid.len(), 0)
    );
    assert_eq!(texts(&fourth), texts(&whole));
    // Every point is recorded exactly once, the partial line cut off.
    let lines = fs::read_to_string(&path).unwrap();
    assert!(lines.ends_with('\n'));
    assert_eq!(lines.lines().count(), grid.len());

    // A different sweep in the same folder is refused.
    let other = serde_json::json!({"plane": plane, "x": null});
    assert!(SweepStore::open_scan(&dir, "basins", &other, &grid, &config).is_err());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn results_do_not_depend_on_the_number_of_threads() {
    let grid = Grid2::linspace((2.1, 2.3, 4), (0.0, 0.1, 3)).unwrap();
    let plane = ParamPlane::new(
        Preset::Fig8a.params(),
        SweepParameter::Eta,
        SweepParameter::Preload,
    );
    let run = |t| {
        scan_grid(
            &grid,
            plane.setup(),
            &quick(),
            None,
            &RunOptions::default().with_threads(t),
            None,
        )
        .unwrap()
    };
    let (one, two) = (run(1), run(2));
    assert_eq!((one.results.threads, two.results.threads), (1, 2));
    assert_eq!(texts(&one), texts(&two));
}

#[test]
fn failed_points_are_recorded_with_their_kind_and_not_rerun() {
    // nu1 < 0 cannot build; a budget of 2 steps per contact fails the contact integration.
    let grid = Grid2::new(vec![2.0, 2.2], vec![-0.1, 0.125]).unwrap();
    let plane = ParamPlane::new(
        Preset::Fig8a.params(),
        SweepParameter::Eta,
        SweepParameter::Nu1,
    );
    let dir = temp_dir("failures");
    let mut config = quick();
    config.opts.max_steps = 2;
    let store = SweepStore::open_scan(&dir, "failures", &(), &grid, &config).unwrap();
    let scan = scan_grid(
        &grid,
        plane.setup(),
        &config,
        Some(&store),
        &RunOptions::default(),
        None,
    )
    .unwrap();
    let f: Vec<_> = scan
        .results
        .failures()
        .map(|(i, e)| (i, e.clone()))
        .collect();
    assert_eq!(f.len(), 4);
    assert!(matches!(f[0].1, PointFailure::Build { ref message } if message.contains("nu1")));
    assert!(
        matches!(f[2].1, PointFailure::Simulation { kind: SimFailureKind::Integrator, t, .. } if t > 0.0)
    );
    let again = scan_grid(
        &grid,
        plane.setup(),
        &config,
        Some(&store),
        &RunOptions::default(),
        None,
    )
    .unwrap();
    assert_eq!((again.results.computed, again.results.reused), (0, 4));
    assert_eq!(again.results.results, scan.results.results);
    let cat = again.catalogue(&MatchOptions::default());
    assert_eq!(cat.labels, vec![PointLabel::Failed; 4]);
    // With a sound budget the valid points succeed.
    let fine = scan_grid(
        &grid,
        plane.setup(),
        &quick(),
        None,
        &RunOptions::default(),
        None,
    )
    .unwrap();
    assert_eq!(fine.results.failures().count(), 2);
    assert_eq!(fine.periods(), [None, None, Some(1), Some(3)]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn run_points_works_on_any_points_and_stops_on_a_time_budget() {
    let points: Vec<[f64; 2]> = (0..40).map(|i| [i as f64, 0.5]).collect();
    let f = |p: &[f64; 2]| -> Result<f64, String> {
        std::thread::sleep(std::time::Duration::from_millis(5));
        Ok(p[0].sin() * p[1])
    };
    let cfg = RunOptions::default()
        .with_threads(2)
        .with_time_budget(std::time::Duration::from_millis(30));
    let partial = run_points(&points, None, &cfg, f, None).unwrap();
    assert!(
        partial.computed > 0 && partial.computed < 40,
        "{}",
        partial.computed
    );
    let done: Vec<f64> = partial.successes().map(|(_, v)| *v).collect();
    assert!(partial
        .successes()
        .all(|(i, v)| v.to_bits() == ((i as f64).sin() * 0.5).to_bits()));
    assert_eq!(done.len(), partial.computed);
    let start = RotorStart::at_rest();
    assert_eq!(start.position, [0.0, 0.0]);
}

/// Every f64 of a scan's outcomes as its bits, point by point (`None` for a failed or missing
/// point): the cycle, the statistics and the occupancy.
fn bits(scan: &GridScan) -> Vec<Option<Vec<u64>>> {
    scan.results
        .results
        .iter()
        .map(|r| match r {
            Some(Ok(a)) => {
                let s = &a.stats;
                let mut v: Vec<u64> = a.cycle.iter().flatten().map(|x| x.to_bits()).collect();
                v.extend([s.contacts_per_period, s.contact_fraction].map(f64::to_bits));
                v.extend(s.occupancy.iter().map(|o| o.1.to_bits()));
                v.extend(s.lo.iter().chain(&s.hi).map(|x| x.to_bits()));
                v.extend([s.periods_run, s.window]);
                Some(v)
            }
            _ => None,
        })
        .collect()
}

#[test]
fn shards_run_separately_then_merged_equal_one_run_bitwise() {
    let grid = Grid2::linspace((-1.0, 1.0, 4), (-1.5, 1.5, 3)).unwrap();
    let plane = BasinPlane::new(Preset::Fig8b.params().with_eta(2.2), StartPlane::XVx);
    let config = quick();
    let description = plane;
    let one = RunOptions::default().with_threads(1);

    // One run, one process, its own folder.
    let dir = temp_dir("shard-whole");
    let store = SweepStore::open_scan(&dir, "basins", &description, &grid, &config).unwrap();
    let whole = scan_grid(&grid, plane.setup(), &config, Some(&store), &one, None).unwrap();
    assert!(whole.results.is_complete());

    // Three shards, as three tasks of a job array would: each opens the folder and runs its
    // part only, into its own file; the other points stay `None`.
    let dir = temp_dir("shards");
    let mut done = Vec::new();
    for i in 0..3 {
        let shard = Shard::new(i, 3).unwrap();
        let store = SweepStore::open_scan(&dir, "basins", &description, &grid, &config).unwrap();
        let part = scan_grid(
            &grid,
            plane.setup(),
            &config,
            Some(&store),
            &one.with_shard(shard),
            None,
        )
        .unwrap();
        // Shard i runs the points i, i + 3, i + 6, i + 9 (the MPI ranks' rule).
        let mine: Vec<usize> = (0..grid.len()).filter(|k| k % 3 == i).collect();
        assert_eq!(part.results.computed, mine.len());
        assert_eq!(part.results.reused, done.len());
        done.extend(&mine);
        for k in 0..grid.len() {
            assert_eq!(part.results.results[k].is_some(), done.contains(&k), "{k}");
        }
        assert!(store.shard_records_path(shard).exists());
        assert!(!store.records_path(0).exists());
    }
    // The merge: a run without a shard reads every point from the three files, runs none.
    let store = SweepStore::open_scan(&dir, "basins", &description, &grid, &config).unwrap();
    let merged = scan_grid(&grid, plane.setup(), &config, Some(&store), &one, None).unwrap();
    assert_eq!(
        (merged.results.reused, merged.results.computed),
        (grid.len(), 0)
    );
    assert_eq!(merged.results.duplicates, 0);
    assert!(merged.results.is_complete());
    assert_eq!(bits(&merged), bits(&whole));
    assert_eq!(texts(&merged), texts(&whole));
    assert_eq!(merged.results.results, whole.results.results);
    // The same labels and catalogue (the figure's data) as one run.
    let tol = MatchOptions::default();
    assert_eq!(merged.catalogue(&tol).labels, whole.catalogue(&tol).labels);
    // The same record set: every point once, in point order after sorting by index.
    let records = |d: &std::path::Path| {
        let mut lines: Vec<String> = fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "jsonl"))
            .flat_map(|p| {
                fs::read_to_string(p)
                    .unwrap()
                    .lines()
                    .map(String::from)
                    .collect::<Vec<_>>()
            })
            .collect();
        lines.sort_by_key(|l| {
            serde_json::from_str::<serde_json::Value>(l).unwrap()["index"].as_u64()
        });
        lines
    };
    assert_eq!(records(&dir), records(&temp_dir_kept("shard-whole")));
    assert_eq!(
        fs::read_to_string(dir.join("manifest.json")).unwrap(),
        fs::read_to_string(temp_dir_kept("shard-whole").join("manifest.json")).unwrap()
    );
    fs::remove_dir_all(&dir).unwrap();
    fs::remove_dir_all(temp_dir_kept("shard-whole")).unwrap();
}

/// The folder of `temp_dir(name)`, not emptied.
fn temp_dir_kept(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let target = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    target.join("global_scan_test").join(name)
}

#[test]
fn a_shard_resumed_runs_only_its_points_not_yet_done() {
    let grid = Grid2::linspace((-1.0, 1.0, 3), (-1.5, 1.5, 3)).unwrap();
    let plane = BasinPlane::new(Preset::Fig8a.params().with_eta(2.2), StartPlane::XVx);
    let config = quick();
    let dir = temp_dir("shard-resume");
    let store = SweepStore::open_scan(&dir, "basins", &(), &grid, &config).unwrap();
    let shard = "1/2".parse::<Shard>().unwrap();
    let run = RunOptions::default().with_threads(1).with_shard(shard);
    // Shard 1 of 2 owns the points 1, 3, 5, 7: killed after 2 of them.
    let first = scan_grid(
        &grid,
        plane.setup(),
        &config,
        Some(&store),
        &run.with_max_new_points(2),
        None,
    )
    .unwrap();
    assert_eq!(first.results.computed, 2);
    let second = scan_grid(&grid, plane.setup(), &config, Some(&store), &run, None).unwrap();
    assert_eq!((second.results.reused, second.results.computed), (2, 2));
    let has = |k: usize| second.results.results[k].is_some();
    assert!((0..grid.len()).all(|k| has(k) == (k % 2 == 1)));
    // Done: a third run of the shard has nothing to do.
    let third = scan_grid(&grid, plane.setup(), &config, Some(&store), &run, None).unwrap();
    assert_eq!((third.results.reused, third.results.computed), (4, 0));
    let lines = fs::read_to_string(store.shard_records_path(shard)).unwrap();
    assert_eq!(lines.lines().count(), 4);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_shard_that_does_not_exist_is_a_typed_error() {
    assert!(matches!(
        Shard::new(3, 3),
        Err(StoreError::InvalidShard {
            field: "index",
            index: 3,
            count: 3
        })
    ));
    assert!(matches!(
        Shard::new(0, 0),
        Err(StoreError::InvalidShard {
            field: "count",
            index: 0,
            count: 0
        })
    ));
    assert!(matches!(
        "3/3".parse::<Shard>(),
        Err(StoreError::InvalidShard { field: "index", .. })
    ));
    assert!(matches!(
        "0/0".parse::<Shard>(),
        Err(StoreError::InvalidShard { field: "count", .. })
    ));
    for text in ["2", "2/", "a/8", "-1/8", "2/8/1", ""] {
        assert!(
            matches!(text.parse::<Shard>(), Err(StoreError::ShardSyntax { .. })),
            "{text}"
        );
    }
    let s: Shard = " 2/8 ".parse().unwrap();
    assert_eq!(
        (s.index(), s.count(), s.to_string()),
        (2, 8, "2/8".to_string())
    );
    let msg = Shard::new(3, 3).unwrap_err().to_string();
    assert!(msg.contains("3/3") && msg.contains("0 to 2"), "{msg}");
}

#[test]
fn shards_creating_one_folder_at_once_agree_on_one_manifest() {
    let grid = Grid2::linspace((0.0, 1.0, 2), (0.0, 1.0, 2)).unwrap();
    let config = quick();
    for round in 0..200 {
        let dir = temp_dir(&format!("shard-race-{round}"));
        // Eight processes of the same sweep, and eight of another description, at once.
        let barrier = std::sync::Barrier::new(16);
        let outcomes: Vec<(usize, bool)> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..16)
                .map(|t| {
                    let (dir, grid, config, barrier) = (&dir, &grid, &config, &barrier);
                    s.spawn(move || {
                        let desc = serde_json::json!({"sweep": t % 2});
                        barrier.wait();
                        let ok = SweepStore::open_scan(dir, "basins", &desc, grid, config).is_ok();
                        (t % 2, ok)
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        // Exactly one sweep's processes opened the folder: those of the manifest it holds.
        let text = fs::read_to_string(dir.join("manifest.json")).unwrap();
        let winner = usize::from(text.contains("\"sweep\":1"));
        for (sweep, ok) in outcomes {
            assert_eq!(ok, sweep == winner, "round {round}: {text}");
        }
        // No temporary file is left.
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
        fs::remove_dir_all(&dir).unwrap();
    }
}
