use std::fs::{self, File, OpenOptions};
use std::io::{self, BufRead, BufReader, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_json::Value;
use thiserror::Error;

use super::record::Record;
use crate::analysis::AnalysisError;

/// Version of the folder layout and record format written in the manifest (3: the records are
/// serde's JSON of the values; 2, of jeffcott 0.2.0, wrote its own).
pub const FORMAT_VERSION: u64 = 3;

/// Version of the crate's *results*, written in every manifest: bumped by every release
/// whose changes move the outcome of a sweep's point (integrators, event location, the ring's
/// rules, the period test, attractor identification, record encoding). A folder written with
/// another results version is not resumed ([`StoreError::ResultsVersion`]).
pub const RESULTS_VERSION: u64 = 1;

/// The crate's version (`CARGO_PKG_VERSION`), written in every manifest.
pub const CRATE_VERSION: &str = env!("CARGO_PKG_VERSION");

/// File name of the manifest.
pub(crate) const MANIFEST_FILE: &str = "manifest.json";

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
    /// The folder was written in another layout or record format ([`FORMAT_VERSION`]).
    #[error("{}: written in the folder format {found}; this is jeffcott {crate_version}, which reads format {expected} only: finish the sweep with the version that started it, or use a new folder", path.display())]
    Format {
        /// The manifest.
        path: PathBuf,
        /// The folder's format.
        found: u64,
        /// This crate's format ([`FORMAT_VERSION`]).
        expected: u64,
        /// This crate's version ([`CRATE_VERSION`]).
        crate_version: &'static str,
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
        /// The settings the computation needs recorded (e.g. `"AttractorOptions"`).
        needed: &'static str,
    },
    /// A complete line of a records file (or the manifest) is not a valid record.
    #[error("{}, line {line}: not a valid record ({message}); the file was changed by hand or written by another program: move it away and restart", path.display())]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// Line number (from 1).
        line: usize,
        /// What is wrong with it (serde_json's message, with the column).
        message: String,
    },
    /// A value could not be written as JSON (its `Serialize` failed, e.g. a map whose keys
    /// are not strings).
    #[error("{what} cannot be written as JSON: {message}")]
    Encode {
        /// Which value: `point 17`, `the outcome of point 17`, `the description`, `the
        /// settings`.
        what: String,
        /// serde_json's message.
        message: String,
    },
    /// The outcome of a point does not read back from its record (not written: the run
    /// stops). Typically a NaN or an infinity, which JSON writes as `null` (see
    /// [`Record`]).
    #[error("the outcome of point {index} does not read back from its record ({message}); JSON has no NaN or infinity (written as null): hold such a value in an Option<f64>, or return an error for the point")]
    RoundTrip {
        /// The point.
        index: usize,
        /// serde_json's message.
        message: String,
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

/// Which sweep a folder holds (see the [module docs](super)).
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
    pub settings: Value,
    /// The caller's description: every setting that changes the results and that the crate
    /// does not record itself (e.g. the model's parameters).
    pub description: Value,
    /// The crate version that wrote the folder ([`CRATE_VERSION`] for a new one).
    pub crate_version: String,
    /// The results version of that crate ([`RESULTS_VERSION`] for a new one).
    pub results_version: u64,
}

/// The manifest as written, in this order.
#[derive(Serialize, Deserialize)]
struct ManifestFile {
    format: u64,
    crate_version: String,
    results_version: u64,
    kind: String,
    points: usize,
    fingerprint: String,
    settings: Value,
    description: Value,
}

/// FNV-1a hash of the points' JSON, one a line.
///
/// # Errors
/// [`StoreError::Encode`] for a point that cannot be written.
pub(crate) fn fingerprint<P: Record>(points: &[P]) -> Result<u64, StoreError> {
    let mut hash = Fnv::new();
    for (i, p) in points.iter().enumerate() {
        serde_json::to_writer(&mut hash, p).map_err(|e| encode_err(format!("point {i}"), &e))?;
        hash.update(b"\n");
    }
    Ok(hash.0)
}

/// `value` as JSON, or [`StoreError::Encode`] naming it `what`.
fn to_value<V: Serialize + ?Sized>(value: &V, what: &str) -> Result<Value, StoreError> {
    serde_json::to_value(value).map_err(|e| encode_err(what.to_string(), &e))
}

fn encode_err(what: String, e: &serde_json::Error) -> StoreError {
    StoreError::Encode {
        what,
        message: e.to_string(),
    }
}

