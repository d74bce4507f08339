//! Writing the data behind each figure as CSV.
//!
//! Numbers are written so that they read back to the same `f64` bits: Rust's shortest
//! round-trip form, in plain notation for magnitudes in [1e-4, 1e15) and in exponent notation
//! (`1.5e-7`) otherwise; `NaN`, `inf` and `-inf` for the special values.
//! Text fields are quoted when they contain a comma, a quote or a line break.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// Formats a number for CSV (round-trips exactly; see the module docs).
pub fn fmt_f64(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || (1e-4..1e15).contains(&a) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Writes a number as [`fmt_f64`] formats it, without building a `String` (for long outputs).
pub fn write_f64(out: &mut impl Write, v: f64) -> io::Result<()> {
    let a = v.abs();
    if v == 0.0 || (1e-4..1e15).contains(&a) || !v.is_finite() {
        write!(out, "{v}")
    } else {
        write!(out, "{v:e}")
    }
}

/// Quotes a text field if it needs it.
pub fn quote(field: &str) -> String {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_string()
    }
}

/// Creates the parent folder of `path` if it does not exist.
pub fn ensure_parent(path: &Path) -> io::Result<()> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => fs::create_dir_all(dir),
        _ => Ok(()),
    }
}

/// A CSV file being written, row by row.
pub struct CsvWriter {
    out: BufWriter<File>,
    path: PathBuf,
    columns: usize,
}

impl CsvWriter {
    /// Creates (or truncates) the file, creating its folder, and writes the header line.
    pub fn create(path: impl AsRef<Path>, header: &[&str]) -> io::Result<Self> {
        let path = path.as_ref().to_path_buf();
        ensure_parent(&path)?;
        let file = File::create(&path).map_err(|e| with_path(e, &path))?;
        let mut w = CsvWriter {
            out: BufWriter::new(file),
            path,
            columns: header.len(),
        };
        let line: Vec<String> = header.iter().map(|h| quote(h)).collect();
        w.line(&line.join(","))?;
        Ok(w)
    }

    fn line(&mut self, text: &str) -> io::Result<()> {
        let path = self.path.clone();
        writeln!(self.out, "{text}").map_err(|e| with_path(e, &path))
    }

    fn check(&self, n: usize) -> io::Result<()> {
        if n == self.columns {
            Ok(())
        } else {
            Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "{}: row has {n} fields but the header has {}",
                    self.path.display(),
                    self.columns
                ),
            ))
        }
    }

    /// Writes a row of numbers.
    pub fn row(&mut self, values: &[f64]) -> io::Result<()> {
        self.check(values.len())?;
        let fields: Vec<String> = values.iter().map(|&v| fmt_f64(v)).collect();
        self.line(&fields.join(","))
    }

    /// Writes a row of already formatted fields (text is quoted as needed).
    pub fn record<S: AsRef<str>>(&mut self, fields: &[S]) -> io::Result<()> {
        self.check(fields.len())?;
        let fields: Vec<String> = fields.iter().map(|f| quote(f.as_ref())).collect();
        self.line(&fields.join(","))
    }

    /// Flushes the file; call it at the end to see write errors (dropping also flushes, but
    /// silently).
    pub fn finish(mut self) -> io::Result<()> {
        let path = self.path.clone();
        self.out.flush().map_err(|e| with_path(e, &path))
    }
}

fn with_path(e: io::Error, path: &Path) -> io::Error {
    io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// Writes a whole table of numbers: the header, then one line per row.
pub fn write_csv<R: AsRef<[f64]>>(
    path: impl AsRef<Path>,
    header: &[&str],
    rows: impl IntoIterator<Item = R>,
) -> io::Result<()> {
    let mut w = CsvWriter::create(path, header)?;
    for r in rows {
        w.row(r.as_ref())?;
    }
    w.finish()
}
