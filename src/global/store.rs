//! A sweep's output folder: a manifest saying which sweep it holds, and its records, one JSON
//! object a line, written as points finish.
//!
//! # The folder
//!
//! * `manifest.json`: `{"format": 2, "crate_version": "0.2.0", "results_version": 1, "kind":
//!   "...", "points": N, "fingerprint": "<16 hex digits>", "settings": {...}, "description":
//!   {...}}`, written when the folder is created and checked whenever it is opened again:
//!   * `crate_version` and `results_version` are written by the crate ([`CRATE_VERSION`],
//!     [`RESULTS_VERSION`]); a folder of another results version is refused
//!     ([`StoreError::ResultsVersion`]): its records were computed by a version whose results
//!     differ from this one's. A folder of another crate version with the same results
//!     version is resumed.
//!   * `fingerprint` is the 64-bit FNV-1a hash of the points' JSON, one a line (the grid).
//!   * `settings` are the computation's settings, recorded by the crate: for
//!     [`super::scan_grid`] every field of its [`super::AttractorConfig`]
//!     ([`SweepStore::open_scan`]); `null` for a folder opened with [`SweepStore::open`].
//!   * `kind` and `description` are the caller's: what the sweep computes, and what the crate
//!     cannot see, e.g. the model's parameters that the caller's `setup` closure uses.
//!
//!   A folder whose manifest differs from the sweep being run is refused
//!   ([`StoreError::Mismatch`], [`StoreError::SettingMismatch`] naming the setting, the
//!   folder's value and this run's): results of one sweep are never mixed into another, and a
//!   sweep is resumed only with the settings it was started with.
//! * `records-<w>.jsonl`, one file per writer `w` (the process, or the MPI rank), and
//!   `records-shard-<i>-of-<n>.jsonl`, one per shard of a sweep split into independent
//!   processes ([`super::Shard`], e.g. the tasks of a job array); each line one point:
//!   `{"index": i, "point": <the point>, "ok": <the result>}` or
//!   `{"index": i, "point": <the point>, "error": <the error>}`. `index` is the point's position
//!   in the sweep's list, so the order of the lines never matters. Reading the folder merges
//!   every records file: no file is written by two processes at once, so no file locking is
//!   needed, on a shared file system neither.
//!
//! Several processes may open the same new folder at once (the shards of a job array): the
//! manifest is written whole to a temporary file and linked to `manifest.json` only if there
//! is none yet (an atomic create-if-absent, also on NFS), then read back and checked: exactly
//! one manifest is created, and a process of another sweep is refused.
//!
//! # Crashes and restarts
//!
//! A record is written with one `write` call as soon as its point finishes. A process killed
//! in the middle of a write leaves at most a partial last line without its line break: readers
//! ignore it, and the next writer of that file cuts it off before appending. On reading, a
//! point recorded twice (a rare race of two writers) keeps its first record, in the order of
//! the file names and the lines; the others are counted in [`Loaded::duplicates`]. A complete
//! line that is not a valid record is an error ([`StoreError::Corrupt`]), not silently redone.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufRead, BufReader, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use thiserror::Error;

use super::json::{Json, JsonError};
use super::record::{field, Record};
use crate::analysis::AnalysisError;

/// Version of the folder layout and record format written in the manifest (2: the manifest
/// records the crate's version, its results version and the computation's settings).
pub const FORMAT_VERSION: u64 = 2;

/// Version of the crate's *results*, written in every manifest: bumped by every release
/// whose changes move the outcome of a sweep's point (integrators, event location, the ring's
/// rules, the period test, attractor identification, record encoding). A folder written with
/// another results version is not resumed ([`StoreError::ResultsVersion`]).
pub const RESULTS_VERSION: u64 = 1;

/// The crate's version (`CARGO_PKG_VERSION`), written in every manifest.
pub const CRATE_VERSION: &str = env!("CARGO_PKG_VERSION");

/// File name of the manifest.
pub const MANIFEST_FILE: &str = "manifest.json";

