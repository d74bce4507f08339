//! Resumed sweeps refuse what they cannot continue (issue 16, item 6): a folder records the
//! grid, every setting of the scan's `AttractorOptions`, the crate's version and its results
//! version; a resume with another setting, another grid of the same size, or from a folder
//! of another results version is an error naming the field and both values. A resume with
//! the same everything continues and equals one uninterrupted run bit for bit.

use std::fs;
use std::path::{Path, PathBuf};

use jeffcott::global::{
    run_points, scan_grid, AttractorOptions, Grid2, GridScan, RunOptions, StoreError, SweepStore,
    CRATE_VERSION, FORMAT_VERSION, RESULTS_VERSION,
};
use jeffcott::paper::{BasinPlane, StartPlane};
use jeffcott::params::Preset;
use serde_json::{json, Value};

fn temp_dir(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let target = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let dir = target.join("global_resume_test").join(name);
    let _ = fs::remove_dir_all(&dir);
    dir
}

/// Short runs: the tests are about the folder, not the attractors.
fn quick() -> AttractorOptions {
    AttractorOptions::default()
        .with_transient(100)
        .with_record(32)
        .with_max_transient(100)
}

fn plane() -> BasinPlane {
    BasinPlane::new(Preset::Fig8a.params().with_eta(2.2), StartPlane::XVx)
}

fn grid() -> Grid2 {
    Grid2::linspace((0.2, 0.8, 2), (0.0, 0.5, 2)).unwrap()
}

/// The sweep's description: the plane (its parameters).
fn description() -> BasinPlane {
    plane()
}

fn one_thread() -> RunOptions {
    RunOptions::default().with_threads(1)
}

/// A folder of `grid()` with `quick()` in which the first point is recorded.
fn started(name: &str) -> PathBuf {
    let dir = temp_dir(name);
    let store = SweepStore::open_scan(&dir, "basins", &description(), &grid(), &quick()).unwrap();
    let first = scan_grid(
        &grid(),
        plane().setup(),
        &quick(),
        Some(&store),
        &one_thread().with_max_new_points(1),
        None,
    )
    .unwrap();
    assert_eq!(first.results.computed, 1);
    dir
}

/// Resumes the folder `dir` with `config` over `grid`, as a user would: opening it for this
/// scan, then scanning.
fn resume(dir: &Path, grid: &Grid2, config: &AttractorOptions) -> Result<GridScan, StoreError> {
    let store = SweepStore::open_scan(dir, "basins", &description(), grid, config)?;
    scan_grid(
        grid,
        plane().setup(),
        config,
        Some(&store),
        &one_thread(),
        None,
    )
}

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

#[test]
fn a_resume_with_another_setting_is_refused_naming_it() {
    let dir = started("setting");
    let mut other = quick();
    let stored = other.opts.samples_per_step();
    other.opts.event_samples = Some(stored + 1);
    match resume(&dir, &grid(), &other) {
        Err(StoreError::SettingMismatch {
            setting,
            expected,
            found,
            ..
        }) => assert_eq!(
            (&*setting, &*expected, &*found),
            (
                "settings.opts.event_samples",
                &*(stored + 1).to_string(),
                // Stored: the method's default, `None`.
                "null"
            )
        ),
        other => panic!("{:?}", other.map(|s| s.results.computed)),
    }
    let other = quick().with_transient(200);
    let err = resume(&dir, &grid(), &other).unwrap_err();
    assert!(
        matches!(&err, StoreError::SettingMismatch { setting, .. } if setting == "settings.transient"),
        "{err}"
    );
    assert!(
        err.to_string().contains("settings.transient = 100"),
        "{err}"
    );
}

#[test]
fn a_scan_with_another_config_than_its_open_folder_is_refused() {
    // The folder opened for one config, the scan called with another (before: it went on).
    let dir = started("config");
    let store = SweepStore::open_scan(&dir, "basins", &description(), &grid(), &quick()).unwrap();
    let other = quick().with_record(40);
    let err = scan_grid(
        &grid(),
        plane().setup(),
        &other,
        Some(&store),
        &one_thread(),
        None,
    )
    .unwrap_err();
    assert!(
        matches!(&err, StoreError::SettingMismatch { setting, expected, found, .. }
            if setting == "settings.record" && expected == "40" && found == "32"),
        "{err}"
    );
    // A folder opened without the scan's settings cannot tell: refused too.
    let plain = temp_dir("config-plain");
    let store = SweepStore::open(&plain, "basins", &description(), &grid().points()).unwrap();
    let err = scan_grid(
        &grid(),
        plane().setup(),
        &quick(),
        Some(&store),
        &one_thread(),
        None,
    )
    .unwrap_err();
    assert!(
        matches!(err, StoreError::SettingsNotRecorded { .. }),
        "{err}"
    );
}

#[test]
fn a_scan_over_another_grid_of_the_same_size_is_refused() {
    // Before: `run_points` compared only the number of points.
    let dir = started("grid");
    let store = SweepStore::open_scan(&dir, "basins", &description(), &grid(), &quick()).unwrap();
    let moved = Grid2::linspace((0.3, 0.9, 2), (0.0, 0.5, 2)).unwrap();
    let err = scan_grid(
        &moved,
        plane().setup(),
        &quick(),
        Some(&store),
        &one_thread(),
        None,
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            StoreError::Mismatch {
                field: "fingerprint (the points)",
                ..
            }
        ),
        "{err}"
    );
    // And through the plain runner.
    let points = [1.0, 2.0];
    let plain = temp_dir("grid-plain");
    let store = SweepStore::open(&plain, "squares", &(), &points).unwrap();
    let square = |x: &f64| Ok::<f64, String>(x * x);
    let err = run_points(&[1.0, 3.0], Some(&store), &one_thread(), square, None).unwrap_err();
    assert!(matches!(err, StoreError::Mismatch { .. }), "{err}");
}