impl Manifest {
    /// The manifest of a sweep of `kind` over `points`, without settings, by this crate
    /// version; `description` is any `Serialize` value (`&()` for none, written `null`).
    ///
    /// # Errors
    /// [`StoreError::Encode`] if a point or the description cannot be written as JSON.
    pub fn new<P: Record, D: Serialize + ?Sized>(
        kind: &str,
        description: &D,
        points: &[P],
    ) -> Result<Self, StoreError> {
        Ok(Manifest {
            kind: kind.to_string(),
            points: points.len(),
            fingerprint: fingerprint(points)?,
            settings: Value::Null,
            description: to_value(description, "the description")?,
            crate_version: CRATE_VERSION.to_string(),
            results_version: RESULTS_VERSION,
        })
    }

    /// The same manifest recording the computation's `settings`.
    ///
    /// # Errors
    /// [`StoreError::Encode`] if the settings cannot be written as JSON.
    pub fn with_settings<S: Serialize + ?Sized>(self, settings: &S) -> Result<Self, StoreError> {
        Ok(Manifest {
            settings: to_value(settings, "the settings")?,
            ..self
        })
    }

    fn to_file(&self) -> ManifestFile {
        ManifestFile {
            format: FORMAT_VERSION,
            crate_version: self.crate_version.clone(),
            results_version: self.results_version,
            kind: self.kind.clone(),
            points: self.points,
            fingerprint: format!("{:016x}", self.fingerprint),
            settings: self.settings.clone(),
            description: self.description.clone(),
        }
    }
}

/// 64-bit FNV-1a: a fixed, platform-independent hash.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// The points' JSON is hashed as it is written.
impl Write for Fnv {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.update(bytes);
        Ok(bytes.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// A sweep's output folder (see the [module docs](super)).
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
    /// As [`Manifest::new`] and [`SweepStore::open_manifest`].
    pub fn open<P: Record, D: Serialize + ?Sized>(
        dir: impl AsRef<Path>,
        kind: &str,
        description: &D,
        points: &[P],
    ) -> Result<Self, StoreError> {
        Self::open_manifest(dir, Manifest::new(kind, description, points)?)
    }

    /// Opens the folder `dir` for the sweep of `manifest`: creates it with its manifest if it
    /// does not exist (or holds no manifest), and checks that its manifest is this sweep's
    /// otherwise (see the [module docs](super)).
    ///
    /// # Errors
    /// [`StoreError::Io`] if the folder or manifest cannot be created or read;
    /// [`StoreError::Format`] if it was written in another folder format;
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
                let corrupt = |message| StoreError::Corrupt {
                    path: path.clone(),
                    line: k + 1,
                    message,
                };
                let line = std::str::from_utf8(&buf)
                    .map_err(|e| corrupt(format!("not UTF-8 text: {e}")))?;
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
    let mut text = serde_json::to_string(&manifest.to_file())
        .map_err(|e| encode_err("the manifest".into(), &e))?;
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
    let corrupt = |e: serde_json::Error| StoreError::Corrupt {
        path: path.to_path_buf(),
        line: e.line().max(1),
        message: e.to_string(),
    };
    let json: Value = serde_json::from_str(text).map_err(corrupt)?;
    // The format first, read leniently: format 2 wrote it as `2.0`.
    let format = json.get("format").and_then(Value::as_f64);
    if format != Some(FORMAT_VERSION as f64)
        && let Some(found) = format.filter(|f| f.fract() == 0.0 && *f >= 0.0)
    {
        return Err(StoreError::Format {
            path: path.to_path_buf(),
            found: found as u64,
            expected: FORMAT_VERSION,
            crate_version: CRATE_VERSION,
        });
    }
    let found: ManifestFile = serde_json::from_value(json).map_err(corrupt)?;
    let mismatch = |field, expected: String, found: String| StoreError::Mismatch {
        path: path.to_path_buf(),
        field,
        expected,
        found,
    };
    if found.results_version != expected.results_version {
        return Err(StoreError::ResultsVersion {
            path: path.to_path_buf(),
            found: found.results_version,
            found_crate: found.crate_version,
            expected: expected.results_version,
            crate_version: CRATE_VERSION,
        });
    }
    if found.kind != expected.kind {
        return Err(mismatch("kind", expected.kind.clone(), found.kind));
    }
    if found.points != expected.points {
        return Err(mismatch(
            "points",
            expected.points.to_string(),
            found.points.to_string(),
        ));
    }
    let want = format!("{:016x}", expected.fingerprint);
    if found.fingerprint != want {
        return Err(mismatch(
            "fingerprint (the points)",
            want,
            found.fingerprint,
        ));
    }
    check_same(path, "settings", &expected.settings, &found.settings)?;
    check_same(
        path,
        "description",
        &expected.description,
        &found.description,
    )?;
    Ok(found.crate_version)
}

/// [`StoreError::SettingMismatch`] naming the first key where `found` (the folder's) differs
/// from `given` (this run's), as a path from `name`.
pub(crate) fn check_same(
    path: &Path,
    name: &str,
    given: &Value,
    found: &Value,
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
/// objects key by key (`given`'s keys first, then keys only `found` has; each in key order).
fn first_difference(at: String, given: &Value, found: &Value) -> Option<(String, String, String)> {
    const ABSENT: &str = "absent";
    if given == found {
        return None;
    }
    if let (Value::Object(g), Value::Object(f)) = (given, found) {
        for (k, gv) in g {
            let at = format!("{at}.{k}");
            match f.get(k) {
                Some(fv) => {
                    if let Some(d) = first_difference(at, gv, fv) {
                        return Some(d);
                    }
                }
                None => return Some((at, gv.to_string(), ABSENT.into())),
            }
        }
        if let Some((k, fv)) = f.iter().find(|(k, _)| !g.contains_key(*k)) {
            return Some((format!("{at}.{k}"), ABSENT.into(), fv.to_string()));
        }
    }
    // Values of other shapes.
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

/// A record line as written.
#[derive(Serialize)]
struct LineOut<'a, P, T, E> {
    index: usize,
    point: &'a P,
    #[serde(skip_serializing_if = "Option::is_none")]
    ok: Option<&'a T>,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<&'a E>,
}

/// A record line as read: the point is not read back (the sweep's list has it).
#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    bound(deserialize = "T: Deserialize<'de>, E: Deserialize<'de>")
)]
struct LineIn<T, E> {
    index: usize,
    #[allow(dead_code)]
    point: serde::de::IgnoredAny,
    #[serde(default, deserialize_with = "present")]
    ok: Option<T>,
    #[serde(default, deserialize_with = "present")]
    error: Option<E>,
}