/// What went wrong with a sweep's folder or its configuration.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum StoreError {
    /// Reading or writing a file failed.
    #[error("{}: {message}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The system's message.
        message: String,
    },
    /// The folder holds another sweep (or another version of this one).
    #[error("{}: the folder holds another sweep: {field} is {found}, this sweep has {expected}; use a new folder (or delete this one to start over)", path.display())]
    Mismatch {
        /// The manifest.
        path: PathBuf,
        /// The field that differs.
        field: &'static str,
        /// This sweep's value.
        expected: String,
        /// The folder's value.
        found: String,
    },
    /// A setting (or a key of the caller's description) differs from the folder's: resuming
    /// would mix results of two sweeps.
    #[error("{}: the folder's sweep was run with {setting} = {found}, this run has {setting} = {expected}; resume with the folder's settings, or use a new folder", path.display())]
    SettingMismatch {
        /// The manifest.
        path: PathBuf,
        /// The setting that differs, as a path into the manifest (e.g.
        /// `settings.transient`, `description.plane.eta`).
        setting: String,
        /// This run's value (JSON; `absent` if this run has no such key).
        expected: String,
        /// The folder's value (JSON; `absent` if the folder has no such key).
        found: String,
    },
    /// The folder was written by a version of the crate whose results differ from this one's.
    #[error("{}: written by jeffcott {found_crate} (results version {found}); this is jeffcott {crate_version} (results version {expected}), whose results differ: resuming would mix results of both versions; use a new folder (or delete this one to start over)", path.display())]
    ResultsVersion {
        /// The manifest.
        path: PathBuf,
        /// The folder's results version.
        found: u64,
        /// The crate version that wrote the folder.
        found_crate: String,
        /// This crate's results version ([`RESULTS_VERSION`]).
        expected: u64,
        /// This crate's version ([`CRATE_VERSION`]).
        crate_version: &'static str,
    },
    /// A scan was given a folder opened without its settings ([`SweepStore::open`] instead of
    /// [`SweepStore::open_scan`]): the folder could not tell a resume with other settings.
    #[error("{}: the folder does not record the {needed} of the scan (opened with SweepStore::open); open it with SweepStore::open_scan", path.display())]
    SettingsNotRecorded {
        /// The manifest.
        path: PathBuf,
        /// The settings the computation needs recorded (e.g. `"AttractorConfig"`).
        needed: &'static str,
    },
    /// A complete line of a records file (or the manifest) is not a valid record.
    #[error("{}, line {line}: not a valid record ({error}); the file was changed by hand or written by another program: move it away and restart", path.display())]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// Line number (from 1).
        line: usize,
        /// What is wrong with it.
        error: JsonError,
    },
    /// A record's index is not a point of this sweep.
    #[error("{}, line {line}: index {index} but the sweep has {points} points", path.display())]
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// Line number (from 1).
        line: usize,
        /// The index found.
        index: usize,
        /// Number of points of the sweep.
        points: usize,
    },
    /// A bad setting of the run (e.g. 0 threads).
    #[error(transparent)]
    Config(#[from] AnalysisError),
    /// A shard that does not exist: `count` 0, or `index` not below `count`
    /// ([`super::Shard::new`]).
    #[error("shard {index}/{count}: {}", shard_rule(field, *count))]
    InvalidShard {
        /// The field that is wrong: `"count"` or `"index"`.
        field: &'static str,
        /// The shard's index given.
        index: usize,
        /// The number of shards given.
        count: usize,
    },
    /// Text that is not a shard `i/n` ([`super::Shard`]'s `FromStr`).
    #[error("{text:?} is not a shard: expected i/n, two whole numbers (e.g. 2/8, the shard 2 of 0 to 7)")]
    ShardSyntax {
        /// The text given.
        text: String,
    },
    /// The message-passing layer failed or the ranks disagree (feature `mpi`).
    #[error("MPI: {0}")]
    Mpi(String),
}

