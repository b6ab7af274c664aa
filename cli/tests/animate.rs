//! `telescopic animate` and `modes --animate`, end to end. The page is checked in a real
//! headless Chromium (Debian's `chromium`; `TELESCOPIC_CHROMIUM` names another binary): it
//! loads from a `file://` path with the network off, logs nothing to the console, and the
//! pixels it draws for the load, the section tops and the vehicle are the run's CSV values
//! through the page's own layout numbers, to half a pixel. Those tests need the browser and
//! are ignored by a plain `cargo test`; `./scripts/test` installs it and runs them. A missing
//! browser fails the test, naming it. The GIF is decoded here: its frames, size and the
//! load's pixel against `tip_rel`.

mod common;

use common::{Csv, fails_with, scratch, succeeds};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The case study's telescopic position `a_2(t)` (m), from the scene's definition: a
/// quintic smoothstep from 0.35 m to 1.15 m over 12 s.
fn case_study_a2(t: f64) -> f64 {
    let u = (t / 12.0).clamp(0.0, 1.0);
    0.35 + 0.8 * (10.0 * u.powi(3) - 15.0 * u.powi(4) + 6.0 * u.powi(5))
}

#[test]
fn the_gif_has_the_frames_and_size_asked_and_its_load_follows_tip_rel() {
    let dir = scratch("animate-gif");
    let gif_path = dir.join("run.gif");
    let csv = dir.join("run.csv");
    let scene = ["scenes/case-study.toml", "--set", "time.end=4"];
    let args = [
        &scene[..],
        &[
            "--out",
            gif_path.to_str().unwrap(),
            "--fps",
            "10",
            "--size",
            "400x300",
        ],
        &["--scale", "2"],
    ]
    .concat();
    let out = succeeds(&[&["animate"][..], &args].concat());
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("41 frames at 10 per second"), "{said}");
    succeeds(
        &[
            &["simulate"][..],
            &scene,
            &["--no-error-estimate", "--out", csv.to_str().unwrap()],
        ]
        .concat(),
    );
    let run = Csv::read(&csv);
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options
        .read_info(std::fs::File::open(&gif_path).unwrap())
        .unwrap();
    assert_eq!((decoder.width(), decoder.height()), (400, 300));
    // the layout of one track (telescopic::animate::gif::GifLayout): the vehicle's centre at
    // half the width, the rail at 0.75 h - 34, 30 px headroom, 1.06 x the tallest telescope
    // of the frames
    let tallest = (0..=40)
        .map(|i| case_study_a2(0.1 * f64::from(i)) + 1.35)
        .fold(0.0, f64::max)
        .max(1.35);
    let ground = (0.75 * 300.0_f64).round() - 34.0;
    let ppm = (ground - 30.0) / (1.06 * tallest);
    let mut frames = 0;
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        let t = 0.1 * f64::from(frames);
        assert_eq!((frame.width, frame.height), (400, 300));
        assert_eq!(
            frame.delay, 10,
            "10 frames per second at speed 1: 10 cs each"
        );
        // the load is the only magenta: the centroid of its square
        let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
        for (i, px) in frame.buffer.chunks_exact(4).enumerate() {
            if px[..3] == [204, 0, 204] {
                sx += (i % 400) as f64;
                sy += (i / 400) as f64;
                n += 1.0;
            }
        }
        assert!(n > 50.0, "frame {frames}: the load's square is missing");
        let expected_x = 200.0 + ppm * 2.0 * run.at("tip_rel", t);
        let expected_top = ground - ppm * (case_study_a2(t) + 1.35);
        assert!(
            (sx / n - expected_x).abs() <= 1.0,
            "frame {frames} (t = {t}): load at x = {}, tip_rel says {expected_x}",
            sx / n
        );
        // the square spans the 12 pixels above the top
        assert!(
            (sy / n - (expected_top - 6.0)).abs() <= 1.0,
            "frame {frames}: y {}",
            sy / n
        );
        frames += 1;
    }
    assert_eq!(frames, 41);
}

