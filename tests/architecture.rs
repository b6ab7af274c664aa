//! The rooms of the source stay apart: within each crate, no file imports (by `use` or a
//! path) a file that imports it back. The crate root, a facade of re-exports, is left out.
//! Paths are read from the source text (`crate::`, `super::`, `self::` and a module's own
//! children), comments and inline test modules left out; a file is a module (`a/b.rs` or
//! `a/b/mod.rs`). And no hand-written function, tests included, is over 100 lines.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The most lines a hand-written function may take, its signature and braces included.
const MAX_FUNCTION_LINES: usize = 100;

const CRATES: [&str; 6] = [
    "src",
    "runtime/src",
    "cli/src",
    "codegen/src",
    "fmu/src",
    "python/src",
];

/// Module path (`["run", "held"]`) of every `.rs` file under `root`.
fn modules(root: &Path) -> BTreeMap<Vec<String>, PathBuf> {
    let mut out = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let relative = path.strip_prefix(root).unwrap().with_extension("");
            let mut parts: Vec<String> = relative
                .iter()
                .map(|p| p.to_string_lossy().into_owned())
                .collect();
            if matches!(
                parts.last().map(String::as_str),
                Some("mod" | "lib" | "main")
            ) {
                parts.pop();
            }
            out.insert(parts, path);
        }
    }
    out
}

/// The text that imports: comments and a trailing `#[cfg(test)] mod` left out.
fn code_of(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod ") {
        Some(at) => &text[..at],
        None => text,
    };
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every path of a use tree (`a::{b, c::{d, e}}` -> `a::b`, `a::c::d`, `a::c::e`).
fn expand(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        return vec![tree.split(" as ").next().unwrap().trim().to_string()];
    };
    let prefix = &tree[..open];
    let inner = &tree[open + 1..tree.rfind('}').unwrap()];
    let (mut depth, mut start, mut parts) = (0, 0, Vec::new());
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .filter(|p| !p.trim().is_empty())
        .flat_map(expand)
        .map(|p| format!("{prefix}{p}"))
        .collect()
}

/// The paths `file` (module `at`) names, as absolute module paths.
fn imported(code: &str, at: &[String], children: &BTreeSet<String>) -> Vec<Vec<String>> {
    let mut paths: Vec<String> = Vec::new();
    let mut offset = 0;
    for line in code.split_inclusive('\n') {
        let trimmed = line.trim_start();
        let statement = ["use ", "pub use ", "pub(crate) use ", "pub(super) use "]
            .iter()
            .find(|start| trimmed.starts_with(*start));
        if let Some(start) = statement {
            let from = offset + (line.len() - trimmed.len()) + start.len();
            let to = from + code[from..].find(';').unwrap();
            paths.extend(expand(&code[from..to]));
        }
        offset += line.len();
    }
    for prefix in ["crate::", "super::", "self::"] {
        for (i, _) in code.match_indices(prefix) {
            let rest: String = code[i..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            // `crate::x::{..}` is a use tree, read above
            if !rest.ends_with("::") {
                paths.push(rest);
            }
        }
    }
    paths
        .into_iter()
        .filter_map(|p| {
            let segments: Vec<&str> = p.split("::").filter(|s| !s.is_empty()).collect();
            let (first, rest) = segments.split_first()?;
            let mut out: Vec<String> = match *first {
                "crate" => Vec::new(),
                "super" => at[..at.len().saturating_sub(1)].to_vec(),
                "self" => at.to_vec(),
                child if children.contains(child) => {
                    let mut out = at.to_vec();
                    out.push(child.to_string());
                    return Some(
                        out.into_iter()
                            .chain(rest.iter().map(|s| s.to_string()))
                            .collect(),
                    );
                }
                _ => return None,
            };
            out.extend(rest.iter().map(|s| s.to_string()));
            Some(out)
        })
        .collect()
}

/// The module files each module imports (the longest known prefix of each path).
fn edges(root: &Path) -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
    let modules = modules(root);
    let mut out = BTreeMap::new();
    for (at, file) in &modules {
        let children: BTreeSet<String> = modules
            .keys()
            .filter(|m| m.len() == at.len() + 1 && m.starts_with(at))
            .map(|m| m.last().unwrap().clone())
            .collect();
        let code = code_of(&std::fs::read_to_string(file).unwrap());
        let mut targets = BTreeSet::new();
        for path in imported(&code, at, &children) {
            let target = (0..=path.len())
                .rev()
                .map(|n| path[..n].to_vec())
                .find(|p| modules.contains_key(p))
                .unwrap();
            if &target != at {
                targets.insert(target);
            }
        }
        out.insert(at.clone(), targets);
    }
    out
}

