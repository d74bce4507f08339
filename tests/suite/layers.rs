//! The house has no back doors: no module of `src/` names, in code, a module of a higher layer
//! (issue 17, item 3). Doc comments, comments and string literals are not code and may link
//! anywhere.
//!
//! The test reads every `.rs` file under `src/`, strips comments and literals, and collects the
//! top-level module named by each `crate::` path (`use crate::x::...`, `crate::x::f()`, the
//! items of `use crate::{x::..., y::...}`), each `$crate::` path, and each `super::` chain that
//! climbs to the crate root. A file belongs to the top-level module of its first path
//! component (`src/stability/orbit.rs` to `stability`); `src/lib.rs` and the prelude are the
//! roof and may name everything.

use std::fs;
use std::path::{Path, PathBuf};

/// One floor of the house.
struct Layer {
    /// The top-level modules on this floor.
    modules: &'static [&'static str],
    /// Whether the modules of this floor are independent of each other (no imports between
    /// them); otherwise a module may use its neighbours.
    apart: bool,
}

/// The house, bottom to top: a module may use the modules of every lower floor and, unless its
/// floor is `apart`, those of its own.
const LAYERS: &[Layer] = &[
    // Leaves every floor uses: the parameters and the private serde helpers.
    Layer {
        modules: &["params", "serde_util"],
        apart: false,
    },
    // The shared numerics (root finder, bisection, ...) that the integrators and the ring use.
    Layer {
        modules: &["numeric"],
        apart: false,
    },
    // The integrators and the snubber ring's contact element: neither depends on the other.
    Layer {
        modules: &["ode", "ring"],
        apart: true,
    },
    // Piecewise-smooth models, their driver and linearisation; the generic ringed rotor.
    Layer {
        modules: &["hybrid", "rotor"],
        apart: false,
    },
    // The analyses, for any model.
    Layer {
        modules: &["analysis", "stability", "global"],
        apart: false,
    },
    // The paper's model, its sweeps and planes.
    Layer {
        modules: &["paper"],
        apart: false,
    },
];

/// The roof: the crate root (`src/lib.rs`) and the prelude (issue 17 item 6) re-export from
/// every floor and may name everything.
const ROOF: &[&str] = &["lib.rs", "prelude"];

/// The analyses name no concrete model in code: these floors may not use these modules even
/// though they are below them (`rotor` holds `RingedRotor`).
const NO_CONCRETE_MODEL: &[&str] = &["analysis", "stability", "global"];
const CONCRETE_MODELS: &[&str] = &["rotor", "paper"];

/// Known violations that other work of issue 17 removes: (file, module named, why). Each entry
/// must still be needed (the test fails on a stale one).
const ALLOWED: &[(&str, &str, &str)] = &[];