/// A key that is present: `Some` even if its value is `null` (an `ok` of type `Option<_>`).
fn present<'de, D: serde::Deserializer<'de>, T: Deserialize<'de>>(
    d: D,
) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

/// The record line of point `index` (without its line break).
///
/// # Errors
/// [`StoreError::Encode`] if the point or its outcome cannot be written.
pub(crate) fn encode_line<P: Record, T: Record, E: Record>(
    index: usize,
    point: &P,
    outcome: &Result<T, E>,
) -> Result<String, StoreError> {
    let line = LineOut {
        index,
        point,
        ok: outcome.as_ref().ok(),
        error: outcome.as_ref().err(),
    };
    serde_json::to_string(&line)
        .map_err(|e| encode_err(format!("the outcome of point {index}"), &e))
}

/// The index and outcome of a record line, or what is wrong with it.
pub(crate) fn decode_line<T: Record, E: Record>(
    line: &str,
) -> Result<(usize, Result<T, E>), String> {
    let read: LineIn<T, E> = serde_json::from_str(line).map_err(|e| e.to_string())?;
    match (read.ok, read.error) {
        (Some(t), None) => Ok((read.index, Ok(t))),
        (None, Some(e)) => Ok((read.index, Err(e))),
        _ => Err("not exactly one of the keys `ok` and `error`".into()),
    }
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
        let desc = serde_json::json!({"eta": 2.2});
        SweepStore::open(&dir, "test", &desc, &points).unwrap();
        SweepStore::open(&dir, "test", &desc, &points).unwrap();
        let err = SweepStore::open(&dir, "test", &desc, &[1.0, 2.5]).unwrap_err();
        assert!(
            matches!(err, StoreError::Mismatch { field, .. } if field.starts_with("fingerprint"))
        );
        let other = serde_json::json!({"eta": 2.3});
        let err = SweepStore::open(&dir, "test", &other, &points).unwrap_err();
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
        let err = SweepStore::open(&dir, "other", &desc, &points).unwrap_err();
        assert!(matches!(err, StoreError::Mismatch { field: "kind", .. }));
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_partial_last_line_is_ignored_then_cut_off() {
        let dir = temp_dir("partial");
        let points = [10.0, 20.0, 30.0];
        let store = SweepStore::open(&dir, "test", &(), &points).unwrap();
        let full = encode_line::<f64, f64, String>(0, &10.0, &Ok(0.5)).unwrap();
        let half = encode_line::<f64, f64, String>(2, &30.0, &Err("bad".into())).unwrap();
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
        for bad in [
            r#"{"index": 1}"#,
            r#"{"index": 1, "point": 20.0}"#,
            r#"{"index": 1, "point": 20.0, "ok": 1.0, "error": "x"}"#,
            r#"{"index": 1, "point": 20.0, "ok": "x"}"#,
            r#"{"index": 1.0, "point": 20.0, "ok": 1.0}"#,
            r#"{"index": 1, "point": 20.0, "ok": 1.0, "more": 1}"#,
        ] {
            fs::write(store.records_path(1), format!("{bad}\n")).unwrap();
            match store.load::<f64, String>() {
                Err(StoreError::Corrupt { line: 1, .. }) => {}
                other => panic!("{bad}: {other:?}"),
            }
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
