//! A tiny command-line flag parser for the examples (no dependencies).
//!
//! Flags are written `--name value` (or `--name=value`); `--help` or `-h` prints the usage.
//! Declare each flag with a typed getter, then call [`Cli::finish`]:
//!
//! ```ignore
//! let mut cli = Cli::new("Bifurcation diagram of x_r against eta (paper Fig. 8).");
//! let eta_min = cli.f64_in("eta-min", 2.0, 0.0, 100.0, "lowest forcing frequency");
//! let values = cli.usize_in("values", 300, 1, 100_000, "number of eta values");
//! let mode = cli.choice("mode", "carry", &["reset", "carry"], "how values are linked");
//! cli.finish(); // handles --help and unknown flags
//! ```
//!
//! On any bad input (unknown flag, missing value, not a number, NaN or infinity, out of range,
//! unknown choice, a flag given twice) the program prints one line to stderr, such as
//! `error: --eta expects a finite number, got "abc"`, and exits with status 2. Every getter
//! has a `try_` twin that returns the message instead, for tests.

use std::fmt::Display;

/// One declared flag, for the help text.
struct Spec {
    name: String,
    kind: &'static str,
    default: String,
    help: String,
}

/// What [`Cli::try_finish`] found.
#[derive(Debug, PartialEq)]
pub enum Finish {
    /// All flags are known and valid: run.
    Run,
    /// `--help` was given: this is the usage text.
    Help(String),
}

/// The parsed command line and the flags declared so far.
pub struct Cli {
    program: String,
    about: String,
    /// `(name, value)` pairs in command-line order, with a "used" mark.
    given: Vec<(String, String, bool)>,
    help: bool,
    parse_error: Option<String>,
    specs: Vec<Spec>,
}

impl Cli {
    /// Parses the process's own arguments.
    pub fn new(about: &str) -> Self {
        let mut args = std::env::args();
        let program = args
            .next()
            .map(|p| {
                std::path::Path::new(&p)
                    .file_name()
                    .map_or(p.clone(), |f| f.to_string_lossy().into_owned())
            })
            .unwrap_or_else(|| "example".to_string());
        Cli::from_args(&program, about, args)
    }

    /// Parses the given arguments (without the program name).
    pub fn from_args<I, S>(program: &str, about: &str, args: I) -> Self
    where
        I: IntoIterator<Item = S>,
        S: Into<String>,
    {
        let mut cli = Cli {
            program: program.to_string(),
            about: about.to_string(),
            given: Vec::new(),
            help: false,
            parse_error: None,
            specs: Vec::new(),
        };
        let args: Vec<String> = args.into_iter().map(Into::into).collect();
        let mut i = 0;
        while i < args.len() {
            let arg = &args[i];
            i += 1;
            if arg == "--help" || arg == "-h" {
                cli.help = true;
                continue;
            }
            let Some(body) = arg.strip_prefix("--").filter(|b| !b.is_empty()) else {
                cli.fail_parse(format!(
                    "unexpected argument \"{arg}\": flags are written --name value"
                ));
                continue;
            };
            let (name, value) = match body.split_once('=') {
                Some((n, v)) => (n.to_string(), Some(v.to_string())),
                None => {
                    let next = args.get(i).filter(|v| !v.starts_with("--"));
                    if next.is_some() {
                        i += 1;
                    }
                    (body.to_string(), next.cloned())
                }
            };
            let Some(value) = value else {
                cli.fail_parse(format!("--{name} expects a value"));
                continue;
            };
            if cli.given.iter().any(|(n, _, _)| *n == name) {
                cli.fail_parse(format!("--{name} is given twice"));
                continue;
            }
            cli.given.push((name, value, false));
        }
        cli
    }

    fn fail_parse(&mut self, msg: String) {
        if self.parse_error.is_none() {
            self.parse_error = Some(msg);
        }
    }

    /// Records the flag and returns its raw value, if given (and no earlier parse error).
    fn raw(
        &mut self,
        name: &str,
        kind: &'static str,
        default: String,
        help: String,
    ) -> Result<Option<String>, String> {
        self.specs.push(Spec {
            name: name.to_string(),
            kind,
            default,
            help,
        });
        if self.help {
            return Ok(None);
        }
        if let Some(e) = &self.parse_error {
            return Err(e.clone());
        }
        Ok(self
            .given
            .iter_mut()
            .find(|(n, _, _)| n == name)
            .map(|(_, v, used)| {
                *used = true;
                v.clone()
            }))
    }