/// The manifest's JSON.
fn manifest(dir: &Path) -> Value {
    let text = fs::read_to_string(dir.join("manifest.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn the_manifest_records_the_versions_and_every_setting() {
    let dir = started("manifest");
    let m = manifest(&dir);
    assert_eq!(
        m.get("crate_version").and_then(Value::as_str),
        Some(env!("CARGO_PKG_VERSION"))
    );
    assert_eq!(CRATE_VERSION, env!("CARGO_PKG_VERSION"));
    assert_eq!(
        m.get("results_version").and_then(Value::as_u64),
        Some(RESULTS_VERSION)
    );
    assert_eq!(
        m.get("format").and_then(Value::as_u64),
        Some(FORMAT_VERSION)
    );
    assert_eq!(m.get("settings"), Some(&json!(quick())));
    assert_eq!(m.get("description"), Some(&json!(description())));
    // Every field of the config, its SimOptions and its period test is among the settings (by
    // name).
    let settings = &m["settings"];
    for key in [
        "opts/method",
        "opts/rtol",
        "opts/atol",
        "opts/steps_per_period",
        "opts/max_step_fraction",
        "opts/event_samples",
        "opts/max_events_per_period",
        "opts/max_steps",
        "period_test/max_period",
        "period_test/tol",
        "free_label",
        "transient",
        "record",
        "max_transient",
    ] {
        let at = format!("/{key}");
        assert!(settings.pointer(&at).is_some(), "{key} not recorded");
    }
}

/// Rewrites one top-level key of the folder's manifest.
fn edit_manifest(dir: &Path, key: &str, value: Value) {
    let mut m = manifest(dir);
    let slot = m.get_mut(key).expect("a key of the manifest");
    *slot = value;
    fs::write(dir.join("manifest.json"), m.to_string()).unwrap();
}

#[test]
fn a_folder_of_another_results_version_is_refused() {
    let dir = started("results-version");
    edit_manifest(&dir, "results_version", json!(RESULTS_VERSION + 1));
    edit_manifest(&dir, "crate_version", json!("9.9.9"));
    let err = resume(&dir, &grid(), &quick()).unwrap_err();
    match &err {
        StoreError::ResultsVersion {
            found,
            found_crate,
            expected,
            crate_version,
            ..
        } => {
            assert_eq!(
                (*found, found_crate.as_str(), *expected, *crate_version),
                (RESULTS_VERSION + 1, "9.9.9", RESULTS_VERSION, CRATE_VERSION)
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(err.to_string().contains("jeffcott 9.9.9"), "{err}");
    // Another crate version of the same results version resumes (its results are this one's).
    let dir = started("crate-version");
    edit_manifest(&dir, "crate_version", json!("0.0.1"));
    let store = SweepStore::open_scan(&dir, "basins", &description(), &grid(), &quick()).unwrap();
    assert_eq!(store.manifest().crate_version, "0.0.1");
    let scan = resume(&dir, &grid(), &quick()).unwrap();
    assert_eq!((scan.results.reused, scan.results.computed), (1, 3));
}

#[test]
fn a_resume_with_the_same_settings_equals_one_run_bitwise() {
    let dir = started("same");
    let resumed = resume(&dir, &grid(), &quick()).unwrap();
    assert_eq!((resumed.results.reused, resumed.results.computed), (1, 3));
    let whole = scan_grid(
        &grid(),
        plane().setup(),
        &quick(),
        None,
        &one_thread(),
        None,
    )
    .unwrap();
    assert_eq!(texts(&resumed), texts(&whole));
    assert_eq!(resumed.results.results, whole.results.results);
}

#[test]
fn a_folder_of_the_old_format_is_refused_with_a_typed_error() {
    // A folder as jeffcott 0.2.0 wrote it (format 2, its own JSON: whole numbers as `2.0`).
    let dir = temp_dir("format-2");
    fs::create_dir_all(&dir).unwrap();
    let old = r#"{"format":2.0,"crate_version":"0.2.0","results_version":1.0,"kind":"basins","points":4.0,"fingerprint":"00000000000000ff","settings":{"transient":100.0,"record":32.0},"description":null}"#;
    fs::write(dir.join("manifest.json"), format!("{old}\n")).unwrap();
    let line = r#"{"index":0.0,"point":[0.2,0.0],"error":{"kind":"build","message":"x"}}"#;
    fs::write(dir.join("records-0.jsonl"), format!("{line}\n")).unwrap();
    let err = resume(&dir, &grid(), &quick()).unwrap_err();
    match &err {
        StoreError::Format {
            found, expected, ..
        } => assert_eq!((*found, *expected), (2, FORMAT_VERSION)),
        other => panic!("{other:?}"),
    }
    assert!(err.to_string().contains("format 2"), "{err}");
    // Nothing in the folder was touched.
    assert_eq!(
        fs::read_to_string(dir.join("manifest.json")).unwrap(),
        format!("{old}\n")
    );
    // A manifest without a format at all is not a manifest of this crate: corrupt.
    fs::write(dir.join("manifest.json"), "{\"kind\":\"basins\"}\n").unwrap();
    let err = resume(&dir, &grid(), &quick()).unwrap_err();
    assert!(matches!(err, StoreError::Corrupt { .. }), "{err}");
}
