//! Two generator processes started at once must both succeed (the second waits for the
//! first's Symbolica lock instead of aborting) and agree byte for byte. This test binary
//! never touches Symbolica itself: a process holding the lock while waiting for its children
//! would deadlock them.

use std::process::Command;

#[test]
fn two_generator_processes_at_once() {
    let dir = std::env::temp_dir().join(format!("telescopic-codegen-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let models = dir.join("models.toml");
    std::fs::write(
        &models,
        "[[model]]\nmodes = [5, 5]\ncontacts = 3\nforce_flow = \"cable\"\nclearance = false\npositions = \"fixed\"\ndrive = \"force\"\n\n\
         [[model]]\nmodes = [4, 4]\ncontacts = 2\nforce_flow = \"none\"\nclearance = true\npositions = \"moving\"\ndrive = \"force\"\n",
    )
    .unwrap();
    let spawn = |out: &str| {
        Command::new(env!("CARGO_BIN_EXE_telescopic-codegen"))
            .arg("write")
            .arg(&models)
            .arg(dir.join(out))
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("the generator starts")
    };
    let (a, b) = (spawn("a"), spawn("b"));
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    for (name, out) in [("first", &a), ("second", &b)] {
        assert!(
            out.status.success(),
            "{name} process failed: {:?}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            out.stdout.is_empty(),
            "{name} process wrote to stdout: {}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
    for key in [
        "s2_m5x5_c3_cable_linear_fixed_force",
        "s2_m4x4_c2_noflow_clearance_moving_force",
    ] {
        let fa = std::fs::read_to_string(dir.join("a").join(format!("{key}.rs"))).unwrap();
        let fb = std::fs::read_to_string(dir.join("b").join(format!("{key}.rs"))).unwrap();
        assert_eq!(fa, fb, "{key}: the two processes disagree");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn without_a_shared_lock_one_of_two_processes_aborts() {
    // the negative control: separate lock files remove the mutual exclusion, and Symbolica's
    // restricted mode then kills the second process to touch it (this is why the lock exists)
    let dir =
        std::env::temp_dir().join(format!("telescopic-codegen-nolock-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let models = dir.join("models.toml");
    std::fs::write(
        &models,
        "[[model]]\nmodes = [6, 6, 6]\ncontacts = 2\nforce_flow = \"cable\"\nclearance = true\npositions = \"moving\"\ndrive = \"force\"\n",
    )
    .unwrap();
    let spawn = |name: &str| {
        Command::new(env!("CARGO_BIN_EXE_telescopic-codegen"))
            .env(
                "TELESCOPIC_SYMBOLICA_LOCK",
                dir.join(format!("{name}.lock")),
            )
            .arg("write")
            .arg(&models)
            .arg(dir.join(name))
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("the generator starts")
    };
    // hold the default lock meanwhile, so that every cooperating Symbolica process (other
    // tests under nextest, build scripts) waits instead of meeting the unlocked pair
    let guard = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(telescopic_codegen::lock_path())
        .unwrap();
    guard.lock().unwrap();
    let (mut a, mut b) = (spawn("a"), spawn("b"));
    let (sa, sb) = (a.wait().unwrap(), b.wait().unwrap());
    drop(guard);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        sa.success() != sb.success(),
        "expected exactly one of two unlocked processes to abort, got {sa:?} and {sb:?}"
    );
}

#[test]
fn a_configuration_comes_out_the_same_whatever_was_generated_before_it() {
    // Symbolica orders terms by the creation order of its symbols in the process: without
    // the canonical ordering of the generator, a configuration generated after others (the
    // generated crate's list) differed in term order from the same configuration generated
    // alone (a downstream build script), and with it the rounding of every run
    let dir =
        std::env::temp_dir().join(format!("telescopic-codegen-history-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let alone = dir.join("alone.toml");
    std::fs::write(
        &alone,
        "[[model]]\nmodes = [5, 5]\ncontacts = 3\nforce_flow = \"none\"\nclearance = true\npositions = \"fixed\"\ndrive = \"force\"\n",
    )
    .unwrap();
    let all = concat!(env!("CARGO_MANIFEST_DIR"), "/../generated/models.toml");
    let run = |models: &std::path::Path, out: &str| {
        let status = Command::new(env!("CARGO_BIN_EXE_telescopic-codegen"))
            .arg("write")
            .arg(models)
            .arg(dir.join(out))
            .arg("--no-renderings")
            .stderr(std::process::Stdio::null())
            .status()
            .unwrap();
        assert!(status.success());
    };
    run(&alone, "alone");
    run(std::path::Path::new(all), "all");
    let key = "s2_m5x5_c3_noflow_clearance_fixed_force.rs";
    let a = std::fs::read_to_string(dir.join("alone").join(key)).unwrap();
    let b = std::fs::read_to_string(dir.join("all").join(key)).unwrap();
    assert!(a == b, "{key} depends on what was generated before it");
    let _ = std::fs::remove_dir_all(&dir);
}
