//! docs/architecture.md's "Imports" table is what the code does: every
//! `crate::m` path in the code (not the comments) of a top-level module of
//! the library's `src/` names a module the
//! table allows it, and every module the table allows is one it uses (so the
//! table can neither fall behind the code nor keep couplings that are gone).

use crate::common::root;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The table's rows: module → the modules it may import.
fn allowed() -> BTreeMap<String, BTreeSet<String>> {
    let doc = std::fs::read_to_string(root().join("docs/architecture.md")).unwrap();
    let section = doc
        .split("\n## Imports\n")
        .nth(1)
        .expect("docs/architecture.md has an \"## Imports\" section");
    let section = section.split("\n## ").next().unwrap();
    let mut rows = BTreeMap::new();
    for line in section.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let name = cells[1].trim_matches('`').to_string();
        let deps: BTreeSet<String> = cells[2]
            .split(',')
            .map(|d| d.trim().trim_matches('`').to_string())
            .filter(|d| !d.is_empty() && d != "–")
            .collect();
        rows.insert(name, deps);
    }
    rows
}

/// Every `.rs` file under `path` (or `path` itself).
fn rust_files(path: &Path, out: &mut Vec<std::path::PathBuf>) {
    if path.is_dir() {
        for e in std::fs::read_dir(path).unwrap() {
            rust_files(&e.unwrap().path(), out);
        }
    } else if path.extension().is_some_and(|e| e == "rs") {
        out.push(path.to_path_buf());
    }
}

/// The top-level modules each module's files name as `crate::m`, with a
/// file:line for each.
fn used() -> BTreeMap<String, BTreeMap<String, String>> {
    let src = root().join("src");
    let mut uses = BTreeMap::new();
    for e in std::fs::read_dir(&src).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_stem().unwrap().to_string_lossy().to_string();
        // cli is the binary's (its `crate::` is the binary crate).
        let not_rust = p.is_file() && p.extension().is_none_or(|e| e != "rs");
        if ["lib", "main", "cli"].contains(&name.as_str()) || not_rust {
            continue;
        }
        let mut files = Vec::new();
        rust_files(&p, &mut files);
        let deps: &mut BTreeMap<String, String> = uses.entry(name.clone()).or_default();
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            // Code only: a doc link is not an import.
            let code = text
                .lines()
                .enumerate()
                .filter(|(_, l)| !l.trim_start().starts_with("//"));
            for (n, line) in code {
                for (i, _) in line.match_indices("crate::") {
                    let m: String = line[i + 7..]
                        .chars()
                        .take_while(|c| c.is_ascii_lowercase() || *c == '_' || c.is_ascii_digit())
                        .collect();
                    if !m.is_empty() && m != name {
                        let at = format!("{}:{}", f.strip_prefix(root()).unwrap().display(), n + 1);
                        deps.entry(m).or_insert(at);
                    }
                }
            }
        }
    }
    uses
}

#[test]
fn every_module_imports_only_what_the_architecture_allows() {
    let allowed = allowed();
    let used = used();
    let mut wrong = Vec::new();
    for (m, deps) in &used {
        let Some(ok) = allowed.get(m) else {
            wrong.push(format!("module `{m}` has no row in the Imports table"));
            continue;
        };
        for (d, at) in deps {
            if !ok.contains(d) {
                wrong.push(format!(
                    "`{m}` imports `{d}` ({at}), which the table does not allow"
                ));
            }
        }
        for d in ok.difference(&deps.keys().cloned().collect()) {
            wrong.push(format!(
                "`{m}` may import `{d}` but does not: drop it from the table"
            ));
        }
    }
    for m in allowed.keys().filter(|m| !used.contains_key(*m)) {
        wrong.push(format!(
            "the table lists `{m}`, which is not a module of src/"
        ));
    }
    assert!(
        wrong.is_empty(),
        "docs/architecture.md, Imports:\n{}",
        wrong.join("\n")
    );
    // The scan sees the code: the pipeline reaches the field and the job.
    assert!(used["pipeline"].contains_key("field") && used["pipeline"].contains_key("job"));
}