#[test]
fn a_long_run_makes_a_small_page_and_bad_options_are_refused() {
    let dir = scratch("animate-page");
    let page = dir.join("case-study.html");
    let out = succeeds(&[
        "animate",
        "scenes/case-study.toml",
        "--out",
        page.to_str().unwrap(),
    ]);
    let size = std::fs::metadata(&page).unwrap().len();
    assert!(size < 2_000_000, "a 16 s case-study page is {size} bytes");
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("801 frames at 50 per second"), "{said}");
    let html = std::fs::read_to_string(&page).unwrap();
    for external in [
        "http://", "https://", "src=\"", "href=\"", "@import", "url(",
    ] {
        assert!(
            !html.contains(external),
            "the page refers to something outside: {external}"
        );
    }
    let scene = "scenes/adams-linear.toml";
    let refused: [(&str, &[&str], &[&str]); 8] = [
        ("a.mp4", &[], &["--out", ".html, .htm or .gif"]),
        ("b.html", &["--fps", "0"], &["--fps", "above 0"]),
        ("c.html", &["--fps", "2000"], &["--fps", "1000"]),
        ("d.html", &["--scale", "-3"], &["--scale", "above 0"]),
        (
            "e.gif",
            &["--size", "10x10"],
            &["--size", "width 160 to 4096"],
        ),
        ("f.gif", &["--size", "big"], &["WIDTHxHEIGHT"]),
        (
            "g.html",
            &["--set", "time.sample=0.1", "--fps", "50"],
            &["--fps", "time.sample"],
        ),
        (
            "h.html",
            &["--size", "400x300"],
            &["--size and --speed are a GIF's"],
        ),
    ];
    for (name, flags, needles) in refused {
        let path = dir.join(name);
        let args = [
            &["animate", scene, "--out", path.to_str().unwrap()][..],
            flags,
        ]
        .concat();
        fails_with(&args, needles);
        assert!(!path.exists(), "{name} was written");
    }
    let modes_gif = dir.join("m.gif");
    fails_with(
        &["modes", scene, "--animate", modes_gif.to_str().unwrap()],
        &["--animate", ".html"],
    );
    assert!(!modes_gif.exists());
    let no_modes = dir.join("none.html");
    fails_with(
        &[
            "modes",
            scene,
            "--count",
            "0",
            "--animate",
            no_modes.to_str().unwrap(),
        ],
        &["--count", "at least one mode"],
    );
    assert!(!no_modes.exists());
}

/// Chromium, from `TELESCOPIC_CHROMIUM` or on the PATH; a missing browser fails the test.
fn chromium() -> PathBuf {
    if let Some(path) = std::env::var_os("TELESCOPIC_CHROMIUM") {
        return PathBuf::from(path);
    }
    for name in ["chromium", "chromium-browser"] {
        if let Ok(out) = Command::new("which").arg(name).output()
            && out.status.success()
        {
            return PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
        }
    }
    panic!(
        "headless Chromium is missing: install Debian's chromium (./scripts/test does) or \
         name the binary in TELESCOPIC_CHROMIUM"
    );
}