/// What a shard's `field` must satisfy, for [`StoreError::InvalidShard`].
fn shard_rule(field: &str, count: usize) -> String {
    if field == "count" {
        "the count of shards must be at least 1".to_string()
    } else {
        format!(
            "the index must be below the count (the shards of {count} are 0 to {})",
            count.saturating_sub(1)
        )
    }
}

pub(crate) fn io_err(path: &Path, e: io::Error) -> StoreError {
    StoreError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Which sweep a folder holds (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Manifest {
    /// What the sweep computes (e.g. `"basins"`).
    pub kind: String,
    /// Number of points.
    pub points: usize,
    /// FNV-1a hash of the points' JSON (one a line).
    pub fingerprint: u64,
    /// The computation's settings, recorded by the crate (`null` if it records none).
    pub settings: Json,
    /// The caller's description: every setting that changes the results and that the crate
    /// does not record itself (e.g. the model's parameters).
    pub description: Json,
    /// The crate version that wrote the folder ([`CRATE_VERSION`] for a new one).
    pub crate_version: String,
    /// The results version of that crate ([`RESULTS_VERSION`] for a new one).
    pub results_version: u64,
}

/// FNV-1a hash of the points' JSON, one a line.
pub(crate) fn fingerprint<P: Record>(points: &[P]) -> u64 {
    let mut hash = Fnv::new();
    for p in points {
        hash.write(p.to_json().to_string().as_bytes());
        hash.write(b"\n");
    }
    hash.0
}

impl Manifest {
    /// The manifest of a sweep of `kind` over `points`, without settings, by this crate
    /// version.
    pub fn new<P: Record>(kind: &str, description: Json, points: &[P]) -> Self {
        Manifest {
            kind: kind.to_string(),
            points: points.len(),
            fingerprint: fingerprint(points),
            settings: Json::Null,
            description,
            crate_version: CRATE_VERSION.to_string(),
            results_version: RESULTS_VERSION,
        }
    }

    /// The same manifest recording the computation's `settings`.
    pub fn with_settings(self, settings: Json) -> Self {
        Manifest { settings, ..self }
    }

    fn to_json(&self) -> Json {
        Json::object([
            ("format", Json::from(FORMAT_VERSION)),
            ("crate_version", Json::from(self.crate_version.as_str())),
            ("results_version", Json::from(self.results_version)),
            ("kind", Json::from(self.kind.as_str())),
            ("points", Json::from(self.points)),
            (
                "fingerprint",
                Json::from(format!("{:016x}", self.fingerprint)),
            ),
            ("settings", self.settings.clone()),
            ("description", self.description.clone()),
        ])
    }
}

/// 64-bit FNV-1a: a fixed, platform-independent hash.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// A sweep's output folder (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct SweepStore {
    dir: PathBuf,
    manifest: Manifest,
}

/// The records found in a folder.
#[derive(Debug, Clone, PartialEq)]
pub struct Loaded<T, E> {
    /// One slot per point: its recorded outcome, or `None` if not recorded yet.
    pub results: Vec<Option<Result<T, E>>>,
    /// Points recorded more than once (the first record is kept).
    pub duplicates: usize,
    /// Partial last lines ignored (a writer killed mid-write).
    pub partial_lines: usize,
}

impl<T, E> Loaded<T, E> {
    /// Number of points recorded.
    pub fn recorded(&self) -> usize {
        self.results.iter().filter(|r| r.is_some()).count()
    }
}

impl SweepStore {
    /// Opens the folder `dir` for the sweep of `kind` over `points` described by `description`,
    /// without settings recorded by the crate ([`Manifest::new`]): for [`super::run_points`]
    /// with the caller's own computation, whose settings `description` must hold. A scan opens
    /// its folder with [`SweepStore::open_scan`].
    ///
    /// # Errors
    /// As [`SweepStore::open_manifest`].
    pub fn open<P: Record>(
        dir: impl AsRef<Path>,
        kind: &str,
        description: Json,
        points: &[P],
    ) -> Result<Self, StoreError> {
        Self::open_manifest(dir, Manifest::new(kind, description, points))
    }

    /// Opens the folder `dir` for the sweep of `manifest`: creates it with its manifest if it
    /// does not exist (or holds no manifest), and checks that its manifest is this sweep's
    /// otherwise (see the [module docs](self)).
    ///
    /// # Errors
    /// [`StoreError::Io`] if the folder or manifest cannot be created or read;
    /// [`StoreError::ResultsVersion`] if it was written by a version of other results;
    /// [`StoreError::Mismatch`] if it holds another sweep (kind, points);
    /// [`StoreError::SettingMismatch`] if it was run with other settings or description;
    /// [`StoreError::Corrupt`] for an unreadable manifest.
    pub fn open_manifest(dir: impl AsRef<Path>, manifest: Manifest) -> Result<Self, StoreError> {
        let dir = dir.as_ref().to_path_buf();
        fs::create_dir_all(&dir).map_err(|e| io_err(&dir, e))?;
        let path = dir.join(MANIFEST_FILE);
        let mut manifest = manifest;
        let text = match fs::read_to_string(&path) {
            Ok(text) => text,
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                create_manifest(&dir, &path, &manifest)?;
                // Read back: another process may have created it first.
                fs::read_to_string(&path).map_err(|e| io_err(&path, e))?
            }
            Err(e) => return Err(io_err(&path, e)),
        };
        manifest.crate_version = check_manifest(&path, &text, &manifest)?;
        Ok(SweepStore { dir, manifest })
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The manifest of the sweep (its `crate_version` that of the crate that created the
    /// folder).
    pub fn manifest(&self) -> &Manifest {
        &self.manifest
    }

    /// The records file of writer `writer`.
    pub fn records_path(&self, writer: usize) -> PathBuf {
        self.dir.join(format!("records-{writer}.jsonl"))
    }

    /// The records file of shard `shard` ([`super::Shard`]):
    /// `records-shard-<index>-of-<count>.jsonl`.
    pub fn shard_records_path(&self, shard: super::Shard) -> PathBuf {
        self.dir.join(format!(
            "records-shard-{}-of-{}.jsonl",
            shard.index(),
            shard.count()
        ))
    }

    /// The records files present, in name order.
    fn records_files(&self) -> Result<Vec<PathBuf>, StoreError> {
        let mut files = Vec::new();
        for entry in fs::read_dir(&self.dir).map_err(|e| io_err(&self.dir, e))? {
            let entry = entry.map_err(|e| io_err(&self.dir, e))?;
            let name = entry.file_name();
            let name = name.to_string_lossy();
            if name.starts_with("records-") && name.ends_with(".jsonl") {
                files.push(entry.path());
            }
        }
        files.sort();
        Ok(files)
    }

    /// Reads every record in the folder.
    ///
    /// # Errors
    /// [`StoreError::Io`], or [`StoreError::Corrupt`] / [`StoreError::IndexOutOfRange`] for
    /// a complete line that is not a record of this sweep.
    pub fn load<T: Record, E: Record>(&self) -> Result<Loaded<T, E>, StoreError> {
        let n = self.manifest.points;
        let mut loaded = Loaded {
            results: (0..n).map(|_| None).collect(),
            duplicates: 0,
            partial_lines: 0,
        };
        for path in self.records_files()? {
            // Streamed line by line: a big sweep's records need not fit in memory twice.
            let file = File::open(&path).map_err(|e| io_err(&path, e))?;
            let mut reader = BufReader::new(file);
            let mut buf = Vec::new();
            for k in 0.. {
                buf.clear();
                let read = reader
                    .read_until(b'\n', &mut buf)
                    .map_err(|e| io_err(&path, e))?;
                if read == 0 {
                    break;
                }
                if buf.last() != Some(&b'\n') {
                    // A writer killed mid-write: ignored, and cut off by the next writer.
                    loaded.partial_lines += 1;
                    break;
                }
                let corrupt = |error| StoreError::Corrupt {
                    path: path.clone(),
                    line: k + 1,
                    error,
                };
                let line = std::str::from_utf8(&buf).map_err(|_| {
                    corrupt(JsonError::Syntax {
                        at: 0,
                        what: "UTF-8 text",
                    })
                })?;
                if line.trim().is_empty() {
                    continue;
                }
                let (index, outcome) = decode_line::<T, E>(line.trim_end()).map_err(corrupt)?;
                if index >= n {
                    return Err(StoreError::IndexOutOfRange {
                        path: path.clone(),
                        line: k + 1,
                        index,
                        points: n,
                    });
                }
                if loaded.results[index].is_some() {
                    loaded.duplicates += 1;
                } else {
                    loaded.results[index] = Some(outcome);
                }
            }
        }
        Ok(loaded)
    }

    /// Opens writer `writer`'s records file for appending, cutting off a partial last line.
    pub(crate) fn writer(&self, writer: usize) -> Result<RecordWriter, StoreError> {
        self.writer_at(self.records_path(writer))
    }

    /// Opens shard `shard`'s records file for appending, cutting off a partial last line.
    pub(crate) fn shard_writer(&self, shard: super::Shard) -> Result<RecordWriter, StoreError> {
        self.writer_at(self.shard_records_path(shard))
    }

    /// Opens the records file `path` for appending, cutting off a partial last line.
    fn writer_at(&self, path: PathBuf) -> Result<RecordWriter, StoreError> {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|e| io_err(&path, e))?;
        let len = file.metadata().map_err(|e| io_err(&path, e))?.len();
        if len > 0 {
            let keep = complete_length(&mut file, len).map_err(|e| io_err(&path, e))?;
            if keep < len {
                file.set_len(keep).map_err(|e| io_err(&path, e))?;
            }
        }
        file.seek(SeekFrom::End(0)).map_err(|e| io_err(&path, e))?;
        Ok(RecordWriter { file, path })
    }
}

/// Creates the manifest `path` of `manifest` unless it exists: written whole to a temporary
/// file of a name no other process uses, then hard-linked to `path`, which fails if `path`
/// exists (atomic, also on NFS): a reader never sees half a manifest, and of several processes
/// creating the folder at once exactly one manifest wins (the caller reads it back and checks
/// it). On a file system without hard links, renamed instead if `path` is still absent.
fn create_manifest(dir: &Path, path: &Path, manifest: &Manifest) -> Result<(), StoreError> {
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let unique = format!(
        "{}-{nanos}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
    );
    let tmp = dir.join(format!("{MANIFEST_FILE}.{unique}.tmp"));
    let mut text = manifest.to_json().to_string();
    text.push('\n');
    fs::write(&tmp, text).map_err(|e| io_err(&tmp, e))?;
    let linked = match fs::hard_link(&tmp, path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => Ok(()),
        Err(_) if !path.exists() => fs::rename(&tmp, path).map_err(|e| io_err(path, e)),
        Err(_) => Ok(()),
    };
    // Nothing to do if the rename moved it already.
    let _ = fs::remove_file(&tmp);
    linked
}

/// Length of the file up to and including its last line break.
fn complete_length(file: &mut File, len: u64) -> io::Result<u64> {
    const BLOCK: u64 = 64 * 1024;
    let mut end = len;
    let mut buf = vec![0u8; BLOCK as usize];
    while end > 0 {
        let start = end.saturating_sub(BLOCK);
        let n = (end - start) as usize;
        file.seek(SeekFrom::Start(start))?;
        file.read_exact(&mut buf[..n])?;
        if let Some(pos) = buf[..n].iter().rposition(|&b| b == b'\n') {
            return Ok(start + pos as u64 + 1);
        }
        end = start;
    }
    Ok(0)
}

/// Checks the folder's manifest `text` against this sweep's; returns the crate version that
/// wrote it.
fn check_manifest(path: &Path, text: &str, expected: &Manifest) -> Result<String, StoreError> {
    let corrupt = |error| StoreError::Corrupt {
        path: path.to_path_buf(),
        line: 1,
        error,
    };
    let json = Json::parse(text.trim()).map_err(corrupt)?;
    let mismatch = |field, expected: String, found: String| StoreError::Mismatch {
        path: path.to_path_buf(),
        field,
        expected,
        found,
    };
    let format: u64 = field(&json, "format").map_err(corrupt)?;
    if format != FORMAT_VERSION {
        return Err(mismatch(
            "format",
            FORMAT_VERSION.to_string(),
            format.to_string(),
        ));
    }
    let found_crate: String = field(&json, "crate_version").map_err(corrupt)?;
    let results_version: u64 = field(&json, "results_version").map_err(corrupt)?;
    if results_version != expected.results_version {
        return Err(StoreError::ResultsVersion {
            path: path.to_path_buf(),
            found: results_version,
            found_crate,
            expected: expected.results_version,
            crate_version: CRATE_VERSION,
        });
    }
    let kind: String = field(&json, "kind").map_err(corrupt)?;
    if kind != expected.kind {
        return Err(mismatch("kind", expected.kind.clone(), kind));
    }
    let points: usize = field(&json, "points").map_err(corrupt)?;
    if points != expected.points {
        return Err(mismatch(
            "points",
            expected.points.to_string(),
            points.to_string(),
        ));
    }
    let fp: String = field(&json, "fingerprint").map_err(corrupt)?;
    let want = format!("{:016x}", expected.fingerprint);
    if fp != want {
        return Err(mismatch("fingerprint (the points)", want, fp));
    }
    for key in ["settings", "description"] {
        let found = json.field(key).map_err(corrupt)?;
        let given = if key == "settings" {
            &expected.settings
        } else {
            &expected.description
        };
        check_same(path, key, given, found)?;
    }
    Ok(found_crate)
}

/// [`StoreError::SettingMismatch`] naming the first key where `found` (the folder's) differs
/// from `given` (this run's), as a path from `name`.
pub(crate) fn check_same(
    path: &Path,
    name: &str,
    given: &Json,
    found: &Json,
) -> Result<(), StoreError> {
    match first_difference(name.to_string(), given, found) {
        None => Ok(()),
        Some((setting, expected, found)) => Err(StoreError::SettingMismatch {
            path: path.to_path_buf(),
            setting,
            expected,
            found,
        }),
    }
}

/// The path and both values of the first difference of two JSON values, descending into
/// objects key by key (`given`'s keys first, then keys only `found` has).
fn first_difference(at: String, given: &Json, found: &Json) -> Option<(String, String, String)> {
    const ABSENT: &str = "absent";
    if given == found {
        return None;
    }
    if let (Json::Object(g), Json::Object(f)) = (given, found) {
        for (k, gv) in g {
            let at = format!("{at}.{k}");
            match found.get(k) {
                Some(fv) => {
                    if let Some(d) = first_difference(at, gv, fv) {
                        return Some(d);
                    }
                }
                None => return Some((at, gv.to_string(), ABSENT.into())),
            }
        }
        if let Some((k, fv)) = f.iter().find(|(k, _)| given.get(k).is_none()) {
            return Some((format!("{at}.{k}"), ABSENT.into(), fv.to_string()));
        }
    }
    // Same keys and values in another order, or values of other shapes.
    Some((at, given.to_string(), found.to_string()))
}

/// One writer's records file, open for appending.
#[derive(Debug)]
pub(crate) struct RecordWriter {
    file: File,
    path: PathBuf,
}

impl RecordWriter {
    /// Appends one line (`line` without its line break) in a single write.
    pub(crate) fn append(&mut self, line: &str) -> Result<(), StoreError> {
        let mut buf = Vec::with_capacity(line.len() + 1);
        buf.extend_from_slice(line.as_bytes());
        buf.push(b'\n');
        self.file.write_all(&buf).map_err(|e| io_err(&self.path, e))
    }
}

/// The record line of point `index` (without its line break).
pub(crate) fn encode_line<P: Record, T: Record, E: Record>(
    index: usize,
    point: &P,
    outcome: &Result<T, E>,
) -> String {
    let (key, value) = match outcome {
        Ok(t) => ("ok", t.to_json()),
        Err(e) => ("error", e.to_json()),
    };
    Json::object([
        ("index", Json::from(index)),
        ("point", point.to_json()),
        (key, value),
    ])
    .to_string()
}

/// The index and outcome of a record line.
pub(crate) fn decode_line<T: Record, E: Record>(
    line: &str,
) -> Result<(usize, Result<T, E>), JsonError> {
    let json = Json::parse(line)?;
    let index: usize = field(&json, "index")?;
    let outcome = match (json.get("ok"), json.get("error")) {
        (Some(_), None) => Ok(field::<T>(&json, "ok")?),
        (None, Some(_)) => Err(field::<E>(&json, "error")?),
        _ => {
            return Err(JsonError::shape(
                "",
                "exactly one of the keys `ok` and `error`",
                &json,
            ))
        }
    };
    Ok((index, outcome))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("jeffcott-store-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn a_folder_of_another_sweep_is_refused() {
        let dir = temp_dir("mismatch");
        let points = [1.0, 2.0];
        let desc = Json::object([("eta", Json::from(2.2))]);
        SweepStore::open(&dir, "test", desc.clone(), &points).unwrap();
        SweepStore::open(&dir, "test", desc.clone(), &points).unwrap();
        let err = SweepStore::open(&dir, "test", desc.clone(), &[1.0, 2.5]).unwrap_err();
        assert!(
            matches!(err, StoreError::Mismatch { field, .. } if field.starts_with("fingerprint"))
        );
        let other = Json::object([("eta", Json::from(2.3))]);
        let err = SweepStore::open(&dir, "test", other, &points).unwrap_err();
        match err {
            StoreError::SettingMismatch {
                setting,
                expected,
                found,
                ..
            } => assert_eq!(
                (&*setting, &*expected, &*found),
                ("description.eta", "2.3", "2.2")
            ),
            other => panic!("{other:?}"),
        }
        let err = SweepStore::open(&dir, "other", desc, &points).unwrap_err();
        assert!(matches!(err, StoreError::Mismatch { field: "kind", .. }));
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_partial_last_line_is_ignored_then_cut_off() {
        let dir = temp_dir("partial");
        let points = [10.0, 20.0, 30.0];
        let store = SweepStore::open(&dir, "test", Json::Null, &points).unwrap();
        let full = encode_line::<f64, f64, String>(0, &10.0, &Ok(0.5));
        let half = encode_line::<f64, f64, String>(2, &30.0, &Err("bad".into()));
        fs::write(store.records_path(0), format!("{full}\n{}", &half[..10])).unwrap();
        let loaded = store.load::<f64, String>().unwrap();
        assert_eq!(loaded.partial_lines, 1);
        assert_eq!(loaded.results, vec![Some(Ok(0.5)), None, None]);
        let mut w = store.writer(0).unwrap();
        w.append(&half).unwrap();
        let loaded = store.load::<f64, String>().unwrap();
        assert_eq!(loaded.partial_lines, 0);
        assert_eq!(
            loaded.results,
            vec![Some(Ok(0.5)), None, Some(Err("bad".to_string()))]
        );
        // A complete line that is not a record is an error, with its line number.
        fs::write(store.records_path(1), "{\"index\": 1}\n").unwrap();
        match store.load::<f64, String>() {
            Err(StoreError::Corrupt { line: 1, .. }) => {}
            other => panic!("{other:?}"),
        }
        fs::write(
            store.records_path(1),
            format!("{}\n", full.replace("\"index\":0", "\"index\":7")),
        )
        .unwrap();
        assert!(matches!(
            store.load::<f64, String>(),
            Err(StoreError::IndexOutOfRange { index: 7, .. })
        ));
        fs::remove_dir_all(&dir).unwrap();
    }
}
