//! The text rendering of a small configuration is kept as a snapshot, so every change to the
//! emitted equations shows up as a reviewable diff; the LaTeX document is checked
//! structurally, and compiled when `pdflatex` is installed.

use telescopic_codegen::{DriveKind, ForceFlow, ModelConfig, Positions, generate};

fn small() -> ModelConfig {
    ModelConfig {
        modes: vec![2, 2],
        contacts: 2,
        force_flow: ForceFlow::Cable,
        clearance: true,
        positions: Positions::Moving,
        drive: DriveKind::Force,
        static_knots: None,
    }
}

#[test]
fn text_rendering_matches_the_snapshot() {
    let model = generate(&small()).unwrap();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/snapshots")
        .join(format!("{}.txt", model.module));
    if std::env::var_os("UPDATE_EXPECT").is_some() {
        std::fs::write(&path, &model.text).unwrap();
    }
    let expected = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        model.text == expected,
        "the text rendering of {} changed; review the diff and rerun with UPDATE_EXPECT=1 to accept:\n--- expected\n{expected}\n--- got\n{}",
        model.module,
        model.text
    );
}

#[test]
fn latex_document_is_well_formed() {
    let tex = generate(&small()).unwrap().latex;
    assert!(tex.starts_with("\\documentclass"));
    assert!(tex.trim_end().ends_with("\\end{document}"));
    // braces balance outside verbatim blocks, and every environment closes
    let mut depth: i64 = 0;
    let mut in_verbatim = false;
    for line in tex.lines() {
        if line.starts_with("\\begin{verbatim}") {
            in_verbatim = true;
            continue;
        }
        if line.starts_with("\\end{verbatim}") {
            in_verbatim = false;
        }
        if in_verbatim {
            continue;
        }
        for ch in line.chars() {
            depth += match ch {
                '{' => 1,
                '}' => -1,
                _ => 0,
            };
            assert!(depth >= 0, "unbalanced braces at: {line}");
        }
    }
    assert_eq!(depth, 0, "unbalanced braces");
    for env in ["document", "align*", "verbatim"] {
        assert_eq!(
            tex.matches(&format!("\\begin{{{env}}}")).count(),
            tex.matches(&format!("\\end{{{env}}}")).count(),
            "{env}"
        );
    }
    // compile it when a TeX engine is there (CI installs one where apt-get works)
    if std::process::Command::new("pdflatex")
        .arg("--version")
        .output()
        .is_ok()
    {
        let dir = std::env::temp_dir().join(format!("telescopic-tex-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("model.tex"), &tex).unwrap();
        let out = std::process::Command::new("pdflatex")
            .args(["-interaction=nonstopmode", "-halt-on-error", "model.tex"])
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "pdflatex failed:\n{}",
            String::from_utf8_lossy(&out.stdout)
        );
        assert!(dir.join("model.pdf").exists());
        let _ = std::fs::remove_dir_all(&dir);
    } else {
        eprintln!("pdflatex not installed: LaTeX checked structurally only");
    }
}
