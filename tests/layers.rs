//! The one-way rule of `ARCHITECTURE.md`, checked on the source: a folder of
//! `src/` names (`crate::x`) only the folders of lower layers, never its own
//! layer's siblings nor anything above. Unit tests (after `#[cfg(test)]`) may
//! reach anywhere: a test of the plots may open the demo.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::fs;
use std::path::{Path, PathBuf};

/// The layers, bottom first. A module may use the modules of lower layers.
const LAYERS: [&[&str]; 8] = [
    &["error", "signal", "image"],
    &["body", "camera"],
    &["io"],
    &["translate", "synth"],
    &["track"],
    &["eval"],
    &["app"],
    &["web"],
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&module))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level modules named as `crate::NAME` in `text`, with the 1-based
/// line of each use, leaving out the items behind `#[cfg(test)]`: a line
/// such as `mod testing;`, or a block up to its closing brace.
fn crate_references(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    let mut skipping = false;
    let mut depth = 0i64;
    for (number, line) in text.lines().enumerate() {
        let code = line.split("//").next().unwrap_or("");
        if code.trim_start().starts_with("#[cfg(test)]") {
            skipping = true;
            depth = 0;
            continue;
        }
        if skipping {
            depth += code.matches('{').count() as i64 - code.matches('}').count() as i64;
            let item_ends = depth <= 0 && (code.contains(';') || code.contains('}'));
            if item_ends {
                skipping = false;
            }
            continue;
        }
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            let after = &rest[at + "crate::".len()..];
            let name: String = after.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
            found.push((number + 1, name));
            rest = after;
        }
    }
    found
}

#[test]
fn no_import_runs_sideways_or_up() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut checked = 0;
    let mut wrong = Vec::new();
    for file in &files {
        let relative = file.strip_prefix(&src).unwrap();
        let module = relative.components().next().unwrap().as_os_str().to_string_lossy();
        let module = module.trim_end_matches(".rs");
        // lib.rs declares the modules; bin/ is the CLI, a crate of its own
        // that uses the library from outside.
        let Some(own_layer) = layer_of(module) else { continue };
        let text = fs::read_to_string(file).unwrap();
        for (line, used) in crate_references(&text) {
            checked += 1;
            let Some(used_layer) = layer_of(&used) else {
                wrong.push(format!("src/{}:{line}: crate::{used} is in no layer", relative.display()));
                continue;
            };
            // `error` is the one error type: a leaf that its layer-0
            // siblings (`image`) use too.
            if used != module && used != "error" && used_layer >= own_layer {
                wrong.push(format!(
                    "src/{}:{line}: {module} (layer {own_layer}) uses crate::{used} (layer {used_layer})",
                    relative.display()
                ));
            }
        }
    }
    assert!(checked > 50, "only {checked} crate:: references found: is the scan broken?");
    assert!(wrong.is_empty(), "imports against the one-way rule:\n{}", wrong.join("\n"));
}

/// The command line's own crates (its arguments, its progress bars) stay
/// in `src/bin`: the library is the same for the CLI and the browser.
#[test]
fn the_command_line_s_crates_stay_in_the_cli() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut wrong = Vec::new();
    let mut checked = 0;
    for file in files.iter().filter(|f| !f.strip_prefix(&src).unwrap().starts_with("bin")) {
        checked += 1;
        let text = fs::read_to_string(file).unwrap();
        for (k, line) in text.lines().enumerate() {
            if ["clap::", "indicatif::"].iter().any(|c| line.contains(c)) {
                wrong.push(format!(
                    "src/{}:{}: {}",
                    file.strip_prefix(&src).unwrap().display(),
                    k + 1,
                    line.trim()
                ));
            }
        }
    }
    assert!(checked > 50, "only {checked} library files found: is the scan broken?");
    assert!(wrong.is_empty(), "the CLI's crates in the library:\n{}", wrong.join("\n"));
}

#[test]
fn every_folder_says_what_it_is_for_and_may_import() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    for layer in LAYERS {
        for module in layer {
            let folder = src.join(module).join("mod.rs");
            let file = if folder.exists() { folder } else { src.join(format!("{module}.rs")) };
            let text = fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            let doc: String = text.lines().take_while(|l| l.starts_with("//!")).collect::<Vec<_>>().join(" ");
            assert!(doc.len() > 80, "{} opens with no paragraph on what it is for", file.display());
            if file.ends_with("mod.rs") {
                assert!(
                    doc.contains("import"),
                    "{}: its opening paragraph says nothing of what it may import",
                    file.display()
                );
            }
        }
    }
}

#[test]
fn the_scan_sees_an_upward_import() {
    let text = "use crate::body::feet::Foot;\nlet x = crate::web::thing(); // crate::app in a comment\n\
                #[cfg(test)]\nmod testing;\nuse crate::io::x;\n#[cfg(test)]\nmod tests {\n    use crate::app;\n    fn f() {\n    }\n}\nuse crate::eval::y;";
    let lines: Vec<(usize, String)> =
        [(1, "body"), (2, "web"), (5, "io"), (12, "eval")].iter().map(|(l, m)| (*l, m.to_string())).collect();
    assert_eq!(crate_references(text), lines);
}