/// Runs headless Chromium on `page#fragment` with the network off, `extra` arguments last;
/// returns stdout, and checks that the page logged nothing to the console.
fn browse(page: &Path, fragment: &str, extra: &[&str], profile: &Path) -> String {
    let url = format!(
        "file://{}#{fragment}",
        page.canonicalize().unwrap().display()
    );
    let out = Command::new(chromium())
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-quic",
            // the network off: every host name fails to resolve, every proxy is dead
            "--host-resolver-rules=MAP * ~NOTFOUND",
            "--proxy-server=127.0.0.1:9",
            "--enable-logging=stderr",
            "--v=0",
            "--hide-scrollbars",
            "--window-size=1000,760",
            "--virtual-time-budget=3000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(&url)
        .output()
        .expect("chromium runs");
    assert!(out.status.success(), "chromium failed on {url}");
    let log = String::from_utf8_lossy(&out.stderr);
    let console: Vec<&str> = log.lines().filter(|l| l.contains(":CONSOLE")).collect();
    assert!(
        console.is_empty(),
        "the page logged to the console: {console:#?}"
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The JSON the page's probe wrote for `times` (its `#probe=` fragment).
fn probe(page: &Path, times: &[f64], profile: &Path) -> Value {
    let list: Vec<String> = times.iter().map(f64::to_string).collect();
    let dom = browse(
        page,
        &format!("probe={}", list.join(",")),
        &["--dump-dom"],
        profile,
    );
    let start = dom
        .find("<pre id=\"probe\"")
        .expect("the probe element is in the DOM");
    let start = start + dom[start..].find('>').unwrap() + 1;
    let end = start + dom[start..].find("</pre>").unwrap();
    let text = dom[start..end]
        .replace("&amp;", "&")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"");
    let probe: Value = serde_json::from_str(&text).expect("the probe is JSON");
    assert_eq!(
        probe["errors"],
        Value::Array(vec![]),
        "the page caught errors"
    );
    probe
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

/// The page's layout: the vehicle's centre, the rail, pixels per metre and the scale.
fn stage(layout: &Value) -> (f64, f64, f64, f64) {
    let number = |key: &str| f(&layout[key]);
    (
        number("cx"),
        number("groundY"),
        number("ppm"),
        number("scale"),
    )
}

/// A screenshot of `page#at=T` as RGB pixels.
fn screenshot(page: &Path, t: f64, dir: &Path, profile: &Path) -> Vec<u8> {
    let shot = dir.join(format!("shot-{t}.png"));
    browse(
        page,
        &format!("at={t}"),
        &[&format!("--screenshot={}", shot.display())],
        profile,
    );
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&shot).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    buf
}

#[test]
#[ignore = "needs headless Chromium; ./scripts/test installs it"]
fn the_page_draws_the_runs_csv_values_in_a_real_browser() {
    let dir = scratch("animate-browser");
    let profile = dir.join("profile");
    let page = dir.join("case-study.html");
    let csv = dir.join("case-study.csv");
    succeeds(&[
        "animate",
        "scenes/case-study.toml",
        "--out",
        page.to_str().unwrap(),
        "--scale",
        "4",
    ]);
    succeeds(&[
        "simulate",
        "scenes/case-study.toml",
        "--no-error-estimate",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let run = Csv::read(&csv);
    let times = [0.0, 0.5, 2.02, 6.3, 9.14, 13.7, 16.0];
    let probe = probe(&page, &times, &profile);
    let layout = &probe["layout"];
    let (cx, ground, ppm, scale) = stage(layout);
    assert_eq!(scale, 4.0);
    let half_band = 0.005;
    let mut switched = false;
    for (result, &t) in probe["results"].as_array().unwrap().iter().zip(&times) {
        let drawn = &result["drawn"][0];
        assert!(
            (f(&drawn["time"]) - t).abs() < 1e-9,
            "seeked to {t}, drew {}",
            drawn["time"]
        );
        let near = |got: f64, want: f64, what: &str| {
            assert!(
                (got - want).abs() <= 0.5,
                "t = {t}: {what} drawn at {got}, the CSV says {want}"
            );
        };
        let load = &drawn["load"];
        near(
            f(&load["x"]),
            cx + ppm * scale * run.at("tip_rel", t),
            "the load's x",
        );
        near(
            f(&load["y"]),
            ground - ppm * (case_study_a2(t) + 1.35),
            "the load's y",
        );
        let top1 = &drawn["tops"][0];
        near(
            f(&top1["x"]),
            cx + ppm * scale * run.at("top1_rel", t),
            "section 1's top, x",
        );
        near(f(&top1["y"]), ground - ppm * 1.35, "section 1's top, y");
        near(
            f(&drawn["rail_zero_x"]),
            cx - ppm * run.at("vehicle", t),
            "the rail's zero",
        );
        let strip = &drawn["overview"];
        let (x0, x1, lo, hi) = (
            f(&strip["x0"]),
            f(&strip["x1"]),
            f(&strip["lo"]),
            f(&strip["hi"]),
        );
        near(
            f(&drawn["vehicle_overview_x"]),
            x0 + (x1 - x0) * (run.at("vehicle", t) - lo) / (hi - lo),
            "the vehicle",
        );
        for (c, contact) in drawn["contacts"].as_array().unwrap().iter().enumerate() {
            let gap = run.at(&format!("xi_2_{c}"), t);
            assert_eq!(
                contact["closed"].as_bool().unwrap(),
                gap.abs() > half_band,
                "t = {t}, contact {c}"
            );
            switched |= gap.abs() > half_band;
        }
    }
    assert!(switched, "no probed frame has a closed contact");
    frames_are_drawn_and_differ(&page, &dir, &profile);
}

/// Screenshots of `page` at 2 s and 9 s are pictures (not blank) and differ.
fn frames_are_drawn_and_differ(page: &Path, dir: &Path, profile: &Path) {
    let (a, b) = (
        screenshot(page, 2.0, dir, profile),
        screenshot(page, 9.0, dir, profile),
    );
    let colours: std::collections::HashSet<&[u8]> = a.chunks(3).collect();
    assert!(
        colours.len() > 20,
        "the screenshot is blank ({} colours)",
        colours.len()
    );
    let differing = a.iter().zip(&b).filter(|(p, q)| p != q).count();
    assert!(
        differing > 1000,
        "two frames look the same ({differing} bytes differ)"
    );
}

#[test]
#[ignore = "needs headless Chromium; ./scripts/test installs it"]
fn the_modes_page_draws_each_eigenvector_in_a_real_browser() {
    let dir = scratch("animate-modes-browser");
    let profile = dir.join("profile");
    let page = dir.join("modes.html");
    let out = succeeds(&[
        "modes",
        "scenes/three-section.toml",
        "--count",
        "5",
        "--shapes",
        "41",
        "--json",
        "--animate",
        page.to_str().unwrap(),
    ]);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let probe = probe(&page, &[1.0, 2.0, 3.0, 4.0, 5.0], &profile);
    let layout = &probe["layout"];
    let (cx, ground, ppm, scale) = stage(layout);
    // three sections of 1.35 m, a_2 = a_3 = 1.0 m: feet at 0, 1 and 2 m
    let feet = [0.0, 1.0, 2.0];
    for (m, result) in probe["results"].as_array().unwrap().iter().enumerate() {
        let shape = &report["mode_shapes"][m]["sections"];
        let drawn = &result["drawn"];
        assert_eq!(drawn["mode"].as_u64(), Some(m as u64 + 1));
        for (k, section) in drawn["sections"].as_array().unwrap().iter().enumerate() {
            for (p, point) in section.as_array().unwrap().iter().enumerate() {
                let w = f(&shape[k][p]);
                let x = 1.35 * p as f64 / 40.0;
                let (gx, gy) = (f(&point["x"]), f(&point["y"]));
                assert!(
                    (gx - (cx + ppm * scale * w)).abs() <= 0.5,
                    "mode {}, section {}, point {p}: x {gx} against the eigenvector's {}",
                    m + 1,
                    k + 1,
                    cx + ppm * scale * w
                );
                assert!(
                    (gy - (ground - ppm * (feet[k] + x))).abs() <= 0.5,
                    "mode {}, section {}, point {p}: y",
                    m + 1,
                    k + 1
                );
            }
        }
    }
}

/// case-study with its vehicle held 1e17 m out (a metre is below the position's resolution
/// there), for a second, written into `dir`.
fn far_out_scene(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string("scenes/case-study.toml").unwrap();
    let force = text
        .lines()
        .find(|l| l.starts_with("force = "))
        .expect("case-study is driven by a force");
    let path = dir.join("far-out.toml");
    std::fs::write(&path, text.replace(force, "motion = 1e17")).unwrap();
    path
}

#[test]
fn a_gif_of_a_vehicle_far_out_is_written() {
    let dir = scratch("animate-far-gif");
    let gif_path = dir.join("far.gif");
    let scene = far_out_scene(&dir);
    let out = succeeds(&[
        "animate",
        scene.to_str().unwrap(),
        "--set",
        "time.end=1",
        "--out",
        gif_path.to_str().unwrap(),
        "--fps",
        "5",
    ]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("6 frames at 5 per second"), "{said}");
    let decoder = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(&gif_path).unwrap())
        .unwrap();
    assert!(decoder.width() > 0);
}

#[test]
#[ignore = "needs headless Chromium; ./scripts/test installs it"]
fn the_page_of_a_vehicle_far_out_draws_in_a_real_browser() {
    let dir = scratch("animate-far-page");
    let page = dir.join("far.html");
    let scene = far_out_scene(&dir);
    succeeds(&[
        "animate",
        scene.to_str().unwrap(),
        "--set",
        "time.end=1",
        "--out",
        page.to_str().unwrap(),
    ]);
    let probe = probe(&page, &[0.0, 0.5], &dir.join("profile"));
    let results = probe["results"].as_array().unwrap();
    assert_eq!(results.len(), 2);
    assert!((f(&results[1]["drawn"][0]["time"]) - 0.5).abs() < 1e-9);
}

#[test]
fn a_page_or_gif_beyond_its_bounds_is_refused_before_the_run() {
    let dir = scratch("animate-bounds");
    let page = dir.join("long.html");
    // 400 s at 1000 frames a second: a page of about 90 MB, built at 5x that
    let out = Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args([
            "animate",
            "scenes/case-study.toml",
            "--set",
            "time.end=400",
            "--fps",
            "1000",
            "--out",
            page.to_str().unwrap(),
        ])
        .env("TELESCOPIC_MEMORY_BUDGET", "256M")
        .current_dir(common::ROOT)
        .output()
        .unwrap();
    let args = ["animate", "--fps"];
    common::failed_cleanly(
        &args,
        &out,
        &["--fps", "building a page", "more than the budget"],
    );
    assert!(!String::from_utf8_lossy(&out.stderr).contains("simulating"));
    assert!(!page.exists());
    let gif = dir.join("long.gif");
    fails_with(
        &[
            "animate",
            "scenes/case-study.toml",
            "--set",
            "time.end=10",
            "--fps",
            "1000",
            "--out",
            gif.to_str().unwrap(),
        ],
        &["--fps", "10001 frames", "at most 6000"],
    );
    assert!(!gif.exists());
}