    /// A finite real number.
    pub fn try_f64(&mut self, name: &str, default: f64, help: &str) -> Result<f64, String> {
        match self.raw(name, "number", default.to_string(), help.to_string())? {
            None => Ok(default),
            Some(v) => parse_f64(name, &v),
        }
    }

    /// A finite real number in `[lo, hi]`.
    pub fn try_f64_in(
        &mut self,
        name: &str,
        default: f64,
        lo: f64,
        hi: f64,
        help: &str,
    ) -> Result<f64, String> {
        let help = format!("{help} (range [{lo}, {hi}])");
        match self.raw(name, "number", default.to_string(), help)? {
            None => Ok(default),
            Some(v) => {
                let x = parse_f64(name, &v)?;
                if (lo..=hi).contains(&x) {
                    Ok(x)
                } else {
                    Err(format!("--{name} must be in [{lo}, {hi}], got {v}"))
                }
            }
        }
    }

    /// A whole number `≥ 0`.
    pub fn try_usize(&mut self, name: &str, default: usize, help: &str) -> Result<usize, String> {
        match self.raw(name, "count", default.to_string(), help.to_string())? {
            None => Ok(default),
            Some(v) => parse_usize(name, &v),
        }
    }

    /// A whole number in `[lo, hi]`.
    pub fn try_usize_in(
        &mut self,
        name: &str,
        default: usize,
        lo: usize,
        hi: usize,
        help: &str,
    ) -> Result<usize, String> {
        let help = format!("{help} (range {lo} to {hi})");
        match self.raw(name, "count", default.to_string(), help)? {
            None => Ok(default),
            Some(v) => {
                let x = parse_usize(name, &v)?;
                if (lo..=hi).contains(&x) {
                    Ok(x)
                } else {
                    Err(format!("--{name} must be between {lo} and {hi}, got {x}"))
                }
            }
        }
    }

    /// An optional whole number in `[lo, hi]` (no default: `None` when absent).
    pub fn try_opt_usize_in(
        &mut self,
        name: &str,
        lo: usize,
        hi: usize,
        help: &str,
    ) -> Result<Option<usize>, String> {
        let help = format!("{help} (range {lo} to {hi})");
        match self.raw(name, "count", "unset".to_string(), help)? {
            None => Ok(None),
            Some(v) => {
                let x = parse_usize(name, &v)?;
                if (lo..=hi).contains(&x) {
                    Ok(Some(x))
                } else {
                    Err(format!("--{name} must be between {lo} and {hi}, got {x}"))
                }
            }
        }
    }

    /// One of the `allowed` words.
    pub fn try_choice(
        &mut self,
        name: &str,
        default: &str,
        allowed: &[&str],
        help: &str,
    ) -> Result<String, String> {
        let help = format!("{help} (one of: {})", allowed.join(", "));
        match self.raw(name, "choice", default.to_string(), help)? {
            None => Ok(default.to_string()),
            Some(v) if allowed.contains(&v.as_str()) => Ok(v),
            Some(v) => Err(format!(
                "--{name} expects one of {}, got \"{v}\"",
                allowed.join(", ")
            )),
        }
    }

    /// Any non-empty text (a path, a label).
    pub fn try_string(&mut self, name: &str, default: &str, help: &str) -> Result<String, String> {
        match self.raw(name, "text", default.to_string(), help.to_string())? {
            None => Ok(default.to_string()),
            Some(v) if v.is_empty() => Err(format!("--{name} expects a non-empty value")),
            Some(v) => Ok(v),
        }
    }