#[test]
fn no_file_imports_a_file_that_imports_it() {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut cycles = Vec::new();
    for krate in CRATES {
        let edges = edges(&workspace.join(krate));
        for (a, targets) in &edges {
            for b in targets {
                if !a.is_empty() && !b.is_empty() && a < b && edges[b].contains(a) {
                    cycles.push(format!("{krate}: {} <-> {}", a.join("::"), b.join("::")));
                }
            }
        }
    }
    assert!(
        cycles.is_empty(),
        "files importing each other:\n{}",
        cycles.join("\n")
    );
}

#[test]
fn the_reader_finds_the_imports_it_must() {
    let children: BTreeSet<String> = ["child".to_string()].into();
    let at = vec!["a".to_string(), "b".to_string()];
    let code = code_of(
        "// use crate::commented::Out;\nuse crate::x::{y::Z, w};\npub use child::Thing;\nfn f() { super::sibling::g() }\n#[cfg(test)]\nmod tests { use crate::only_in_tests; }",
    );
    let found: BTreeSet<String> = imported(&code, &at, &children)
        .into_iter()
        .map(|p| p.join("::"))
        .collect();
    let expected: BTreeSet<String> = ["x::y::Z", "x::w", "a::b::child::Thing", "a::sibling::g"]
        .into_iter()
        .map(String::from)
        .collect();
    assert_eq!(found, expected);
}

/// Every `.rs` file under `root`, recursively, build directories (`target`) left out.
fn rust_files(root: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![root.to_path_buf()];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).expect("a source directory") {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                if path.file_name().is_some_and(|n| n != "target") {
                    pending.push(path);
                }
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The functions of one file longer than [`MAX_FUNCTION_LINES`]: name, first line, lines.
#[derive(Default)]
struct LongFunctions(Vec<(String, usize, usize)>);

impl LongFunctions {
    /// Counts from the signature to the closing brace (doc comments and attributes left out).
    fn check(&mut self, sig: &syn::Signature, block: &syn::Block) {
        let (start, end) = (
            sig.fn_token.span.start().line,
            block.brace_token.span.close().end().line,
        );
        let lines = end - start + 1;
        if lines > MAX_FUNCTION_LINES {
            self.0.push((sig.ident.to_string(), start, lines));
        }
    }
}

impl<'ast> syn::visit::Visit<'ast> for LongFunctions {
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        self.check(&f.sig, &f.block);
        syn::visit::visit_item_fn(self, f);
    }
    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        self.check(&f.sig, &f.block);
        syn::visit::visit_impl_item_fn(self, f);
    }
    fn visit_trait_item_fn(&mut self, f: &'ast syn::TraitItemFn) {
        if let Some(block) = &f.default {
            self.check(&f.sig, block);
        }
        syn::visit::visit_trait_item_fn(self, f);
    }
}

/// The functions over [`MAX_FUNCTION_LINES`] in `text` (a whole source file).
fn long_functions(text: &str) -> Vec<(String, usize, usize)> {
    let file = syn::parse_file(text).expect("the source parses");
    let mut long = LongFunctions::default();
    syn::visit::Visit::visit_file(&mut long, &file);
    long.0
}

#[test]
fn no_hand_written_function_is_over_100_lines() {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR"));
    // every crate with its tests, benchmarks and build scripts, and the examples; the
    // committed generated models are the generator's output, not hand-written
    let roots = [
        "src", "tests", "runtime", "cli", "codegen", "fmu", "python", "examples",
    ];
    let mut found = Vec::new();
    for root in roots {
        for file in rust_files(&workspace.join(root)) {
            let text = std::fs::read_to_string(&file).expect("a readable source file");
            for (name, line, lines) in long_functions(&text) {
                let at = file.strip_prefix(workspace).unwrap_or(&file).display();
                found.push(format!("{at}:{line} {name}: {lines} lines"));
            }
        }
    }
    assert!(
        found.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_function_reader_counts_every_kind_of_function() {
    let body = "    let x = 1;\n".repeat(MAX_FUNCTION_LINES - 1);
    let text = format!(
        "fn free() {{\n{body}}}\nstruct S;\nimpl S {{\n    fn method() {{\n{body}    }}\n}}\n\
         trait T {{\n    fn provided() {{\n{body}    }}\n}}\nfn short() {{}}\n"
    );
    let names: Vec<String> = long_functions(&text)
        .into_iter()
        .map(|(n, _, _)| n)
        .collect();
    assert_eq!(names, ["free", "method", "provided"]);
    let exact = format!(
        "/// A doc comment is not counted.\n#[inline]\nfn edge() {{\n{}}}\n",
        "    let x = 1;\n".repeat(MAX_FUNCTION_LINES - 2)
    );
    assert!(
        long_functions(&exact).is_empty(),
        "exactly {MAX_FUNCTION_LINES} lines is allowed"
    );
}
