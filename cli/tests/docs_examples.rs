//! The outputs quoted in the docs come from the code: every ```text block of docs/*.md that
//! starts with `$ telescopic ARGS` is run (files it would write go to a scratch directory)
//! and each line quoted under it must be a line the command printed, in order. A line ending
//! in `...` quotes the start of one; the wall time of a summary is not compared.

mod common;

use std::path::{Path, PathBuf};

/// One quoted example: where it is, the arguments, the lines quoted.
struct Example {
    place: String,
    args: Vec<String>,
    lines: Vec<String>,
}

/// Every example of every page of docs/.
fn examples(root: &Path) -> Vec<Example> {
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    pages.sort();
    let mut out = Vec::new();
    for page in pages {
        let text = std::fs::read_to_string(&page).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        for (i, line) in lines.iter().enumerate() {
            let Some(command) = line.strip_prefix("$ telescopic ") else {
                continue;
            };
            if i == 0 || lines[i - 1] != "```text" {
                continue;
            }
            let quoted = lines[i + 1..]
                .iter()
                .take_while(|l| **l != "```")
                .map(|l| l.to_string())
                .collect();
            out.push(Example {
                place: format!("{}:{}", page.display(), i + 1),
                args: command.split_whitespace().map(String::from).collect(),
                lines: quoted,
            });
        }
    }
    out
}

/// `line` with the number after `wall time ` left out.
fn without_wall_time(line: &str) -> String {
    match line.find("wall time ") {
        Some(at) => line[..at + "wall time ".len()].to_string(),
        None => line.to_string(),
    }
}

#[test]
fn every_quoted_output_is_what_the_command_prints() {
    let root = Path::new(common::ROOT);
    let dir = common::scratch("docs-examples");
    let examples = examples(root);
    assert!(
        examples.len() >= 5,
        "the docs quote {} examples",
        examples.len()
    );
    for example in examples {
        // an output file goes to the scratch directory
        let mut args = example.args.clone();
        for i in 1..args.len() {
            if ["--out", "--plot", "--csv", "--animate"].contains(&args[i - 1].as_str()) {
                args[i] = dir.join(&args[i]).to_string_lossy().into_owned();
            }
        }
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_telescopic"))
            .args(&args)
            .current_dir(root)
            .output()
            .unwrap();
        let printed: Vec<String> = String::from_utf8_lossy(&out.stdout)
            .lines()
            .chain(String::from_utf8_lossy(&out.stderr).lines())
            .map(without_wall_time)
            .collect();
        let mut from = 0;
        for quoted in &example.lines {
            let quoted = without_wall_time(quoted.trim_end());
            let found = match quoted.strip_suffix("...") {
                Some(start) => printed[from..]
                    .iter()
                    .position(|p| p.starts_with(start.trim_end())),
                None => printed[from..]
                    .iter()
                    .position(|p| p.trim_end() == quoted.trim_end()),
            };
            let Some(at) = found else {
                panic!(
                    "{}: `telescopic {}` did not print\n{quoted}\nafter line {from}; it printed:\n{}",
                    example.place,
                    example.args.join(" "),
                    printed.join("\n")
                );
            };
            from += at + 1;
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