    /// Ends the declarations: `Help` if `--help` was given, an error for a parse error or an
    /// unknown flag, `Run` otherwise.
    pub fn try_finish(&self) -> Result<Finish, String> {
        if self.help {
            return Ok(Finish::Help(self.help_text()));
        }
        if let Some(e) = &self.parse_error {
            return Err(e.clone());
        }
        if let Some((name, _, _)) = self.given.iter().find(|(_, _, used)| !used) {
            let known: Vec<String> = self.specs.iter().map(|s| format!("--{}", s.name)).collect();
            return Err(format!(
                "unknown flag --{name} (known: {}; see --help)",
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            ));
        }
        Ok(Finish::Run)
    }

    /// The usage text listing every declared flag.
    pub fn help_text(&self) -> String {
        let mut s = format!(
            "{}\n\nusage: {} [--flag value]...\n\nflags:\n",
            self.about, self.program
        );
        let width = self
            .specs
            .iter()
            .map(|f| f.name.len() + f.kind.len() + 5)
            .max()
            .unwrap_or(0);
        for f in &self.specs {
            let left = format!("--{} <{}>", f.name, f.kind);
            s.push_str(&format!(
                "  {left:width$}  {} [default: {}]\n",
                f.help, f.default
            ));
        }
        s.push_str(&format!("  {:width$}  print this help\n", "--help"));
        s
    }

    /// Unwraps a getter's result, or prints the error line and exits with status 2.
    fn or_exit<T>(&self, r: Result<T, String>) -> T {
        r.unwrap_or_else(|e| fail(e))
    }

    /// [`Cli::try_f64`], exiting with status 2 on bad input.
    pub fn f64(&mut self, name: &str, default: f64, help: &str) -> f64 {
        let r = self.try_f64(name, default, help);
        self.or_exit(r)
    }

    /// [`Cli::try_f64_in`], exiting with status 2 on bad input.
    pub fn f64_in(&mut self, name: &str, default: f64, lo: f64, hi: f64, help: &str) -> f64 {
        let r = self.try_f64_in(name, default, lo, hi, help);
        self.or_exit(r)
    }

    /// [`Cli::try_usize`], exiting with status 2 on bad input.
    pub fn usize(&mut self, name: &str, default: usize, help: &str) -> usize {
        let r = self.try_usize(name, default, help);
        self.or_exit(r)
    }

    /// [`Cli::try_usize_in`], exiting with status 2 on bad input.
    pub fn usize_in(
        &mut self,
        name: &str,
        default: usize,
        lo: usize,
        hi: usize,
        help: &str,
    ) -> usize {
        let r = self.try_usize_in(name, default, lo, hi, help);
        self.or_exit(r)
    }

    /// [`Cli::try_opt_usize_in`], exiting with status 2 on bad input.
    pub fn opt_usize_in(&mut self, name: &str, lo: usize, hi: usize, help: &str) -> Option<usize> {
        let r = self.try_opt_usize_in(name, lo, hi, help);
        self.or_exit(r)
    }

    /// [`Cli::try_choice`], exiting with status 2 on bad input.
    pub fn choice(&mut self, name: &str, default: &str, allowed: &[&str], help: &str) -> String {
        let r = self.try_choice(name, default, allowed, help);
        self.or_exit(r)
    }

    /// [`Cli::try_string`], exiting with status 2 on bad input.
    pub fn string(&mut self, name: &str, default: &str, help: &str) -> String {
        let r = self.try_string(name, default, help);
        self.or_exit(r)
    }

    /// [`Cli::try_finish`]: prints the help and exits with status 0 for `--help`, prints the
    /// error and exits with status 2 for bad input, returns otherwise.
    pub fn finish(self) {
        match self.try_finish() {
            Ok(Finish::Run) => {}
            Ok(Finish::Help(text)) => {
                print!("{text}");
                std::process::exit(0);
            }
            Err(e) => fail(e),
        }
    }
}

/// Prints `error: {msg}` on stderr and exits with status 2 (bad command line).
pub fn fail(msg: impl Display) -> ! {
    eprintln!("error: {msg}");
    std::process::exit(2)
}

fn parse_f64(name: &str, v: &str) -> Result<f64, String> {
    match v.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("--{name} expects a finite number, got \"{v}\"")),
    }
}

fn parse_usize(name: &str, v: &str) -> Result<usize, String> {
    v.trim()
        .parse::<usize>()
        .map_err(|_| format!("--{name} expects a whole number >= 0, got \"{v}\""))
}