fn floor(module: &str) -> Option<(usize, bool)> {
    LAYERS
        .iter()
        .enumerate()
        .find(|(_, l)| l.modules.contains(&module))
        .map(|(i, l)| (i, l.apart))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).expect("read src/") {
        let path = entry.expect("dir entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The code of a Rust file with comments (doc comments included), string literals and char
/// literals replaced by spaces (newlines kept, so that line numbers stay right).
fn strip(src: &str) -> String {
    let b: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(blank(b[i]));
                    i += 1;
                }
            }
        } else if c == 'r' && (next == Some('"') || next == Some('#')) && !ident_before(&b, i) {
            // A raw string: r"...", r#"..."#.
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|h| b.get(j + 1 + h) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            out.extend(b[i..j.min(b.len())].iter().map(|&c| blank(c)));
            i = j;
        } else if c == '"' {
            let mut j = i + 1;
            while j < b.len() && b[j] != '"' {
                j += if b[j] == '\\' { 2 } else { 1 };
            }
            let j = (j + 1).min(b.len());
            out.extend(b[i..j].iter().map(|&c| blank(c)));
            i = j;
        } else if c == '\'' {
            // A char literal ('x', '\n', '\u{..}') or a lifetime ('a).
            let end = if next == Some('\\') {
                (i + 2..b.len()).find(|&j| b[j] == '\'')
            } else if b.get(i + 2) == Some(&'\'') {
                Some(i + 2)
            } else {
                None
            };
            match end {
                Some(j) => {
                    out.extend(b[i..=j].iter().map(|&c| blank(c)));
                    i = j + 1;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn ident_before(b: &[char], i: usize) -> bool {
    i > 0 && (b[i - 1].is_alphanumeric() || b[i - 1] == '_')
}

fn ident_at(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The top-level modules named from the crate root at byte `at` of `code` (just after
/// `crate::`): one, or the first segment of each item of a `{...}` group.
fn named_from_root(code: &str, at: usize) -> Vec<(usize, String)> {
    let rest = code[at..].trim_start();
    let start = code.len() - rest.len();
    if !rest.starts_with('{') {
        return vec![(start, ident_at(rest).to_string())];
    }
    let mut names = Vec::new();
    let mut depth = 0;
    let mut expect_item = false;
    for (k, ch) in rest.char_indices() {
        match ch {
            '{' => {
                depth += 1;
                expect_item = depth == 1;
            }
            '}' => {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            ',' if depth == 1 => expect_item = true,
            c if expect_item && (c.is_alphanumeric() || c == '_') => {
                names.push((start + k, ident_at(&rest[k..]).to_string()));
                expect_item = false;
            }
            _ => {}
        }
    }
    names
}

/// (line, module) for every top-level module a file's code names.
fn named_modules(code: &str, file_depth: usize) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    let bytes = code.as_bytes();
    let boundary =
        |k: usize| k == 0 || !(bytes[k - 1].is_ascii_alphanumeric() || bytes[k - 1] == b'_');
    for (k, _) in code.match_indices("crate::") {
        let dollar = k > 0 && bytes[k - 1] == b'$';
        if dollar || boundary(k) {
            found.extend(named_from_root(code, k + "crate::".len()));
        }
    }
    for (k, _) in code.match_indices("super::") {
        if !boundary(k) || (k >= 2 && &code[k - 2..k] == "::") {
            continue;
        }
        let mut at = k;
        let mut supers = 0;
        while code[at..].starts_with("super::") {
            supers += 1;
            at += "super::".len();
        }
        if supers >= file_depth {
            found.extend(named_from_root(code, at));
        }
    }
    found
        .into_iter()
        .map(|(at, m)| (code[..at].matches('\n').count() + 1, m))
        .collect()
}

#[test]
fn no_import_runs_up_the_house() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = root.join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut violations = Vec::new();
    let mut used_allowances = vec![false; ALLOWED.len()];
    for file in &files {
        let rel = file.strip_prefix(&src).expect("under src/");
        let parts: Vec<&str> = rel
            .iter()
            .map(|p| p.to_str().expect("utf-8 path"))
            .collect();
        let from = parts[0].trim_end_matches(".rs");
        if ROOF.contains(&parts[0]) || ROOF.contains(&from) {
            continue;
        }
        let Some((from_floor, apart)) = floor(from) else {
            violations.push(format!(
                "src/{}: module `{from}` is in no floor of the layer table (tests/suite/layers.rs)",
                rel.display()
            ));
            continue;
        };
        // Modules below the root: `a.rs` and `a/mod.rs` are 1 deep, `a/b.rs` 2, ...
        let depth = parts.len() - usize::from(parts.last() == Some(&"mod.rs"));
        let code = strip(&fs::read_to_string(file).expect("read a source file"));
        let shown = format!("src/{}", rel.display()).replace('\\', "/");
        for (line, to) in named_modules(&code, depth) {
            if to == from || to == "self" {
                continue;
            }
            let Some((to_floor, _)) = floor(&to) else {
                continue; // an item of the root (lib.rs), not a module
            };
            let up = to_floor > from_floor || (to_floor == from_floor && apart);
            let concrete =
                NO_CONCRETE_MODEL.contains(&from) && CONCRETE_MODELS.contains(&to.as_str());
            if !(up || concrete) {
                continue;
            }
            if let Some(a) = ALLOWED.iter().position(|&(f, m, _)| f == shown && m == to) {
                used_allowances[a] = true;
                continue;
            }
            let why = if up {
                "a higher or independent layer"
            } else {
                "a concrete model (the analyses name none)"
            };
            violations.push(format!(
                "{shown}:{line}: `{from}` names `crate::{to}`, {why}"
            ));
        }
    }
    for (a, used) in used_allowances.iter().enumerate() {
        if !used {
            violations.push(format!(
                "stale allowance in tests/suite/layers.rs: {} -> {} ({})",
                ALLOWED[a].0, ALLOWED[a].1, ALLOWED[a].2
            ));
        }
    }
    assert!(
        violations.is_empty(),
        "imports that run up the house (layer table in tests/suite/layers.rs):\n{}",
        violations.join("\n")
    );
}

/// The scanner itself: comments and literals are not code; groups, `$crate` and `super` chains
/// are.
#[test]
fn the_scanner_sees_paths_in_code_only() {
    let code = strip(
        "//! [`crate::paper`]\n/// crate::global\nuse crate::{hybrid::X, ring::{a, b}};\n\
         let s = \"crate::analysis\"; let c = '\"'; /* crate::stability */\n\
         fn f<'a>(x: &'a str) { crate::ode::f(); $crate::rotor::g(); super::super::params::P; }\n\
         let r = r#\"crate::numeric\"#;",
    );
    let names: Vec<(usize, String)> = named_modules(&code, 2);
    let expect = [
        (3, "hybrid"),
        (3, "ring"),
        (5, "ode"),
        (5, "rotor"),
        (5, "params"),
    ];
    let expect: Vec<(usize, String)> = expect.iter().map(|&(l, m)| (l, m.to_string())).collect();
    assert_eq!(names, expect);
    // One `super::` from a file two deep stays inside its module.
    assert!(named_modules(&strip("use super::orbit;"), 2).is_empty());
}
